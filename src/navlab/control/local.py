"""What the costmap-reading local planners (DWA, MPPI, RPP) share.

They follow a global path, read a Nav2-style costmap (given by the
simulator before every cycle with :meth:`CostmapController.set_costmap`,
together with the robot's footprint) and remember the last twist they
commanded as the robot's current velocity (the simulator is kinematic: the
plant reaches a command within the acceleration limits these planners
respect). A new global path may arrive between cycles (:meth:`set_path`).
"""

from __future__ import annotations

import math
from typing import Dict

import numpy as np

from ..errors import ParameterError
from ..registry import suggest
from .base import REACHED, RUNNING, STALLED, Command, Controller, StallDetector, check_number  # noqa: F401


class CostmapController(Controller):
    """A path-following local planner on a costmap.

    Parameters (shared)
    -------------------
    xy_goal_tolerance : float
        [m] the run ends REACHED within this distance of the goal.
    stall_window, stall_progress : float
        [s], [m] STALLED when the distance left along the path has not
        dropped by ``stall_progress`` over ``stall_window``.
    inflation_radius, cost_scaling_factor : float
        The costmap's inflation (read by the simulator when it builds it).
    layers : str
        What the costmap holds: ``static`` (the world or map, known in
        advance), ``sensor`` (only what the LiDAR has seen, Nav2's obstacle
        layer; the global path is planned again on it every
        ``replan_interval`` s) or ``static+sensor``.
    replan_interval : float
        [s] how often the global path is planned again on a costmap with a
        sensor layer.
    costmap_resolution : float
        [m] the costmap's cell size for worlds (maps keep their own; 0.05 m,
        the challenge's).
    footprint_padding : float
        [m] the footprint the costmap and the planner's collision checks use
        is the robot's grown by this (costmap_2d's ``footprint_padding``); the
        simulator still tests the true footprint.
    """

    needs_path = True
    needs_costmap = True
    LAYERS = ("static", "sensor", "static+sensor")

    def __init__(self, xy_goal_tolerance: float = 0.25, stall_window: float = 20.0, stall_progress: float = 0.05,
                 inflation_radius: float = 0.55, cost_scaling_factor: float = 3.0, layers: str = "static",
                 replan_interval: float = 1.0, footprint_padding: float = 0.0,
                 costmap_resolution: float = 0.05) -> None:
        self.costmap_resolution = check_number("costmap_resolution", costmap_resolution, high=100.0)
        self.footprint_padding = check_number("footprint_padding", footprint_padding, allow_low=True, high=10.0)
        if layers not in self.LAYERS:
            raise ParameterError(f"layers must be one of {', '.join(self.LAYERS)}, got {layers!r}."
                                 f"{suggest(layers, list(self.LAYERS))}".rstrip("."))
        self.layers = layers
        self.needs_scan = "sensor" in layers
        self.replan_interval = check_number("replan_interval", replan_interval)
        self.xy_goal_tolerance = check_number("xy_goal_tolerance", xy_goal_tolerance)
        self.stall = StallDetector(check_number("stall_window", stall_window),
                                   check_number("stall_progress", stall_progress))
        self.costmap_settings: Dict[str, float] = {
            "inflation_radius": check_number("inflation_radius", inflation_radius, allow_low=True),
            "cost_scaling_factor": check_number("cost_scaling_factor", cost_scaling_factor, allow_low=True)}
        self.costmap = None
        self.footprint = None
        self.body = np.zeros((0, 2))
        self.goal = np.zeros(2)
        self.path = np.zeros((1, 2))
        self.velocity = np.zeros(3)  #: the last commanded twist (vx, vy, ω)

    def reset(self, goal, path=None) -> None:
        self.goal = np.asarray(goal, float)[:2]
        self.set_path(path if path is not None else np.array([self.goal]))
        self.velocity = np.zeros(3)
        self.stall.reset()

    def set_path(self, path) -> None:
        """A new global path (N, 2) to follow from now on."""
        self.path = np.ascontiguousarray(np.asarray(path, float)[:, :2])
        seg = np.hypot(*np.diff(self.path, axis=0).T) if len(self.path) > 1 else np.zeros(0)
        self._to_end = np.concatenate((np.cumsum(seg[::-1])[::-1], [0.0]))  #: path length left from each point

    def remaining(self, pose) -> float:
        """How far the robot still has to go: to the nearest path point, then along the path
        (progress is judged on this, so a path that first leads away from the goal is not a stall)."""
        d = np.hypot(*(self.path - np.asarray(pose[:2], float)).T)
        i = int(np.argmin(d))
        return float(d[i] + self._to_end[i])

    def set_costmap(self, costmap, footprint) -> None:
        """The costmap and footprint the next :meth:`command` plans on."""
        self.costmap, self.footprint = costmap, footprint
        self.body = np.zeros((0, 2)) if footprint.is_disc else np.ascontiguousarray(footprint.vertices)

    def command(self, t: float, pose, points=None) -> Command:
        pose = np.asarray(pose, float)
        distance = float(np.hypot(*(self.goal - pose[:2])))
        if distance <= self.xy_goal_tolerance:
            self.velocity = np.zeros(3)
            return Command(0.0, 0.0, 0.0, REACHED)
        if self.stall.stalled(t, self.remaining(pose)):
            return Command(0.0, 0.0, 0.0, STALLED)
        if self.costmap is None:
            raise RuntimeError(f"{type(self).__name__} needs a costmap: call set_costmap before command")
        vx, vy, w = self.plan(t, pose)
        self.velocity = np.array((vx, vy, w), float)
        return Command(vx, vy, w, RUNNING)

    def plan(self, t: float, pose: np.ndarray):
        """The twist (vx, vy, ω) for this cycle."""
        raise NotImplementedError

    # -- path helpers ---------------------------------------------------------
    def local_path(self, pose, horizon: float) -> np.ndarray:
        """The global path from its point nearest the robot onward, cut at ``horizon`` metres."""
        path = self.path
        if len(path) == 1:
            return path.copy()
        d = np.hypot(*(path - pose[:2]).T)
        start = int(np.argmin(d))
        seg = np.hypot(*np.diff(path[start:], axis=0).T)
        along = np.concatenate(([0.0], np.cumsum(seg)))
        stop = int(np.searchsorted(along, horizon, side="right"))
        return path[start:start + max(stop, 1) + 1]


def arc_rollouts(x: float, y: float, th: float, vx: np.ndarray, vy: np.ndarray, w: np.ndarray, dt: float,
                 steps: int) -> np.ndarray:
    """(N, steps, 3) poses along constant-twist arcs, one per sample, at ``dt`` intervals
    (the first after one step)."""
    t = dt * np.arange(1, steps + 1)[None, :]
    vx, vy, w = (np.asarray(a, float)[:, None] for a in (vx, vy, w))
    dth = w * t
    small = np.abs(w) < 1e-9
    safe_w = np.where(small, 1.0, w)
    s0, c0 = math.sin(th), math.cos(th)
    s1, c1 = np.sin(th + dth), np.cos(th + dth)
    mid = th + 0.5 * dth
    dx = np.where(small, (np.cos(mid) * vx - np.sin(mid) * vy) * t, (vx * (s1 - s0) + vy * (c1 - c0)) / safe_w)
    dy = np.where(small, (np.sin(mid) * vx + np.cos(mid) * vy) * t, (vx * (c0 - c1) + vy * (s1 - s0)) / safe_w)
    return np.stack((x + dx, y + dy, th + dth), axis=-1)
