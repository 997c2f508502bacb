"""``pathplanner``: plans on ``/map`` from the pose on ``/odom`` to each
``/goal_pose`` with any registered planner and publishes ``/plan``; a tree
planner's search tree goes to ``/plan_tree`` (visualization_msgs/MarkerArray,
for RViz and Foxglove).

The algorithm is a parameter: the grid searches (``astar``, ``dijkstra``,
``jps``, ``theta_star``; seed 002), the RRT family (``rrt``, ``rrt_star``,
``informed_rrt_star``, ``growth_ratio_rrt``) with any ``sampler``, or a
planner between poses (``hybrid_astar``, or a tree planner with
``-p motion:=reeds_shepp``/``dubins``): it keeps the goal's orientation and
the odometry's heading, and the published poses carry the planned headings
(facing backwards on reverse stretches, as Nav2's Smac planners publish them). Every
other setting of the planner or sampler is a parameter of the same name
(``-p max_iter:=3000 -p goal_sample_rate:=0.1``), routed as ``navlab.plan``
routes them. The odometry frame is taken to coincide with the map frame (the
simulator starts its odometry at the robot's true pose in the map).
"""

from __future__ import annotations

from typing import Any, Dict

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import OccupancyGrid as GridMsg
from nav_msgs.msg import Odometry, Path
from visualization_msgs.msg import MarkerArray

from ..errors import ParameterError
from .base import DEFAULT_QOS, MAP_QOS, PLAN_QOS, NavlabNode, Param, node_main
from .convert import grid_from_msg, path_to_msg, pose_from_msg, tree_to_markers
from .core import GoalPlanner


class PathPlanner(NavlabNode):
    NODE_NAME = "pathplanner"
    PARAMETERS = (
        Param("algorithm", "astar", "any registered planner: astar, dijkstra, jps, theta_star, rrt, rrt_star, "
                                    "informed_rrt_star, growth_ratio_rrt, hybrid_astar (between poses)"),
        Param("sampler", "uniform", "tree planners: uniform, gaussian, boundary, integration or goal_bias"),
        Param("seed", 0, "tree planners: random seed of every plan (same map, pose and goal: same path)"),
        Param("inflation_radius", 0.175, "keep this far from obstacles (m): robot radius + margin"),
        Param("allow_unknown", False, "plan through cells of unknown occupancy"),
        Param("frame_id", "map", "frame of the published path and tree"),
        Param("publish_tree", True, "tree planners: publish the search tree on /plan_tree"),
    )
    def __init__(self, **kwargs) -> None:
        super().__init__(self.NODE_NAME, automatically_declare_parameters_from_overrides=True, **kwargs)
        p = self.params
        self.tree = None
        settings = self.planner_params()
        self.core = GoalPlanner(self.log, p["algorithm"], p["sampler"],
                                p["seed"], p["inflation_radius"], p["allow_unknown"],
                                on_tree=self.keep_tree if p["publish_tree"] else None, **settings)
        self.note_unused_settings(p["algorithm"], settings)
        self.publisher = self.create_publisher(Path, "plan", PLAN_QOS)
        self.tree_publisher = self.create_publisher(MarkerArray, "plan_tree", DEFAULT_QOS)
        self.create_subscription(GridMsg, "map", self.on_map, MAP_QOS)
        self.create_subscription(PoseStamped, "goal_pose", self.on_goal, DEFAULT_QOS)
        self.create_subscription(Odometry, "odom", self.on_odom, DEFAULT_QOS)
        # said once, so a user (and a launcher) can tell a node that is up from one still starting
        self.log("info", f"{p['algorithm']} ready: plans on /map from /odom to each /goal_pose")

    def note_unused_settings(self, algorithm: str, settings: Dict[str, Any]) -> None:
        """A warning for each grid setting the grid algorithm does not use, as the command line notes them
        (jps given a heuristic, astar a weight with heuristic none: the node ran without them silently)."""
        from ..grid.planner import GRID_ALGORITHMS, unused_settings

        if algorithm in GRID_ALGORITHMS:
            for line in unused_settings(algorithm, settings, lambda key, value: f"-p {key}:={value}"):
                self.log("warn", line)

    def planner_params(self) -> Dict[str, Any]:
        """The settings given on the command line for the planner (a mapping such as
        integration's ``weights`` comes as YAML text: see :meth:`mapping`)."""
        return self.passed_settings(lambda name, value: self.mapping(name, value)
                                    if isinstance(value, str) and value.lstrip().startswith("{") else value)

    @staticmethod
    def mapping(name: str, text: str) -> dict:
        """A mapping setting (integration's ``weights``) from its YAML text:
        ROS parameters hold no mappings, so it comes as a string,
        ``-p 'weights:="{goal: 0.1, uniform: 0.9}"'``."""
        import yaml

        from ..yamlio import load_value

        try:
            value = load_value(text)
        except (yaml.YAMLError, ValueError, RecursionError) as exc:
            raise ParameterError(f"parameter {name}: cannot read {text!r} as a YAML mapping ({exc})") from None
        if not isinstance(value, dict):
            raise ParameterError(f"parameter {name}: {text!r} is not a YAML mapping")
        return value

    def keep_tree(self, nodes, parent) -> None:
        self.tree = (nodes, parent)

    def on_map(self, msg) -> None:
        grid = self.read(grid_from_msg, msg, "/map")
        if grid is not None:
            self.publish(self.core.set_map(grid))

    def on_goal(self, msg) -> None:
        frame = msg.header.frame_id
        if frame and frame != self.params["frame_id"]:
            self.log("warn", f"goal in frame '{frame}' read as '{self.params['frame_id']}' (no tf here)")
        self.publish(self.core.set_goal(pose_from_msg(msg.pose)))

    def on_odom(self, msg) -> None:
        self.publish(self.core.set_pose(pose_from_msg(msg.pose.pose)))

    def publish(self, path) -> None:
        """The path, and the tree the plan grew (also when it failed), with one stamp."""
        stamp = self.get_clock().now().to_msg()
        frame = self.params["frame_id"]
        if self.tree is not None:
            self.tree_publisher.publish(tree_to_markers(*self.tree, frame, stamp))
            self.tree = None
        if path is not None:
            self.publisher.publish(path_to_msg(path, frame, stamp))


main = node_main(PathPlanner)

if __name__ == "__main__":
    main()
