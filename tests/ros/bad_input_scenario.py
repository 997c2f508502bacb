"""Bad input over real ROS 2 topics (run by test_bad_input.py inside a
private network namespace): the planner, follower and sim nodes run in this
process beside a probe node that sends them what a careless system would,
and records what comes back. Prints one JSON object of observations."""

import json
import math
import sys

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid as GridMsg
from nav_msgs.msg import Odometry, Path
from rcl_interfaces.msg import Log
from sensor_msgs.msg import LaserScan
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from navlab.grid import OccupancyGrid, save_map
from navlab.ros import convert as C
from navlab.ros.astar_pathplanner import AStarPathPlanner
from navlab.ros.base import MAP_QOS, PLAN_QOS
from navlab.ros.goto_waypoint import GotoWaypointNode
from navlab.ros.potential_field_navigator import PotentialFieldNavigator
from navlab.ros.sim import SimNode
from scenario_tools import spinner


class Probe(Node):
    def __init__(self):
        super().__init__("probe")
        self.plans, self.cmds, self.logs, self.odoms = [], [], [], []
        self.create_subscription(Path, "plan", self.plans.append, 10)
        self.create_subscription(Twist, "cmd_vel", self.cmds.append, 10)
        self.create_subscription(Log, "/rosout", lambda m: self.logs.append((m.level, m.name, m.msg)), 100)
        self.create_subscription(Odometry, "sim_odom", self.odoms.append, 10)
        self.map_pub = self.create_publisher(GridMsg, "map", MAP_QOS)
        self.goal_pub = self.create_publisher(PoseStamped, "goal_pose", 10)
        self.odom_pub = self.create_publisher(Odometry, "odom", 10)
        self.plan_pub = self.create_publisher(Path, "plan", PLAN_QOS)
        self.volatile_plan_pub = self.create_publisher(Path, "volatile_plan", 10)  # as nav2's planner_server
        self.late_cmds = []
        self.create_subscription(Twist, "late_cmd_vel", self.late_cmds.append, 10)
        self.cmd_pub = self.create_publisher(Twist, "sim_cmd_vel", 10)
        self.nav_cmds = []
        self.create_subscription(Twist, "nav_cmd_vel", self.nav_cmds.append, 10)
        self.nav_goal_pub = self.create_publisher(PoseStamped, "nav_goal_pose", 10)
        self.nav_odom_pub = self.create_publisher(Odometry, "nav_odom", 10)
        self.nav_scan_pub = self.create_publisher(LaserScan, "nav_scan", 10)

    def goal(self, x, y):
        msg = PoseStamped()
        msg.header.frame_id = "map"
        msg.pose = C.pose_msg(x, y, 0.0)
        self.goal_pub.publish(msg)

    def logs_since(self, n, name):
        return [(level, text) for level, who, text in self.logs[n:] if who == name]


def room():
    blocked = np.zeros((30, 40), bool)
    blocked[0:20, 20] = True
    return OccupancyGrid(blocked, 0.1, (0.0, 0.0, 0.0))


def navlab_lidar():
    from navlab.sensors import Lidar

    return Lidar()


def main(workdir):
    rclpy.init()
    out = {}
    ex = SingleThreadedExecutor()
    planner = AStarPathPlanner(parameter_overrides=[Parameter("inflation_radius", value=0.2)])
    follower = GotoWaypointNode(parameter_overrides=[Parameter("odom_timeout", value=0.3)])
    save_map(room(), f"{workdir}/room.yaml")
    sim = SimNode(parameter_overrides=[Parameter("world", value=f"{workdir}/room.yaml"),
                                       Parameter("x", value=0.5), Parameter("y", value=0.5),
                                       Parameter("real_time_factor", value=5.0), Parameter("scan_rate", value=0.0),
                                       Parameter("publish_clock", value=False)],
                  cli_args=["--ros-args", "-r", "cmd_vel:=sim_cmd_vel", "-r", "odom:=sim_odom",
                            "-r", "ground_truth:=sim_truth"])
    navigator = PotentialFieldNavigator(cli_args=["--ros-args", "-r", "goal_pose:=nav_goal_pose", "-r",
                                                  "odom:=nav_odom", "-r", "scan:=nav_scan", "-r",
                                                  "cmd_vel:=nav_cmd_vel"])
    probe = Probe()
    for node in (planner, follower, sim, navigator, probe):
        ex.add_node(node)

    spin = spinner(ex)

    def drive_a_little():
        """Five /odom messages 50 ms apart: a follower with a plan answers each."""
        for _ in range(5):
            probe.odom_pub.publish(odom)
            spin(0.05)

    def connected(pub, n=1):
        return spin(5.0, lambda: pub.get_subscription_count() >= n)

    connected(probe.goal_pub)
    connected(probe.odom_pub, 2)  # planner and follower
    # 1. a goal before any map: kept, logged, planned once the map arrives
    n = len(probe.logs)
    probe.goal(3.5, 0.5)
    spin(0.5)
    out["goal_before_map_logs"] = probe.logs_since(n, "astar_pathplanner")
    out["plans_before_map"] = len(probe.plans)
    odom = C.odometry_msg((0.5, 0.5, 0.0), (0.0, 0.0, 0.0))
    probe.odom_pub.publish(odom)
    probe.map_pub.publish(C.grid_to_msg(room()))
    out["plan_after_map"] = spin(3.0, lambda: len(probe.plans) >= 1)
    if probe.plans:
        out["plan_points"] = C.path_from_msg(probe.plans[0]).tolist()
    # 2. goals outside the map and in an obstacle: an error each, no path
    for label, (x, y) in (("outside", (9.0, 1.0)), ("obstacle", (2.05, 1.0))):
        n, plans = len(probe.logs), len(probe.plans)
        probe.goal(x, y)
        spin(0.5)
        out[f"goal_{label}_logs"] = probe.logs_since(n, "astar_pathplanner")
        out[f"goal_{label}_plans"] = len(probe.plans) - plans
    # 3. a malformed map (data of the wrong length) and an empty one: errors; the old map stays in use
    for label, msg in (("short", C.grid_to_msg(room())), ("empty", GridMsg())):
        if label == "short":
            msg.data = msg.data[:-5]
        n = len(probe.logs)
        probe.map_pub.publish(msg)
        spin(0.5)
        out[f"map_{label}_logs"] = probe.logs_since(n, "astar_pathplanner")
    plans = len(probe.plans)
    probe.goal(1.0, 2.5)
    out["plans_after_bad_maps"] = spin(3.0, lambda: len(probe.plans) > plans)
    # 3b. a follower started after the last plan went out still follows it (/plan is latched), and one
    #     told to take a volatile /plan (as nav2's planner_server publishes it) follows such a publisher
    late = GotoWaypointNode(cli_args=["--ros-args", "-r", "__node:=late_follower", "-r", "cmd_vel:=late_cmd_vel"])
    volatile = GotoWaypointNode(cli_args=["--ros-args", "-r", "__node:=volatile_follower", "-r",
                                          "cmd_vel:=late_cmd_vel", "-r", "plan:=volatile_plan", "-p",
                                          "qos_overrides./volatile_plan.subscription.durability:=volatile"])
    ex.add_node(late)
    connected(probe.odom_pub, 4)  # the planner and three followers
    drive_a_little()
    out["late_follower_moves"] = sum(c.linear.x > 0 for c in probe.late_cmds)
    ex.remove_node(late)
    late.destroy_node()
    ex.add_node(volatile)
    connected(probe.volatile_plan_pub)
    probe.volatile_plan_pub.publish(C.path_to_msg(np.array([[0.5, 0.5], [1.5, 0.5]])))
    probe.late_cmds.clear()
    drive_a_little()
    out["volatile_follower_moves"] = sum(c.linear.x > 0 for c in probe.late_cmds)
    ex.remove_node(volatile)
    volatile.destroy_node()
    # 4. the follower on the planned path, then /odom stops: it stops the robot
    n, cmds = len(probe.logs), len(probe.cmds)
    drive_a_little()
    moving = [c for c in probe.cmds[cmds:] if c.linear.x > 0]
    out["commands_while_odom"] = len(moving)
    cmds = len(probe.cmds)
    spin(1.0)
    after = probe.cmds[cmds:]
    out["stops_after_odom_loss"] = sum(c.linear.x == 0 and c.angular.z == 0 for c in after)
    out["moves_after_odom_loss"] = sum(c.linear.x != 0 or c.angular.z != 0 for c in after)
    out["odom_loss_logs"] = probe.logs_since(n, "goto_waypoint")
    # 5. an empty /plan stops the robot; a /plan with NaN is refused
    probe.odom_pub.publish(odom)
    spin(0.1)
    n, cmds = len(probe.logs), len(probe.cmds)
    probe.plan_pub.publish(Path())
    spin(0.3)
    out["empty_plan_stops"] = sum(c.linear.x == 0 for c in probe.cmds[cmds:])
    bad = C.path_to_msg(np.array([[0.0, 0.0], [1.0, 1.0]]))
    bad.poses[1].pose.position.x = math.nan
    probe.plan_pub.publish(bad)
    spin(0.3)
    out["plan_logs"] = probe.logs_since(n, "goto_waypoint")
    # 6. the sim: a NaN command is refused, a real one moves it, and a stale one times out
    n = len(probe.logs)
    probe.cmd_pub.publish(C.twist_msg(0.0, 0.0, 0.0))
    bad_cmd = Twist()
    bad_cmd.linear.x = math.nan
    probe.cmd_pub.publish(bad_cmd)
    spin(0.3)
    out["sim_logs"] = probe.logs_since(n, "sim")
    probe.cmd_pub.publish(C.twist_msg(0.2, 0.0, 0.0))
    spin(1.0)  # 5 simulated seconds: the command (0.5 s timeout) moves the robot 0.1 m, then it stops
    last = probe.odoms[-1].pose.pose.position
    out["sim_moved_to"] = [last.x, last.y]
    out["sim_final_speed"] = probe.odoms[-1].twist.twist.linear.x
    # 7. the navigator: with a goal but no scan it stands still; an empty scan is refused;
    #    with a scan it drives; a goal at NaN is refused
    connected(probe.nav_goal_pub)
    connected(probe.nav_scan_pub)
    n = len(probe.logs)
    msg = PoseStamped()
    msg.pose = C.pose_msg(3.0, 0.0, 0.0)
    probe.nav_goal_pub.publish(msg)
    spin(0.2)
    for _ in range(3):
        probe.nav_odom_pub.publish(odom)
        spin(0.05)
    out["nav_blind_commands"] = [[c.linear.x, c.linear.y, c.angular.z] for c in probe.nav_cmds]
    probe.nav_scan_pub.publish(LaserScan())
    spin(0.2)
    probe.nav_scan_pub.publish(C.scan_to_msg(np.full(360, np.inf), navlab_lidar()))
    spin(0.2)
    probe.nav_odom_pub.publish(odom)
    spin(0.3)
    out["nav_seeing_command"] = [probe.nav_cmds[-1].linear.x, probe.nav_cmds[-1].linear.y]
    spin(0.8)  # longer than scan_timeout (0.5 s of wall time) with no scan: the one seen goes stale
    probe.nav_odom_pub.publish(odom)
    spin(0.3)
    out["nav_stale_command"] = [probe.nav_cmds[-1].linear.x, probe.nav_cmds[-1].linear.y]
    nan_goal = PoseStamped()
    nan_goal.pose.position.x = math.nan
    probe.nav_goal_pub.publish(nan_goal)
    spin(0.2)
    out["nav_logs"] = probe.logs_since(n, "potential_field_navigator")
    print(json.dumps(out))
    for node in (planner, follower, sim, navigator, probe):
        node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main(sys.argv[1])
