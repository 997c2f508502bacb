"""A costmap controller drives the sim's Jackal over real ROS 2 (run by
test_local_planner_node.py in a private network namespace): the ``sim`` node
(robot jackal) in a walled room with a wall across it, the ``local_planner``
node with the controller given on the command line, and a probe that
publishes the map and the plan the test wrote to WORKDIR (``room.yaml``,
``plan.json``: the robot starts at the plan's first point) on /map and /plan
and records /ground_truth, /costmap and /rosout.

    python local_planner_scenario.py WORKDIR CONTROLLER [NAME:=VALUE ...]

Prints one JSON object of observations.
"""

import json
import sys
import time

import numpy as np
import rclpy
from nav_msgs.msg import OccupancyGrid as GridMsg
from nav_msgs.msg import Odometry, Path
from rcl_interfaces.msg import Log
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from navlab.grid import load_map
from navlab.ros import convert as C
from navlab.ros.base import MAP_QOS, PLAN_QOS
from navlab.ros.local_planner import LocalPlannerNode
from navlab.ros.sim import SimNode
from scenario_tools import spinner

JACKAL = "[[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]]"
WALL_TIME_S = 60.0


class Probe(Node):
    def __init__(self):
        super().__init__("probe")
        self.truth, self.logs, self.costmaps = [], [], []
        self.create_subscription(Odometry, "ground_truth", self.truth.append, 200)
        self.create_subscription(Log, "/rosout", lambda m: self.logs.append((m.level, m.name, m.msg)), 100)
        self.create_subscription(GridMsg, "costmap", self.costmaps.append, MAP_QOS)
        self.map_pub = self.create_publisher(GridMsg, "map", MAP_QOS)
        self.plan_pub = self.create_publisher(Path, "plan", PLAN_QOS)


def main(workdir, controller, settings):
    grid = load_map(f"{workdir}/room.yaml")
    with open(f"{workdir}/plan.json") as f:
        path = np.array(json.load(f), float)
    rclpy.init()
    ex = SingleThreadedExecutor()
    sim = SimNode(cli_args=["--ros-args", "-p", f"world:={workdir}/room.yaml", "-p", "robot:=jackal",
                            "-p", f"x:={float(path[0, 0])!r}", "-p", f"y:={float(path[0, 1])!r}", "-p", "real_time_factor:=2.0",
                            "-p", "scan_rate:=10.0"])
    local = LocalPlannerNode(cli_args=["--ros-args", "-p", "use_sim_time:=true", "-p", f"controller:={controller}",
                                       "-p", f"footprint:=\"{JACKAL}\"", "-p", "inflation_radius:=0.5",
                                       *[a for s in settings for a in ("-p", s)]])
    probe = Probe()
    for node in (sim, local, probe):
        ex.add_node(node)

    spin = spinner(ex)

    def said(who, *words):
        return [text for _, name, text in probe.logs if name == who and any(w in text for w in words)]

    spin(10.0, lambda: probe.map_pub.get_subscription_count() >= 1 and probe.plan_pub.get_subscription_count() >= 1)
    probe.map_pub.publish(C.grid_to_msg(grid))
    probe.plan_pub.publish(C.path_to_msg(path))
    t0 = time.monotonic()
    ended = spin(WALL_TIME_S, lambda: said("local_planner", "goal reached", "no progress"))
    spin(0.3)  # the stop reaches the sim
    truth = [(*C.pose_from_msg(m.pose.pose), C.stamp_seconds(m.header.stamp)) for m in probe.truth]
    out = {"ended": ended, "wall_s": time.monotonic() - t0, "truth": truth,
           "planner_logs": said("local_planner", ""), "sim_errors": [t for lvl, n, t in probe.logs
                                                                       if n == "sim" and lvl >= 40],
           "costmaps": len(probe.costmaps), "cycles": local.core.cycles}
    if probe.costmaps:
        data = np.array(probe.costmaps[-1].data)
        out["costmap_values"] = {str(v): int((data == v).sum()) for v in (0, 99, 100, -1)}
    print(json.dumps(out))
    for node in (sim, local, probe):
        node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
