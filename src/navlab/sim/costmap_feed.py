"""The costmap a costmap-reading controller (DWA, MPPI, RPP) sees each cycle,
and its global path, planned on that costmap (Nav2's planner server over the
global costmap, at a rate)."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..grid.cost_search import plan_on_costmap, plan_poses_on_costmap
from ..world.costmap import LayeredCostmap


class CostmapFeed:
    """Builds the controller's costmap from the world and the LiDAR and keeps its path current.

    Parameters
    ----------
    scene_world : World or OccupancyGrid
    footprint : Footprint
    controller : CostmapController
        Its ``layers``, ``replan_interval`` and ``costmap_settings`` are read.
    goal : (x, y)
    """

    def __init__(self, scene_world, footprint, controller, goal) -> None:
        # the planner's own idea of the robot: its footprint grown by the padding (costmap_2d's footprint_padding)
        self.footprint = footprint.padded(controller.footprint_padding) if controller.footprint_padding else footprint
        self.controller = controller
        self.goal = np.asarray(goal, float)[:2]
        resolution = None if hasattr(scene_world, "blocked") else controller.costmap_resolution
        self.layers = LayeredCostmap(scene_world, self.footprint, static="static" in controller.layers,
                                     resolution=resolution, **controller.costmap_settings)
        self.sensing = "sensor" in controller.layers
        self.reset()

    def reset(self) -> None:
        """Forget what the LiDAR marked and the paths planned (a new run)."""
        self.layers.marked[:] = False
        self._last_plan = -math.inf
        self.replans = 0
        self.paths = []  #: the global paths planned during the run

    def initial_path(self, start) -> Optional[np.ndarray]:
        """The global path from ``start`` on the costmap known before the run (None: none found).

        A controller that tracks paths of poses (RPP's ``plan_poses``) gets (N, 3) poses planned for
        its footprint instead when the costmap path is tight for it (:func:`tight_for`) and such a
        path exists from the start pose."""
        costmap = self.layers.static_costmap()
        path, _, _ = plan_on_costmap(costmap, start, self.goal, allow_unknown=self.sensing)
        if path is None or not getattr(self.controller, "plan_poses", False) or len(start) < 3:
            return path
        if tight_for(costmap, self.footprint.padded(self.controller.pose_plan_clearance), path):
            poses = self._poses(np.asarray(start, float), costmap, path)
            if poses is not None:
                return poses
        return path

    def update(self, t: float, pose, points=None) -> None:
        """Give the controller this cycle's costmap (and a new global path when one is due)."""
        pose = np.asarray(pose, float)
        costmap = self.layers.update(pose[:2], points) if self.sensing else self.layers.static_costmap()
        self.controller.set_costmap(costmap, self.footprint)
        if getattr(self.controller, "wants_pose_plan", False):
            self._plan_poses(t, pose, costmap)
        # (an infinite interval plans never: 0 - (-inf) >= inf planned at t = 0, a path DWA's own planner
        # replaced in the same cycle, counted as a replan: review, session 29)
        interval = self.controller.replan_interval
        if self.sensing and math.isfinite(interval) and t - self._last_plan >= interval:
            self._last_plan = t
            path, _, _ = plan_on_costmap(costmap, pose, self.goal, allow_unknown=True)
            if path is not None:
                self.controller.set_path(path)
                self.paths.append(path)
                self.replans += 1

    def _poses(self, pose: np.ndarray, costmap, path: np.ndarray) -> Optional[np.ndarray]:
        """A forward path of poses for the footprint from ``pose`` to the goal, arriving along the
        last leg of ``path`` (None: none)."""
        tail = path[-1, :2] - path[-2, :2] if len(path) > 1 else self.goal - pose[:2]
        goal = (*self.goal, math.atan2(tail[1], tail[0]))
        result = plan_poses_on_costmap(costmap, self.footprint, pose, goal,
                                       self.controller.pose_plan_turning_radius, allow_unknown=self.sensing)
        return result.path if result.status.success and len(result.path) > 1 else None

    def _plan_poses(self, t: float, pose: np.ndarray, costmap) -> None:
        """Answer a controller stuck on its path (RPP's ``plan_poses``)."""
        poses = self._poses(pose, costmap, self.controller.path)
        if poses is None:
            self.controller.pose_plan_failed(t)
            return
        self.controller.set_pose_path(poses)
        self.paths.append(poses[:, :2])
        self.replans += 1


#: [m] the costmap path's heading at a point is that of the chord between the points this far before and after
HEADING_SPAN = 0.25


def tight_for(costmap, footprint, path: np.ndarray) -> bool:
    """Whether ``footprint`` meets a LETHAL (or unknown) cell somewhere along ``path`` (N, 2), facing
    along it (its heading smoothed over ±``HEADING_SPAN``: the grid path's own steps zigzag by 45°)."""
    from ..world.costmap import LETHAL_OBSTACLE

    path = np.asarray(path, float)[:, :2]
    if len(path) < 2:
        return False
    along = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))))
    before = np.searchsorted(along, along - HEADING_SPAN, side="left")
    after = np.minimum(np.searchsorted(along, along + HEADING_SPAN, side="right"), len(path)) - 1
    chord = path[after] - path[before]
    heading = np.arctan2(chord[:, 1], chord[:, 0])
    return bool((costmap.footprint_cost(np.column_stack((path, heading)), footprint) >= LETHAL_OBSTACLE).any())
