"""Goal poses with a heading over real ROS 2 (run by test_pose_goals.py in a
private network namespace): a ``pathplanner`` with ``algorithm:=hybrid_astar``
gets a map, an odometry pose and a /goal_pose facing back the way the robot
came; the probe records the /plan. Prints one JSON object of observations."""

import json
import math

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import OccupancyGrid as GridMsg
from nav_msgs.msg import Path
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from navlab.grid import OccupancyGrid
from navlab.ros import convert as C
from navlab.ros.base import MAP_QOS, PLAN_QOS
from navlab.ros.pathplanner import PathPlanner
from scenario_tools import spinner


class Probe(Node):
    def __init__(self):
        super().__init__("probe")
        self.plans = []
        self.create_subscription(Path, "plan", self.plans.append, PLAN_QOS)
        self.map_pub = self.create_publisher(GridMsg, "map", MAP_QOS)
        self.goal_pub = self.create_publisher(PoseStamped, "goal_pose", 10)
        self.odom_pub = self.create_publisher(Odometry, "odom", 10)


def main():
    rclpy.init()
    ex = SingleThreadedExecutor()
    planner = PathPlanner(parameter_overrides=[Parameter("algorithm", value="hybrid_astar"),
                                               Parameter("inflation_radius", value=0.2),
                                               Parameter("turning_radius", value=0.5),
                                               Parameter("motion", value="reeds_shepp")])
    probe = Probe()
    for node in (planner, probe):
        ex.add_node(node)

    spin = spinner(ex)

    spin(5.0, lambda: probe.goal_pub.get_subscription_count() >= 1 and probe.odom_pub.get_subscription_count() >= 1)
    # an empty 6 × 4 m room; the robot at (1, 2) facing east, the goal 3 m east of it facing west
    probe.map_pub.publish(C.grid_to_msg(OccupancyGrid(np.zeros((40, 60), bool), 0.1, (0.0, 0.0, 0.0))))
    probe.odom_pub.publish(C.odometry_msg((1.0, 2.0, 0.0), (0.0, 0.0, 0.0)))
    spin(0.5)
    goal = PoseStamped()
    goal.header.frame_id = "map"
    goal.pose = C.pose_msg(4.0, 2.0, math.pi)
    probe.goal_pub.publish(goal)
    spin(20.0, lambda: len(probe.plans) >= 1)
    out = {"plans": len(probe.plans)}
    if probe.plans:
        out["poses"] = [C.pose_from_msg(p.pose) for p in probe.plans[0].poses]
    print(json.dumps(out))
    for node in (planner, probe):
        node.destroy_node()
    rclpy.shutdown()


if __name__ == "__main__":
    main()
