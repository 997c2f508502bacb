"""``potential_field_navigator`` (seed 004): drives an omnidirectional robot
to each ``/goal_pose`` through the potential field of the goal and the
``/scan`` points, commanding ``/cmd_vel`` (linear.x, linear.y, and
angular.z holding the heading)."""

from __future__ import annotations

import math

from geometry_msgs.msg import PoseStamped
from sensor_msgs.msg import LaserScan

from .base import DEFAULT_QOS, SCAN_QOS, Param, node_main
from .convert import pose_from_msg, scan_points_from_msg
from .drive_node import ODOM_TIMEOUT, DriveNode


class PotentialFieldNavigator(DriveNode):
    CONTROLLER = "potential_field"
    CONTROLLER_PARAMS = ("alpha", "beta", "delta", "obstacle_r", "obstacle_s", "max_speed")
    PARAMETERS = (
        Param("alpha", 1.0, "attractive gain (1/s), seed 004 eq. 9"),
        Param("beta", 0.02, "repulsive gain per scan point (1/s), eq. 12"),
        Param("delta", 0.3, "repulsion inside obstacle_r (m/s per point)"),
        Param("obstacle_r", 0.2, "radius of the repulsive field around each point (m)"),
        Param("obstacle_s", 0.35, "spread of the repulsive field (m)"),
        Param("max_speed", 0.3, "speed limit of the command (m/s)"),
        # (a timeout below 0 took every scan as stale: the robot never moved; attack run, session 18)
        Param("scan_timeout", 0.5, "ignore scans older than this (wall-clock s)", low=0.0),
        ODOM_TIMEOUT,
    )

    def __init__(self, **kwargs) -> None:
        super().__init__("potential_field_navigator", **kwargs)
        self.scan = None
        self.scan_time = -math.inf
        self.waiting_logged = False
        self.create_subscription(PoseStamped, "goal_pose", self.on_goal, DEFAULT_QOS)
        self.create_subscription(LaserScan, "scan", self.on_scan, SCAN_QOS)
        # load the compiled scan-to-points kernel now (0.3 s), not in the first
        # control step, where the delay would look like a stall to the field
        scan_points_from_msg(LaserScan(angle_increment=0.1, range_max=1.0, ranges=[0.5, 0.5]), (0.0, 0.0, 0.0))

    def on_goal(self, msg) -> None:
        self.send(self.drive.set_target(pose_from_msg(msg.pose)[:2]))

    def on_scan(self, msg) -> None:
        if len(msg.ranges) == 0:
            self.log("warn", "ignoring an empty /scan")
            return
        self.scan, self.scan_time = msg, self.monotonic()

    def points(self, pose):
        if self.scan is None or self.monotonic() - self.scan_time > self.params["scan_timeout"]:
            if not self.waiting_logged:
                # before the first scan this is start-up, not a fault: a successful demo's summary listed the
                # warning under REACHED (newcomer, session 25); a scan that stops coming is one
                if self.scan is None:
                    self.log("info", "waiting for the first /scan before moving (the field needs the obstacles)")
                else:
                    self.log("warn", "no recent /scan: not moving (the field needs the obstacles)")
                self.waiting_logged = True
            return False
        self.waiting_logged = False
        return scan_points_from_msg(self.scan, pose)


main = node_main(PotentialFieldNavigator)

if __name__ == "__main__":
    main()
