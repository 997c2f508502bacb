"""The hybrid navigator: a global plan followed with the potential field as
the local avoider, replanning when the field stalls."""

from __future__ import annotations

import math
import numpy as np

from ..limits import check_count
from .base import CONTROLLERS, REACHED, STALLED, Command, Controller, StallDetector, check_number
from .potential_field import PotentialField


@CONTROLLERS.register("hybrid")
class Hybrid(Controller):
    """Follow a global path (A* on a map, RRT* in a world) by pulling the
    seed 004 potential field towards a *carrot* ``carrot`` metres ahead on
    the path, so the field only has to avoid what the plan did not know;
    when progress along the path stalls (a local minimum the plan led into,
    or an obstacle parked on it) plan again from where the robot is, around
    what the LiDAR sees, at most every ``replan_interval`` seconds and
    ``max_replans`` times per run; a stall after that is ``STALLED``.

    Parameters
    ----------
    carrot : float
        Look-ahead along the path (m).
    replan_interval : float
        Least simulated time between two replans (s).
    max_replans : int
        Replans per run before a stall is reported ``STALLED``.
    stall_window, stall_progress :
        No ``stall_progress`` m of progress along the path in ``stall_window``
        s is a stall.
    **field :
        Potential field settings (``alpha``, ``beta``, ``obstacle_s``, ...;
        see :class:`PotentialField`).

    References
    ----------
    O. Brock, O. Khatib, "High-speed navigation using the global dynamic
    window approach", ICRA 1999 (global plan plus local reactive control);
    seed 004 for the field.
    """

    needs_path = True
    needs_scan = True
    speed_setting = "max_speed"  # its potential field's
    holonomic = True

    def __init__(self, carrot: float = 0.5, replan_interval: float = 2.0, max_replans: int = 5,
                 stall_window: float = 4.0, stall_progress: float = 0.03, **field) -> None:
        # (a string was a TypeError, an internal error, and true was taken as 1: attack run, session 18)
        carrot = check_number("hybrid carrot", carrot)
        # as the followers': 0 would replan on every step of a stall
        replan_interval = check_number("hybrid replan_interval", replan_interval)
        max_replans = check_count("hybrid max_replans", max_replans, low=0)
        field.setdefault("stall_window", 1e9)  # the hybrid judges progress along the path itself
        self.field = PotentialField(**field)
        self.carrot, self.replan_interval, self.max_replans = carrot, replan_interval, max_replans
        self.stall = StallDetector(stall_window, stall_progress)
        self.replanner = None  #: set by the simulator: plans from a pose around sensed points
        self.path = np.zeros((1, 2))
        self.goal = np.zeros(2)

    def reset(self, goal, path=None) -> None:
        self.goal = np.asarray(goal, float)[:2]
        self._set_path(np.asarray(path if path is not None else [goal], float)[:, :2])
        self.stall.reset()
        self.replans, self._last_replan = 0, -math.inf

    def _set_path(self, path: np.ndarray) -> None:
        if len(path) == 1:
            path = np.vstack((path, path))
        self.path = path
        self.segment = 0
        seg = np.diff(path, axis=0)
        self._lengths = np.hypot(seg[:, 0], seg[:, 1])
        self._after = np.concatenate((np.cumsum(self._lengths[::-1])[::-1][1:], [0.0]))  # length after each segment

    def _progress(self, pose) -> tuple:
        """(remaining path length from the robot's projection, carrot point)."""
        p = np.asarray(pose[:2], float)
        best, best_d, best_u = self.segment, math.inf, 0.0
        # look a few segments ahead only: the projection never jumps back along the path
        for k in range(self.segment, min(self.segment + 4, len(self._lengths))):
            a, d = self.path[k], self.path[k + 1] - self.path[k]
            L2 = float(d @ d)
            u = 0.0 if L2 == 0 else min(max(float((p - a) @ d) / L2, 0.0), 1.0)
            dist = float(np.hypot(*(a + u * d - p)))
            if dist < best_d - 1e-12:
                best, best_d, best_u = k, dist, u
        self.segment = best
        remaining = (1.0 - best_u) * self._lengths[best] + self._after[best]
        # the carrot: ``carrot`` metres further along the path
        k, u, left = best, best_u, self.carrot
        while True:
            room = (1.0 - u) * self._lengths[k]
            if left <= room or k == len(self._lengths) - 1:
                f = 1.0 if self._lengths[k] == 0 else min(1.0, u + left / self._lengths[k])
                return remaining, self.path[k] + f * (self.path[k + 1] - self.path[k])
            left -= room
            k, u = k + 1, 0.0

    def command(self, t: float, pose, points=None) -> Command:
        if math.hypot(*(self.goal - pose[:2])) < self.field.r + self.field.min_speed / self.field.alpha:
            return Command(status=REACHED)
        remaining, carrot = self._progress(pose)
        if self.stall.stalled(t, remaining):
            if self.replanner is None or self.replans >= self.max_replans:
                return Command(status=STALLED)
            if t - self._last_replan >= self.replan_interval:
                self._replan(t, pose, points)
                remaining, carrot = self._progress(pose)
        self.field.goal = carrot
        return self.field.command(t, pose, points)

    def _replan(self, t: float, pose, points) -> None:
        self.replans += 1
        self._last_replan = t
        new = self.replanner.plan(pose, points)
        if new is not None:
            self._set_path(new)
        self.stall.reset()
