"""Recording ROS 2 topics to a rosbag2 (MCAP) with the ``rosbags`` library,
for Foxglove Studio or ``ros2 bag play``/RViz."""

from __future__ import annotations

from pathlib import Path
from typing import Dict, Sequence, Tuple

from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from nav_msgs.msg import Path as PathMsg
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan

from .base import DEFAULT_QOS, MAP_QOS, SCAN_QOS, NavlabNode

#: the navlab pipeline's topics: message class and subscription QoS
TOPICS: Dict[str, Tuple[type, object]] = {
    "/map": (OccupancyGrid, MAP_QOS),
    "/goal_pose": (PoseStamped, DEFAULT_QOS),
    "/odom": (Odometry, DEFAULT_QOS),
    "/ground_truth": (Odometry, DEFAULT_QOS),
    "/plan": (PathMsg, DEFAULT_QOS),
    "/cmd_vel": (Twist, DEFAULT_QOS),
    "/scan": (LaserScan, SCAN_QOS),
    "/clock": (Clock, DEFAULT_QOS),
}


def ros_type_name(msg_class: type) -> str:
    """``nav_msgs/msg/Odometry`` for nav_msgs.msg.Odometry."""
    return f"{msg_class.__module__.split('.')[0]}/msg/{msg_class.__name__}"


class BagRecorder(NavlabNode):
    """Writes every message of ``topics`` (serialized as received) to an
    MCAP rosbag2 at ``path`` (a new directory), stamped with the node's
    clock (simulated time under ``use_sim_time``)."""

    def __init__(self, path, topics: Sequence[str] = tuple(TOPICS), **kwargs) -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer
        from rosbags.typesys import Stores, get_typestore

        super().__init__("navlab_recorder", **kwargs)
        unknown = [t for t in topics if t not in TOPICS]
        if unknown:
            raise ValueError(f"cannot record {unknown}: known topics are {sorted(TOPICS)}")
        if Path(path).exists():
            raise ValueError(f"{path} exists already: give a new directory for the bag")
        typestore = get_typestore(Stores.ROS2_KILTED)
        self.writer = Writer(Path(path), version=9, storage_plugin=StoragePlugin.MCAP)
        self.writer.open()
        self.path, self.counts = Path(path), {}
        for topic in topics:
            msg_class, qos = TOPICS[topic]
            connection = self.writer.add_connection(topic, ros_type_name(msg_class), typestore=typestore)
            self.counts[topic] = 0
            self.create_subscription(msg_class, topic, self._writer_for(topic, connection), qos, raw=True)

    def _writer_for(self, topic: str, connection):
        def write(data: bytes) -> None:
            self.writer.write(connection, self.get_clock().now().nanoseconds, data)
            self.counts[topic] += 1

        return write

    def close(self) -> None:
        self.writer.close()
