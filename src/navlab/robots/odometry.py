"""Dead reckoning from wheel encoders (and a compass for the heading)."""

from __future__ import annotations

from typing import Optional

import numpy as np

from .kinematics import _wrap, body_to_world


class Odometry:
    """Pose estimate from encoder increments.

    For the omni robot (seed 004, eq. 5–8) the wheel displacements give the
    body displacement through the forward kinematics, which the compass
    heading rotates into the world. For the differential drive it is the
    standard midpoint model: distance (dl + dr)/2 along the mean heading,
    turn (dr − dl)/track; a compass heading replaces the integrated one when
    given.

    Parameters
    ----------
    robot : DiffDrive or Omni3
    pose : array-like
        Initial pose (x, y, θ).
    """

    def __init__(self, robot, pose) -> None:
        self.robot = robot
        self.pose = np.array(pose, dtype=float)

    def update(self, wheel_rotation: np.ndarray, heading: Optional[float] = None) -> np.ndarray:
        """Advance by wheel rotations (rad) since the last update; ``heading``
        is the compass's calibrated heading (rad) after the motion."""
        # Rotations are speeds × dt, so the forward kinematics gives the body
        # displacement: (dx, dy, dθ) for the omni, ((dl + dr)/2, 0, (dr − dl)/track)
        # for the differential drive.
        dx_b, dy_b, dth = self.robot.forward(wheel_rotation)
        x, y, th = self.pose
        th_new = heading if heading is not None else _wrap(th + dth)
        wx, wy = body_to_world(th + 0.5 * _wrap(th_new - th), dx_b, dy_b)
        self.pose = np.array((x + wx, y + wy, th_new))
        return self.pose
