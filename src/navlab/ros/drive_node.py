"""The shell shared by the nodes that drive the robot from odometry: a
:class:`~navlab.ros.core.Drive` fed by ``/odom``, commands on ``/cmd_vel``
and a watchdog that stops the robot when odometry goes quiet."""

from __future__ import annotations

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from ..control import make_controller
from .base import DEFAULT_QOS, NavlabNode, Param
from .convert import pose_from_msg, twist_msg
from .core import Drive, finite

ODOM_TIMEOUT = Param("odom_timeout", 0.5, "stop the robot when /odom is silent this long (wall-clock s)")


class DriveNode(NavlabNode):
    """Subclasses name their controller and which parameters go to it."""

    CONTROLLER = ""
    CONTROLLER_PARAMS: tuple = ()

    def __init__(self, name: str, **kwargs) -> None:
        super().__init__(name, **kwargs)
        settings = {k: self.params[k] for k in self.CONTROLLER_PARAMS}
        self.drive = Drive(make_controller(self.CONTROLLER, **settings), self.log, self.params["odom_timeout"])
        self.cmd_pub = self.create_publisher(Twist, "cmd_vel", DEFAULT_QOS)
        self.create_subscription(Odometry, "odom", self.on_odom, DEFAULT_QOS)
        self.steady_timer(self.params["odom_timeout"] / 4, lambda: self.send(self.drive.watchdog(self.monotonic())))

    def points(self, pose):
        """Obstacle points for the controller (None: no scan needed)."""
        return None

    def on_odom(self, msg) -> None:
        pose = pose_from_msg(msg.pose.pose)
        if not finite(pose, "an /odom pose", self.log):
            return
        t = self.stamp_seconds(msg.header.stamp)
        points = self.points(pose) if self.drive.active else None
        if points is False:  # a sensor the controller needs is silent
            self.send(self.drive.hold(self.monotonic()))
            return
        self.send(self.drive.on_odom(t, pose, self.monotonic(), points))

    def send(self, twist) -> None:
        if twist is not None:
            self.cmd_pub.publish(twist_msg(*twist))
