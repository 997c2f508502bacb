"""Run in a private network namespace by test_costmap_topic.py: the sim node with the jackal in a
BARN world publishes its costmap; prints the received message's figures as JSON."""

import json
import sys

import numpy as np
import rclpy
from nav_msgs.msg import OccupancyGrid
from rclpy.parameter import Parameter

from navlab.ros.base import MAP_QOS
from navlab.ros.sim import SimNode

rclpy.init()
node = SimNode(parameter_overrides=[Parameter("world", value=sys.argv[1]), Parameter("robot", value="jackal"),
                                    Parameter("x", value=-2.0), Parameter("y", value=3.0),
                                    Parameter("yaw", value=1.57), Parameter("costmap_inflation_radius", value=0.5)])
got = []
node.create_subscription(OccupancyGrid, "costmap", got.append, MAP_QOS)
for _ in range(100):
    rclpy.spin_once(node, timeout_sec=0.1)
    if got:
        break
data = np.array(got[0].data)
print(json.dumps({"width": got[0].info.width, "height": got[0].info.height, "resolution": got[0].info.resolution,
                  "lethal": int((data == 100).sum()), "inscribed": int((data == 99).sum()),
                  "unknown": int((data == -1).sum()), "values": sorted(set(data.tolist()))[:3]}))
node.destroy_node()
rclpy.shutdown()
