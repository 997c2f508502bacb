"""``goto_waypoint`` (seed 002): follows each ``/plan`` with the pose on
``/odom`` and commands ``/cmd_vel`` (differential drive: linear.x and
angular.z) until the last pose is reached, then zero velocity."""

from __future__ import annotations

from nav_msgs.msg import Path
from rclpy.qos import QoSPolicyKind
from rclpy.qos_overriding_options import QoSOverridingOptions

from .base import PLAN_QOS, Param, node_main
from .convert import path_from_msg
from .drive_node import ODOM_TIMEOUT, DriveNode

#: the /plan subscription's policies settable as qos_overrides./plan.subscription.<policy>
PLAN_QOS_OVERRIDES = (QoSPolicyKind.DURABILITY, QoSPolicyKind.RELIABILITY, QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH)


class GotoWaypointNode(DriveNode):
    CONTROLLER = "goto_waypoint"
    CONTROLLER_PARAMS = ("speed", "heading_gain", "reach_radius", "goal_radius")
    PARAMETERS = (
        Param("speed", 0.2, "forward speed when on course (m/s)"),
        Param("heading_gain", 1.5, "turn rate per radian of heading error (1/s)"),
        Param("reach_radius", 0.05, "a waypoint counts as reached this close (m)"),
        Param("goal_radius", 0.05, "the last pose counts as reached this close (m)"),
        ODOM_TIMEOUT,
    )

    def __init__(self, **kwargs) -> None:
        super().__init__("goto_waypoint", **kwargs)
        # latched like the pathplanner's /plan; a volatile publisher (nav2's planner_server,
        # `ros2 topic pub`) needs -p qos_overrides./plan.subscription.durability:=volatile
        self.create_subscription(Path, "plan", self.on_plan, PLAN_QOS,
                                 qos_overriding_options=QoSOverridingOptions(PLAN_QOS_OVERRIDES))

    def on_plan(self, msg) -> None:
        path = self.read(path_from_msg, msg, "/plan")
        if path is not None:
            self.send(self.drive.set_target(path[-1] if len(path) else None, path))


main = node_main(GotoWaypointNode)

if __name__ == "__main__":
    main()
