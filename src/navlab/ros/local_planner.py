"""``local_planner``, navlab's Nav2 ``controller_server``: runs a costmap
controller (``dwa``, ``dwa_barn``, ``mppi`` or ``rpp``) along each ``/plan``
from the pose on ``/odom`` and commands ``/cmd_vel`` (linear.x, angular.z;
linear.y for MPPI's omni model).

The controller plans on a Nav2-style layered costmap built for the robot's
footprint (``footprint`` or ``robot_radius``) from ``/map`` (static layer)
and, when its ``layers`` setting asks for it, ``/scan`` (obstacle layer),
with the controller's ``inflation_radius`` and ``cost_scaling_factor``; the
costmap goes out on ``/costmap`` with Nav2's 0–100 scaling. Every other
``-p NAME:=VALUE`` is a setting of the controller, routed by name
(``desired_linear_vel``, ``max_vel_x``, ``vx_max``, ``xy_goal_tolerance``,
``layers``, ...; ``navlab list controllers`` names them). The odometry frame
is taken to coincide with the map frame, as the sim publishes it.
"""

from __future__ import annotations

from typing import Any, Dict

from nav_msgs.msg import OccupancyGrid as GridMsg
from nav_msgs.msg import Odometry, Path
from geometry_msgs.msg import Twist
from rclpy.qos_overriding_options import QoSOverridingOptions
from sensor_msgs.msg import LaserScan

from .base import DEFAULT_QOS, MAP_QOS, PLAN_QOS, SCAN_QOS, NavlabNode, Param, node_main
from .convert import costmap_to_msg, grid_from_msg, path_from_msg, pose_from_msg, scan_points_from_msg, twist_msg
from .core import finite
from .costmap_drive import CostmapDrive
from .drive_node import ODOM_TIMEOUT
from .goto_waypoint import PLAN_QOS_OVERRIDES


class LocalPlannerNode(NavlabNode):
    PARAMETERS = (
        Param("controller", "rpp", "the costmap controller: dwa, dwa_barn, mppi or rpp"),
        Param("footprint", "", "the robot's outline \"[[x, y], ...]\" in its body frame (m), as Nav2's; "
                               "empty: a disc of robot_radius"),
        Param("robot_radius", 0.105, "the robot's radius (m) when no footprint is given (TurtleBot3 Burger's)",
              low=0.0),
        Param("controller_frequency", 20.0, "control cycles per second of /odom time (Hz); also the setting of "
                                            "that name of dwa and rpp"),
        Param("seed", 0, "mppi: seed of its samples (the same inputs give the same commands)"),
        Param("scan_timeout", 0.5, "with a sensor layer: stand still when the last /scan is older "
                                   "(wall-clock s)", low=0.0),
        Param("costmap_interval", 1.0, "with a sensor layer: publish /costmap this often (s of /odom time; "
                                       "0: only when a map arrives)", low=0.0),
        Param("frame_id", "map", "frame of /costmap"),
        ODOM_TIMEOUT,
    )

    def __init__(self, **kwargs) -> None:
        super().__init__("local_planner", automatically_declare_parameters_from_overrides=True, **kwargs)
        p = self.params
        self.pose = None
        self.core = CostmapDrive(self.log, p["controller"], p["footprint"], p["robot_radius"],
                                 p["controller_frequency"], p["odom_timeout"], p["scan_timeout"],
                                 p["costmap_interval"], p["seed"], **self.controller_params())
        self.cmd_pub = self.create_publisher(Twist, "cmd_vel", DEFAULT_QOS)
        self.costmap_pub = self.create_publisher(GridMsg, "costmap", MAP_QOS)
        self.create_subscription(GridMsg, "map", self.on_map, MAP_QOS)
        # latched like the pathplanner's /plan (a volatile publisher: qos_overrides./plan.subscription.durability)
        self.create_subscription(Path, "plan", self.on_plan, PLAN_QOS,
                                 qos_overriding_options=QoSOverridingOptions(PLAN_QOS_OVERRIDES))
        self.create_subscription(Odometry, "odom", self.on_odom, DEFAULT_QOS)
        if self.core.needs_scan:
            self.create_subscription(LaserScan, "scan", self.on_scan, SCAN_QOS)
        self.steady_timer(p["odom_timeout"] / 4, lambda: self.send(self.core.watchdog(self.monotonic())))
        self.log("info", f"{p['controller']} on layers {self.core.controller.layers}, footprint "
                         f"{self.core.footprint.describe()}, {p['controller_frequency']:g} Hz")

    def controller_params(self) -> Dict[str, Any]:
        """The settings given on the command line for the controller."""
        return self.passed_settings()

    def on_map(self, msg) -> None:
        grid = self.read(grid_from_msg, msg, "/map")
        if grid is not None:
            self.publish_costmap(self.core.set_map(grid))

    def on_plan(self, msg) -> None:
        path = self.read(path_from_msg, msg, "/plan")
        if path is not None:
            self.send(self.core.set_plan(path))

    def on_scan(self, msg) -> None:
        if len(msg.ranges) == 0:
            self.log("warn", "ignoring an empty /scan")
            return
        if self.pose is not None:  # placed with the latest /odom pose (the sim stamps both at one step)
            self.core.set_scan(scan_points_from_msg(msg, self.pose), self.monotonic())

    def on_odom(self, msg) -> None:
        pose = pose_from_msg(msg.pose.pose)
        if not finite(pose, "an /odom pose", self.log):
            return
        self.pose = pose
        t = self.stamp_seconds(msg.header.stamp)
        self.send(self.core.on_odom(t, pose, self.monotonic()))
        self.publish_costmap(self.core.costmap_due(t))

    def publish_costmap(self, costmap) -> None:
        if costmap is not None:
            self.costmap_pub.publish(costmap_to_msg(costmap, self.params["frame_id"],
                                                    self.get_clock().now().to_msg()))

    def send(self, twist) -> None:
        if twist is not None:
            self.cmd_pub.publish(twist_msg(*twist))


main = node_main(LocalPlannerNode)

if __name__ == "__main__":
    main()
