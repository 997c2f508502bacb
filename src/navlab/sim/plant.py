"""The robot's physical side, one step at a time: a commanded twist moves
the true pose (through the wheel model) and the odometry (through the
encoders and compass). The closed-loop :class:`~navlab.sim.Simulation` and
the ROS 2 sim node both drive it."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..robots.kinematics import accelerate, integrate_pose
from ..robots.odometry import Odometry
from ..robots.proprioception import Compass, WheelEncoders
from .scene import Scene


class Plant:
    """A robot in a scene, moved by body twists.

    Parameters
    ----------
    scene : Scene
    robot : DiffDrive, Omni3 or Car
    start : (x, y, θ)
    encoders : WheelEncoders
    compass : Compass, optional
    """

    def __init__(self, scene: Scene, robot, start, encoders: WheelEncoders, compass: Optional[Compass] = None):
        self.scene, self.robot, self.encoders, self.compass = scene, robot, encoders, compass
        self.pose = np.array(start, float)
        self.odometry = Odometry(robot, self.pose)
        self._wheel_angles = np.zeros(robot.n_wheels)
        self._ticks = encoders.counts(self._wheel_angles)
        self.last_twist = (0.0, 0.0, 0.0)  #: the limited command of the last step
        self.hit: Optional[str] = None  #: who hit whom in the last step, if anything

    def step(self, vx: float, vy: float, omega: float, dt: float, rng: Optional[np.random.Generator],
             t: float = 0.0) -> bool:
        """Move for ``dt`` from time ``t`` under a commanded twist (limited to
        the robot's capabilities); True when the motion hit something or
        something hit the robot (moving obstacles move over the same step;
        the pose is then the colliding one and :attr:`hit` says who hit whom)."""
        robot, enc = self.robot, self.encoders
        twist = accelerate(self.last_twist, robot.limit(vx, vy, omega), dt,
                           getattr(robot, "max_accel", None), getattr(robot, "max_angular_accel", None))
        if getattr(robot, "steers", False):
            # a car's turn rate follows its speed: the speed reached under the acceleration limit bounds it
            twist = (twist[0], 0.0, robot.steer(twist[0], twist[2]))
        self.last_twist = twist
        rotation = enc.actual_speeds(robot.inverse(*self.last_twist), rng) * dt
        bx, by, bw = robot.forward(enc.ground_rotation(rotation, rng) / dt)
        new_pose = integrate_pose(self.pose, bx, by, bw, dt)
        self.hit = self.scene.hit(self.pose, new_pose, t, t + dt, twist=(bx, by, bw))
        collided = self.hit is not None
        self.pose = new_pose
        self._wheel_angles += rotation
        ticks = enc.counts(self._wheel_angles)
        heading = self.compass.heading(self.compass.read(new_pose[2], rng)) if self.compass else None
        self.odometry.update(enc.angles(ticks - self._ticks), heading)
        self._ticks = ticks
        return collided
