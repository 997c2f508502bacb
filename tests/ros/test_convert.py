"""Message conversions against the real ROS 2 message classes."""

import math

import numpy as np
import pytest

pytest.importorskip("rclpy", reason="rclpy cannot be imported: the ros2 extra is not installed")

from navlab.grid.occupancy import OccupancyGrid  # noqa: E402
from navlab.ros import convert as C  # noqa: E402
from navlab.sensors import Lidar  # noqa: E402


def test_grid_round_trip_keeps_origin_resolution_and_row_order():
    blocked = np.zeros((3, 4), bool)
    blocked[0, 3] = True  # bottom row (y = 0), right column
    unknown = np.zeros_like(blocked)
    unknown[2, 0] = True
    grid = OccupancyGrid(blocked, 0.05, (-1.0, 2.0, 0.3), unknown)
    msg = C.grid_to_msg(grid)
    assert (msg.info.width, msg.info.height) == (4, 3)
    assert msg.data[3] == 100 and msg.data[8] == -1 and msg.data[0] == 0  # row-major from cell (0, 0)
    back = C.grid_from_msg(msg)
    assert np.array_equal(back.blocked, blocked) and np.array_equal(back.unknown, unknown)
    assert back.resolution == pytest.approx(0.05) and back.origin == pytest.approx((-1.0, 2.0, 0.3))


def test_bad_grid_messages():
    msg = C.grid_to_msg(OccupancyGrid(np.zeros((2, 2), bool)))
    msg.data = [0, 0, 0]
    with pytest.raises(ValueError, match="expected 2x2"):
        C.grid_from_msg(msg)
    msg.info.width = 0
    with pytest.raises(ValueError, match="empty"):
        C.grid_from_msg(msg)


@pytest.mark.parametrize("yaw", [0.0, 0.5, -2.0, math.pi - 1e-9])
def test_quaternions(yaw):
    q = C.yaw_to_quaternion(yaw)
    assert math.isclose(sum(v * v for v in q), 1.0)
    assert C.quaternion_to_yaw(*q) == pytest.approx(yaw)


def test_path_and_scan_round_trips():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]])
    msg = C.path_to_msg(pts)
    assert np.array_equal(C.path_from_msg(msg), pts)
    assert C.pose_from_msg(msg.poses[0].pose)[2] == pytest.approx(0.0)
    assert C.pose_from_msg(msg.poses[1].pose)[2] == pytest.approx(math.pi / 2)
    lidar = Lidar(beams=4, range_min=0.15, range_max=12.0)
    ranges = np.array([1.0, np.inf, -np.inf, 11.0])
    angles, back = C.scan_from_msg(C.scan_to_msg(ranges, lidar))
    assert np.array_equal(back, ranges) and angles == pytest.approx(lidar.angles)


def test_twists_and_odometry():
    assert C.twist_from_msg(C.twist_msg(0.1, -0.2, 0.3)) == pytest.approx((0.1, -0.2, 0.3))
    bad = C.twist_msg(float("nan"), 0, 0)
    with pytest.raises(ValueError):
        C.twist_from_msg(bad)
    odom = C.odometry_msg((1.0, 2.0, 0.5), (0.2, 0.0, 0.1))
    assert C.pose_from_msg(odom.pose.pose) == pytest.approx((1.0, 2.0, 0.5))
    assert odom.child_frame_id == "base_link"


def test_transform_places_the_child_frame_at_the_pose():
    msg = C.transform_msg((1.5, -2.0, 2.5), "odom", "base_link", C.time_msg(3.25))
    t, r = msg.transform.translation, msg.transform.rotation
    assert (msg.header.frame_id, msg.child_frame_id) == ("odom", "base_link")
    assert (t.x, t.y, t.z) == (1.5, -2.0, 0.0) and C.stamp_seconds(msg.header.stamp) == 3.25
    assert (r.x, r.y) == (0.0, 0.0) and (r.z, r.w) == pytest.approx((math.sin(1.25), math.cos(1.25)))


def test_the_built_tf_message_is_kilted_tf2_msgs_on_the_wire():
    """ros_interfaces/tf2_msgs must be the same type as ROS 2 Kilted's
    tf2_msgs/TFMessage: the same type hash and the same CDR bytes, checked
    against rosbags' own copy of the Kilted definitions."""
    TFMessage = C.tf_message_type()
    if TFMessage is None:
        pytest.skip("tf2_msgs is not installed: pip install ./ros_interfaces/tf2_msgs")
    import json
    from pathlib import Path

    import tf2_msgs
    from rclpy.serialization import serialize_message
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_KILTED)
    prefix = Path(tf2_msgs.__file__).parents[4]  # <prefix>/lib/pythonX.Y/site-packages/tf2_msgs/__init__.py
    description = json.loads((prefix / "share" / "tf2_msgs" / "msg" / "TFMessage.json").read_text())
    built = {h["type_name"]: h["hash_string"] for h in description["type_hashes"]}
    assert built["tf2_msgs/msg/TFMessage"] == store.hash_rihs01("tf2_msgs/msg/TFMessage")
    msg = TFMessage(transforms=[C.transform_msg((1.0, 2.0, 0.5), "odom", "base_link", C.time_msg(7.5)),
                                C.transform_msg((0.0, 0.0, 0.0), "map", "odom")])
    back = store.deserialize_cdr(bytes(serialize_message(msg)), "tf2_msgs/msg/TFMessage")
    assert [(t.header.frame_id, t.child_frame_id) for t in back.transforms] == [("odom", "base_link"), ("map", "odom")]
    first = back.transforms[0]
    assert (first.header.stamp.sec, first.header.stamp.nanosec) == (7, 500_000_000)
    assert (first.transform.translation.x, first.transform.translation.y) == (1.0, 2.0)
    assert first.transform.rotation.z == pytest.approx(math.sin(0.25))


def test_tree_markers_draw_every_edge_once_in_the_map_frame():
    """A LINE_LIST with one (parent, child) point pair per edge, after a
    DELETEALL; checked against the real message classes and, on the wire,
    against rosbags' own copy of Kilted's visualization_msgs."""
    from rclpy.serialization import serialize_message
    from rosbags.typesys import Stores, get_typestore
    from visualization_msgs.msg import Marker, MarkerArray

    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [2.0, 0.5]])
    parent = np.array([-1, 0, 1, 1])
    msg = C.tree_to_markers(nodes, parent, "map", C.time_msg(12.5))
    assert isinstance(msg, MarkerArray)
    clear, lines = msg.markers
    assert clear.action == Marker.DELETEALL
    assert (lines.type, lines.action, lines.header.frame_id) == (Marker.LINE_LIST, Marker.ADD, "map")
    assert C.stamp_seconds(lines.header.stamp) == 12.5 and lines.scale.x > 0 and lines.color.a > 0
    assert lines.pose.orientation.w == 1.0  # an identity pose: points are map coordinates
    pairs = [((a.x, a.y), (b.x, b.y)) for a, b in zip(lines.points[::2], lines.points[1::2])]
    assert pairs == [((0.0, 0.0), (1.0, 0.0)), ((1.0, 0.0), (1.0, 1.0)), ((1.0, 0.0), (2.0, 0.5))]
    store = get_typestore(Stores.ROS2_KILTED)
    back = store.deserialize_cdr(bytes(serialize_message(msg)), "visualization_msgs/msg/MarkerArray")
    assert [m.action for m in back.markers] == [Marker.DELETEALL, Marker.ADD]
    assert [(p.x, p.y) for p in back.markers[1].points] == [p for pair in pairs for p in pair]
    # a root alone: no edges, an empty line list
    assert len(C.tree_to_markers(nodes[:1], parent[:1]).markers[1].points) == 0


def test_costmap_message_uses_nav2_scaling():
    from navlab.world.costmap import Costmap

    costs = np.array([[0, 1, 128, 252], [253, 254, 255, 0]], np.uint8)
    msg = C.costmap_to_msg(Costmap(costs, 0.05, (1.0, -2.0)))
    assert (msg.info.width, msg.info.height) == (4, 2)
    assert list(msg.data) == [0, 1, 1 + 97 * 127 // 251, 98, 99, 100, -1, 0]
    assert (msg.info.origin.position.x, msg.info.origin.position.y) == (1.0, -2.0)
