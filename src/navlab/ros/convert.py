"""Conversions between ROS 2 messages and navlab's data.

Conventions: nav_msgs/OccupancyGrid stores cells row-major starting with
cell (0, 0) at ``info.origin`` (row index = y), exactly navlab's
``OccupancyGrid.blocked[y, x]``, so no flip is needed (the flip happens only
between map images, whose first row is the top, and grids). Occupancy
values: 100 blocked, 0 free, −1 unknown. Angles are radians; quaternions
are planar rotations about z.
"""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np

from ..errors import ParameterError
from ..grid.occupancy import OccupancyGrid


def yaw_to_quaternion(yaw: float) -> Tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation by ``yaw`` about z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


def quaternion_to_yaw(x: float, y: float, z: float, w: float) -> float:
    """The rotation about z of a quaternion (its planar part)."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def pose_msg(x: float, y: float, yaw: float):
    from geometry_msgs.msg import Pose

    p = Pose()
    p.position.x, p.position.y = float(x), float(y)
    q = yaw_to_quaternion(yaw)
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = q
    return p


def pose_from_msg(pose) -> Tuple[float, float, float]:
    o = pose.orientation
    return pose.position.x, pose.position.y, quaternion_to_yaw(o.x, o.y, o.z, o.w)


def grid_to_msg(grid: OccupancyGrid, frame_id: str = "map", stamp=None):
    """nav_msgs/OccupancyGrid of a navlab grid (100 blocked, 0 free, −1 unknown)."""
    from nav_msgs.msg import OccupancyGrid as GridMsg

    msg = GridMsg()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    msg.info.resolution = float(grid.resolution)
    msg.info.width, msg.info.height = grid.width, grid.height
    msg.info.origin = pose_msg(*grid.origin)
    data = np.where(grid.blocked, 100, np.where(grid.unknown, -1, 0)).astype(np.int8)
    msg.data = data.ravel().tolist()
    return msg


def costmap_to_msg(costmap, frame_id: str = "map", stamp=None):
    """nav_msgs/OccupancyGrid of a :class:`~navlab.world.costmap.Costmap` with Nav2's scaling
    (0 free, 1–98 inflated, 99 inscribed, 100 lethal, −1 unknown), as Nav2's costmap publisher."""
    from nav_msgs.msg import OccupancyGrid as GridMsg

    msg = GridMsg()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    msg.info.resolution = float(costmap.resolution)
    msg.info.height, msg.info.width = costmap.shape
    msg.info.origin = pose_msg(costmap.origin[0], costmap.origin[1], 0.0)
    msg.data = costmap.to_occupancy_values().ravel().tolist()
    return msg


def grid_from_msg(msg, occupied_threshold: int = 65, free_threshold: int = 25, name: str = "map") -> OccupancyGrid:
    """A navlab grid from nav_msgs/OccupancyGrid: values ≥ ``occupied_threshold``
    are blocked, −1 and values between the thresholds unknown.

    Raises
    ------
    ParameterError
        Empty map, zero resolution, or data of the wrong length.
    """
    w, h = int(msg.info.width), int(msg.info.height)
    if w == 0 or h == 0 or not msg.info.resolution > 0:
        raise ParameterError(f"empty map or bad resolution: {w}x{h} cells at {msg.info.resolution} m")
    data = np.asarray(msg.data, dtype=np.int16)
    if data.size != w * h:
        raise ParameterError(f"map data has {data.size} cells, expected {w}x{h} = {w * h}")
    values = data.reshape(h, w)
    blocked = values >= occupied_threshold
    unknown = (values < 0) | ((values > free_threshold) & ~blocked)
    return OccupancyGrid(blocked, float(msg.info.resolution), pose_from_msg(msg.info.origin), unknown, name)


def path_to_msg(points: np.ndarray, frame_id: str = "map", stamp=None):
    """nav_msgs/Path through (N, 2) points, each pose facing the next point; or
    through (N, 3) poses with their own headings (a pose planner's: on a reverse
    stretch they face away from the way the robot goes, as Nav2's planners publish it)."""
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import Path

    msg = Path()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    pts = np.asarray(points, float)
    if pts.ndim == 2 and pts.shape[1] == 3:
        for x, y, yaw in pts:
            ps = PoseStamped()
            ps.header = msg.header
            ps.pose = pose_msg(x, y, yaw)
            msg.poses.append(ps)
        return msg
    for i, (x, y) in enumerate(pts):
        nxt = pts[min(i + 1, len(pts) - 1)] if i + 1 < len(pts) else pts[i] + (pts[i] - pts[i - 1] if i else 0)
        yaw = math.atan2(nxt[1] - y, nxt[0] - x) if np.any(nxt != pts[i]) else 0.0
        ps = PoseStamped()
        ps.header = msg.header
        ps.pose = pose_msg(x, y, yaw)
        msg.poses.append(ps)
    return msg


def tree_edges(nodes: np.ndarray, parent: np.ndarray) -> np.ndarray:
    """(E, 2, 2) segments (parent point, child point) of a search tree given
    as node positions and parent indices (−1 for the root)."""
    nodes = np.asarray(nodes, float).reshape(-1, 2)
    parent = np.asarray(parent, np.int64).reshape(-1)
    child = np.flatnonzero(parent >= 0)
    return np.stack([nodes[parent[child]], nodes[child]], axis=1)


def tree_to_markers(nodes: np.ndarray, parent: np.ndarray, frame_id: str = "map", stamp=None,
                    width: float = 0.01, color=(0.2, 0.5, 1.0, 0.6)):
    """visualization_msgs/MarkerArray drawing a search tree: a DELETEALL (the
    previous plan's tree goes), then one LINE_LIST marker with a point pair
    per edge (parent, child), in ``frame_id`` at z = 0. RViz and Foxglove show it.

    Parameters
    ----------
    nodes : (N, 2) array
    parent : (N,) int array
        Each node's parent index, −1 for the root (``Result.tree``).
    width : float
        Line width (m).
    color : (r, g, b, a)
    """
    from geometry_msgs.msg import Point
    from visualization_msgs.msg import Marker, MarkerArray

    clear = Marker(action=Marker.DELETEALL)
    clear.header.frame_id = frame_id
    lines = Marker(ns="plan_tree", id=0, type=Marker.LINE_LIST, action=Marker.ADD)
    lines.header.frame_id = frame_id
    if stamp is not None:
        clear.header.stamp = lines.header.stamp = stamp
    lines.pose.orientation.w = 1.0
    lines.scale.x = float(width)
    lines.color.r, lines.color.g, lines.color.b, lines.color.a = map(float, color)
    lines.points = [Point(x=float(x), y=float(y)) for x, y in tree_edges(nodes, parent).reshape(-1, 2).tolist()]
    return MarkerArray(markers=[clear, lines])


def path_from_msg(msg) -> np.ndarray:
    return np.array([[p.pose.position.x, p.pose.position.y] for p in msg.poses], dtype=float).reshape(-1, 2)


def scan_to_msg(ranges: np.ndarray, lidar, frame_id: str = "base_link", stamp=None, scan_time: float = 0.1):
    """sensor_msgs/LaserScan of a navlab scan (REP 117 infinities kept)."""
    from sensor_msgs.msg import LaserScan

    msg = LaserScan()
    msg.header.frame_id = frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    msg.angle_min = float(lidar.angles[0])
    msg.angle_increment = float(lidar.angle_increment)
    msg.angle_max = float(lidar.angles[-1])
    msg.range_min, msg.range_max = float(lidar.range_min), float(lidar.range_max)
    msg.scan_time = float(scan_time)
    msg.time_increment = float(scan_time / max(len(ranges), 1))
    msg.ranges = [float(r) for r in ranges]
    return msg


def scan_from_msg(msg) -> Tuple[np.ndarray, np.ndarray]:
    """(angles, ranges) of a LaserScan; readings outside [range_min,
    range_max] and NaNs become ±inf as in REP 117."""
    ranges = np.asarray(msg.ranges, dtype=float)
    if ranges.size == 0:
        raise ParameterError("empty LaserScan")
    angles = msg.angle_min + msg.angle_increment * np.arange(ranges.size)
    ranges = np.where(np.isnan(ranges), np.inf, ranges)
    ranges = np.where(ranges > msg.range_max, np.inf, ranges)
    ranges = np.where(ranges < msg.range_min, -np.inf, ranges)
    return angles, ranges


def scan_points_from_msg(msg, pose) -> np.ndarray:
    """World points (N, 2) of a LaserScan's valid readings seen from ``pose``
    (x, y, θ) of the scanner (seed 004, eq. 18–19)."""
    from ..sensors.raycast import scan_points

    angles, ranges = scan_from_msg(msg)
    out = np.empty((ranges.size, 2))
    n = scan_points(np.asarray(pose, float), angles, ranges, out)
    return out[:n]


def odometry_msg(pose, twist, frame_id: str = "odom", child_frame_id: str = "base_link", stamp=None):
    """nav_msgs/Odometry: pose in ``frame_id``, twist (vx, vy, ω) in the body frame."""
    from nav_msgs.msg import Odometry

    msg = Odometry()
    msg.header.frame_id = frame_id
    msg.child_frame_id = child_frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    msg.pose.pose = pose_msg(*pose)
    msg.twist.twist.linear.x, msg.twist.twist.linear.y = float(twist[0]), float(twist[1])
    msg.twist.twist.angular.z = float(twist[2])
    return msg


def transform_msg(pose, frame_id: str = "odom", child_frame_id: str = "base_link", stamp=None):
    """geometry_msgs/TransformStamped placing ``child_frame_id`` at the planar
    pose (x, y, yaw) in ``frame_id``: the message tf2 reads from ``/tf``."""
    from geometry_msgs.msg import TransformStamped

    msg = TransformStamped()
    msg.header.frame_id, msg.child_frame_id = frame_id, child_frame_id
    if stamp is not None:
        msg.header.stamp = stamp
    msg.transform.translation.x, msg.transform.translation.y = float(pose[0]), float(pose[1])
    r = msg.transform.rotation
    r.x, r.y, r.z, r.w = yaw_to_quaternion(float(pose[2]))
    return msg


def tf_message_type():
    """The tf2_msgs/TFMessage class, or None where tf2_msgs is not installed.

    PyPI has no tf2_msgs wheel; ``pip install ./ros_interfaces/tf2_msgs`` (in
    this repository) builds one against the pinned ROS 2 wheels.
    """
    try:
        from tf2_msgs.msg import TFMessage
    except ImportError:
        return None
    return TFMessage


def twist_msg(vx: float, vy: float, omega: float):
    from geometry_msgs.msg import Twist

    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = float(vx), float(vy), float(omega)
    return msg


def twist_from_msg(msg) -> Tuple[float, float, float]:
    values = (msg.linear.x, msg.linear.y, msg.angular.z)
    if not all(math.isfinite(v) for v in values):
        raise ParameterError(f"non-finite velocity command {values}")
    return values


def time_msg(t: float):
    """builtin_interfaces/Time of ``t`` seconds."""
    from builtin_interfaces.msg import Time

    ns = int(round(t * 1e9))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def stamp_seconds(stamp) -> Optional[float]:
    return stamp.sec + 1e-9 * stamp.nanosec if stamp is not None else None
