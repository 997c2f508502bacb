"""Artificial potential field navigation for a holonomic robot (seed 004)."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..robots.kinematics import _wrap, world_to_body
from .base import CONTROLLERS, REACHED, RUNNING, STALLED, Command, Controller, StallDetector, check_number


def attractive(dx: float, dy: float, alpha: float, r: float, s: float) -> np.ndarray:
    """Seed 004, eq. 9, towards a goal at (dx, dy) from the robot: 0 inside
    r, α(d − r) for r ≤ d ≤ s + r, and α·s beyond. (The seed writes α there,
    which would jump at d = s + r unless s = 1; navlab keeps it continuous.)"""
    d = math.hypot(dx, dy)
    if d < r:
        return np.zeros(2)
    magnitude = alpha * (min(d, s + r) - r)
    return magnitude * np.array((dx, dy)) / d


def repulsive(offsets: np.ndarray, beta: float, delta: float, r: float, s: float) -> np.ndarray:
    """Seed 004, eq. 12, summed over obstacle points at ``offsets`` (N, 2)
    from the robot: −δ·u inside r, −β(s + r − d)·u for r ≤ d ≤ s + r, 0 beyond
    (u the unit vector towards the point)."""
    if len(offsets) == 0:
        return np.zeros(2)
    d = np.hypot(offsets[:, 0], offsets[:, 1])
    mag = np.where(d < r, delta, np.where(d <= s + r, beta * (s + r - d), 0.0))
    used = mag > 0
    if not used.any():
        return np.zeros(2)
    u = offsets[used] / d[used, None]
    return -(mag[used, None] * u).sum(axis=0)


@CONTROLLERS.register("potential_field")
class PotentialField(Controller):
    """Attractive goal plus repulsive LiDAR points; the total force is the
    commanded world velocity (eq. 15–16), turned into the body frame, with
    the heading held at 0 by a proportional turn-rate term.

    Parameters
    ----------
    alpha : float
        Attractive gain (1/s).
    beta : float
        Repulsive gain per obstacle point (1/s).
    delta : float
        Repulsion inside ``obstacle_r`` (m/s per point; "large").
    r, s : float
        Goal radius and spread of the attractive field (m); inside ``r`` the
        goal counts as reached.
    obstacle_r, obstacle_s : float
        Radius and spread of the repulsive field around each point (m);
        ``obstacle_r`` should cover the robot's own radius.
    max_speed : float
        Clip of the commanded speed (m/s).
    heading_gain : float
        Turn rate per radian of heading error (1/s); the heading is held at 0.
    min_speed : float
        The attraction α(d − r) fades to nothing at the goal radius, so the
        robot would only creep towards it; once the attraction alone is below
        ``min_speed`` (d < r + min_speed/α) the goal counts as reached.
    stall_window, stall_progress :
        A run that does not get ``stall_progress`` m closer to the goal in
        ``stall_window`` s is reported ``STALLED`` (a local minimum).

    References
    ----------
    O. Khatib, "Real-time obstacle avoidance for manipulators and mobile
    robots", IJRR 5(1), 1986; seed 004 for the piecewise-linear form.
    """

    needs_scan = True
    speed_setting = "max_speed"
    holonomic = True

    def __init__(self, alpha: float = 1.0, beta: float = 0.02, delta: float = 0.3, r: float = 0.01,
                 s: float = 0.3, obstacle_r: float = 0.2, obstacle_s: float = 0.35, max_speed: float = 0.3,
                 heading_gain: float = 2.0, min_speed: float = 0.01, stall_window: float = 4.0,
                 stall_progress: float = 0.03) -> None:
        # (a number's checks: 'abc' or a list was an internal TypeError, an attack on the command, session 17)
        for name, value in (("alpha", alpha), ("s", s), ("obstacle_s", obstacle_s), ("max_speed", max_speed)):
            check_number(f"potential field {name}", value)
        for name, value in (("beta", beta), ("delta", delta), ("r", r), ("obstacle_r", obstacle_r),
                            ("heading_gain", heading_gain)):
            check_number(f"potential field {name}", value, allow_low=True)
        self.alpha, self.beta, self.delta, self.r, self.s = alpha, beta, delta, r, s
        self.obstacle_r, self.obstacle_s = obstacle_r, obstacle_s
        self.max_speed, self.heading_gain = max_speed, heading_gain
        self.min_speed = check_number("potential field min_speed", min_speed, allow_low=True)
        self.stall = StallDetector(stall_window, stall_progress)
        self.goal = np.zeros(2)

    def reset(self, goal, path=None) -> None:
        self.goal = np.asarray(goal, float)[:2]
        self.stall.reset()

    def force(self, pose, points: Optional[np.ndarray]) -> np.ndarray:
        """Total force (world frame) at ``pose`` with obstacle points (world)."""
        f = attractive(self.goal[0] - pose[0], self.goal[1] - pose[1], self.alpha, self.r, self.s)
        if points is not None and len(points):
            f = f + repulsive(points - np.asarray(pose[:2]), self.beta, self.delta, self.obstacle_r,
                              self.obstacle_s)
        return f

    def command(self, t: float, pose, points=None) -> Command:
        distance = math.hypot(self.goal[0] - pose[0], self.goal[1] - pose[1])
        if distance < self.r + self.min_speed / self.alpha:
            return Command(status=REACHED)
        fx, fy = self.force(pose, points)
        speed = math.hypot(fx, fy)
        if speed > self.max_speed:
            fx, fy = fx * self.max_speed / speed, fy * self.max_speed / speed
        if self.stall.stalled(t, distance):
            return Command(status=STALLED)
        vx, vy = world_to_body(pose[2], fx, fy)
        return Command(vx, vy, -self.heading_gain * _wrap(pose[2]), RUNNING)
