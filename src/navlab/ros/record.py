"""Recording ROS 2 topics to a rosbag2 (MCAP) with the ``rosbags`` library,
for Foxglove Studio or ``ros2 bag play``/RViz."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Dict, Sequence, Tuple

from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from nav_msgs.msg import Path as PathMsg
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from visualization_msgs.msg import MarkerArray

from ..errors import ParameterError
from .base import DEFAULT_QOS, MAP_QOS, PLAN_QOS, SCAN_QOS, NavlabNode
from .convert import tf_message_type

#: the navlab pipeline's topics: message class and subscription QoS
TOPICS: Dict[str, Tuple[type, object]] = {
    "/map": (OccupancyGrid, MAP_QOS),
    "/goal_pose": (PoseStamped, DEFAULT_QOS),
    "/odom": (Odometry, DEFAULT_QOS),
    "/ground_truth": (Odometry, DEFAULT_QOS),
    "/plan": (PathMsg, PLAN_QOS),
    "/plan_tree": (MarkerArray, DEFAULT_QOS),
    "/cmd_vel": (Twist, DEFAULT_QOS),
    "/scan": (LaserScan, SCAN_QOS),
    "/clock": (Clock, DEFAULT_QOS),
}
_TF = tf_message_type()
if _TF is not None:
    TOPICS.update({"/tf": (_TF, DEFAULT_QOS), "/tf_static": (_TF, MAP_QOS)})


def offered_qos(qos) -> tuple:
    """The publisher QoS to store with a topic in the bag, so that ``ros2 bag
    play`` replays latched topics (``/map``, ``/tf_static``) transient-local;
    empty (the player's default) for a plain history depth."""
    from rclpy.qos import QoSProfile
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

    if not isinstance(qos, QoSProfile):
        return ()
    unset = QosTime(0, 0)
    return (Qos(QosHistory[qos.history.name], qos.depth, QosReliability[qos.reliability.name],
                QosDurability[qos.durability.name], unset, unset, QosLiveliness[qos.liveliness.name], unset,
                False),)


#: the recorder's history depth: room for the backlog of a recorder that
#: shares the CPU with a simulator running many times faster than real time
RECORD_DEPTH = 2000


def recording_qos(qos):
    """``qos`` (a profile or a depth) with the recorder's deep history, so
    that a busy recorder falls behind instead of losing messages."""
    from rclpy.qos import QoSProfile

    if not isinstance(qos, QoSProfile):
        return QoSProfile(depth=max(qos, RECORD_DEPTH))
    deep = copy.copy(qos)
    deep.depth = max(qos.depth, RECORD_DEPTH)
    return deep


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
            raise ParameterError(f"cannot record {unknown}: known topics are {sorted(TOPICS)}")
        if Path(path).exists():
            raise ParameterError(f"{path} exists already: give a new directory for the bag")
        typestore = get_typestore(Stores.ROS2_KILTED)
        self.writer = Writer(Path(path), version=9, storage_plugin=StoragePlugin.MCAP)
        self.writer.open()
        self.path, self.counts = Path(path), {}
        for topic in topics:
            msg_class, qos = TOPICS[topic]
            connection = self.writer.add_connection(topic, ros_type_name(msg_class), typestore=typestore,
                                                    offered_qos_profiles=offered_qos(qos))
            self.counts[topic] = 0
            self.create_subscription(msg_class, topic, self._writer_for(topic, connection), recording_qos(qos),
                                     raw=True)

    def _writer_for(self, topic: str, connection):
        def write(data: bytes) -> None:
            self.writer.write(connection, self.get_clock().now().nanoseconds, data)
            self.counts[topic] += 1

        return write

    def close(self) -> None:
        self.writer.close()
