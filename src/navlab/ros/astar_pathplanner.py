"""``astar_pathplanner`` (seed 002): plans on ``/map`` from the pose on
``/odom`` to each ``/goal_pose`` and publishes ``/plan``.

The odometry frame is taken to coincide with the map frame (the simulator
starts its odometry at the robot's true pose in the map).
"""

from __future__ import annotations

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import OccupancyGrid as GridMsg
from nav_msgs.msg import Odometry, Path

from .base import DEFAULT_QOS, MAP_QOS, NavlabNode, Param, node_main
from .convert import grid_from_msg, path_to_msg, pose_from_msg
from .core import GoalPlanner


class AStarPathPlanner(NavlabNode):
    PARAMETERS = (
        Param("algorithm", "astar", "grid search: astar, dijkstra, jps or theta_star"),
        Param("heuristic", "octile", "A* heuristic: octile, euclidean, chebyshev or manhattan"),
        Param("connectivity", 8, "4 or 8 neighbours (diagonals never cut corners)"),
        Param("smooth", True, "shortcut the path along Bresenham lines of sight"),
        Param("inflation_radius", 0.175, "grow obstacles by this much before planning (m): robot radius + margin"),
        Param("allow_unknown", False, "plan through cells of unknown occupancy"),
        Param("frame_id", "map", "frame of the published path"),
    )

    def __init__(self, **kwargs) -> None:
        super().__init__("astar_pathplanner", **kwargs)
        p = self.params
        self.core = GoalPlanner(self.log, p["algorithm"], p["heuristic"], p["connectivity"], p["smooth"],
                                p["inflation_radius"], p["allow_unknown"])
        self.publisher = self.create_publisher(Path, "plan", DEFAULT_QOS)
        self.create_subscription(GridMsg, "map", self.on_map, MAP_QOS)
        self.create_subscription(PoseStamped, "goal_pose", self.on_goal, DEFAULT_QOS)
        self.create_subscription(Odometry, "odom", self.on_odom, DEFAULT_QOS)

    def on_map(self, msg) -> None:
        try:
            grid = grid_from_msg(msg)
        except ValueError as exc:
            self.log("error", f"ignoring a malformed /map: {exc}")
            return
        self.publish(self.core.set_map(grid))

    def on_goal(self, msg) -> None:
        frame = msg.header.frame_id
        if frame and frame != self.params["frame_id"]:
            self.log("warn", f"goal in frame '{frame}' read as '{self.params['frame_id']}' (no tf here)")
        self.publish(self.core.set_goal(pose_from_msg(msg.pose)[:2]))

    def on_odom(self, msg) -> None:
        self.publish(self.core.set_pose(pose_from_msg(msg.pose.pose)))

    def publish(self, path) -> None:
        if path is not None:
            self.publisher.publish(path_to_msg(path, self.params["frame_id"], self.get_clock().now().to_msg()))


main = node_main(AStarPathPlanner)

if __name__ == "__main__":
    main()
