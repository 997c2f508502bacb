"""The costmap a costmap-reading controller (DWA, MPPI, RPP) sees each cycle,
and its global path, planned on that costmap (Nav2's planner server over the
global costmap, at a rate)."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..grid.cost_search import plan_on_costmap
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
        """The global path from ``start`` on the costmap known before the run (None: none found)."""
        path, _, _ = plan_on_costmap(self.layers.static_costmap(), start, self.goal, allow_unknown=self.sensing)
        return path

    def update(self, t: float, pose, points=None) -> None:
        """Give the controller this cycle's costmap (and a new global path when one is due)."""
        pose = np.asarray(pose, float)
        costmap = self.layers.update(pose[:2], points) if self.sensing else self.layers.static_costmap()
        self.controller.set_costmap(costmap, self.footprint)
        if self.sensing and t - self._last_plan >= self.controller.replan_interval:
            self._last_plan = t
            path, _, _ = plan_on_costmap(costmap, pose, self.goal, allow_unknown=True)
            if path is not None:
                self.controller.set_path(path)
                self.paths.append(path)
                self.replans += 1
