"""Robots: kinematics (differential drive, three-wheel omni, car), wheel encoders,
compass and odometry."""

from .kinematics import ROBOTS, Car, DiffDrive, Omni3, body_to_world, integrate_pose, make_robot, world_to_body
from .odometry import Odometry
from .proprioception import Compass, WheelEncoders, calibrate_heading

__all__ = ["ROBOTS", "Car", "Compass", "DiffDrive", "Odometry", "Omni3", "WheelEncoders", "body_to_world",
           "calibrate_heading", "integrate_pose", "make_robot", "world_to_body"]
