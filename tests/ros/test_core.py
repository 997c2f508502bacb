"""The ROS nodes' decisions, without ROS: planning on request, driving on
odometry, and every bad input the nodes must survive."""

import math

import numpy as np
import pytest

from navlab.control import GotoWaypoint, PotentialField
from navlab.grid import OccupancyGrid, line_of_sight
from navlab.ros.core import STOP, Drive, GoalPlanner


class Logbook(list):
    def __call__(self, level, text):
        self.append((level, text))

    def levels(self):
        return [level for level, _ in self]


def room():
    """4 × 3 m at 0.1 m with a wall x ∈ [2.0, 2.1) from y = 0 to 2.0 (a gap above)."""
    blocked = np.zeros((30, 40), bool)
    blocked[0:20, 20] = True
    return OccupancyGrid(blocked, 0.1, (0.0, 0.0, 0.0))


def test_goal_before_map_and_pose_is_kept_and_planned_when_both_arrive():
    log = Logbook()
    planner = GoalPlanner(log, inflation_radius=0.2)
    assert planner.set_goal((3.5, 0.5)) is None
    assert "kept until a map" in log[-1][1]
    assert planner.set_map(room()) is None  # still no pose
    path = planner.set_pose((0.5, 0.5, 0.0))
    assert path is not None and "planning the kept goal" in " ".join(t for _, t in log)
    assert tuple(path[0]) == (0.5, 0.5) and tuple(path[-1]) == (3.5, 0.5)
    # it goes round the wall through the gap, and each leg keeps 0.2 m from it
    assert path[:, 1].max() > 2.0
    inflated = room().inflate(0.2)
    cells = room().world_to_cell(path)
    assert all(line_of_sight(inflated, a, b) for a, b in zip(cells[:-1], cells[1:]))
    assert planner.pending is None and planner.set_pose((0.6, 0.5, 0.0)) is None  # planned once


def test_goal_without_pose_waits_for_odometry():
    log = Logbook()
    planner = GoalPlanner(log)
    planner.set_map(room())
    assert planner.set_pose((math.nan, 0.5, 0.0)) is None and log[-1][0] == "error" and planner.pose is None
    assert planner.set_goal((3.5, 0.5)) is None and "/odom" in log[-1][1]
    assert planner.set_pose((0.5, 0.5, 0.0)) is not None


@pytest.mark.parametrize("goal, why", [
    ((9.0, 1.0), "outside the map"),
    ((-0.01, 1.0), "outside the map"),
    ((2.05, 1.0), "in an obstacle"),
    ((2.25, 1.0), "closer to an obstacle than the inflation radius 0.2"),
    ((math.nan, 1.0), "not a finite position"),
])
def test_bad_goals_give_an_error_and_no_path(goal, why):
    log = Logbook()
    planner = GoalPlanner(log, inflation_radius=0.2)
    planner.set_map(room())
    planner.set_pose((0.5, 0.5, 0.0))
    assert planner.set_goal(goal) is None
    assert log[-1][0] == "error" and why in log[-1][1]
    assert planner.pending is None


def test_unreachable_goal_and_unknown_space():
    wall = np.zeros((30, 40), bool)
    wall[20:30, 20] = True  # close the gap (grids are immutable: a new one)
    grid = room().with_blocked(room().blocked | wall)
    log = Logbook()
    planner = GoalPlanner(log, inflation_radius=0.0)
    planner.set_map(grid)
    planner.set_pose((0.5, 0.5, 0.0))
    assert planner.set_goal((3.5, 0.5)) is None and "FAILED" in log[-1][1]
    unknown = np.zeros_like(grid.blocked)
    unknown[5, 30] = True
    planner.set_map(OccupancyGrid(room().blocked, 0.1, (0.0, 0.0, 0.0), unknown))
    assert planner.set_goal((3.05, 0.55)) is None and "unknown space" in log[-1][1]


def test_start_in_an_obstacle_is_an_error():
    log = Logbook()
    planner = GoalPlanner(log, inflation_radius=0.2)
    planner.set_map(room())
    planner.set_pose((2.05, 0.5, 0.0))
    assert planner.set_goal((3.5, 0.5)) is None and "the start" in log[-1][1] and log[-1][0] == "error"


def test_bad_planner_settings_are_refused():
    with pytest.raises(ValueError, match="connectivity"):
        GoalPlanner(Logbook(), connectivity=6)
    with pytest.raises(ValueError, match="inflation_radius"):
        GoalPlanner(Logbook(), inflation_radius=-1.0)
    with pytest.raises(Exception, match="unknown planner .astra.*Did you mean .astar."):
        GoalPlanner(Logbook(), algorithm="astra")


def clearance(grid, path):
    """Least distance from the path's segments to the grid's blocked squares
    (shapely, not navlab's checker)."""
    from shapely.geometry import LineString, box
    from shapely.ops import unary_union

    ys, xs = np.nonzero(grid.blocked)
    r = grid.resolution
    walls = unary_union([box(x * r, y * r, (x + 1) * r, (y + 1) * r) for x, y in zip(xs, ys)])
    return LineString(path).distance(walls)


@pytest.mark.parametrize("algorithm, sampler", [("rrt_star", "uniform"), ("rrt_star", "integration"),
                                                ("informed_rrt_star", "gaussian"), ("rrt", "goal_bias")])
def test_tree_planners_plan_round_the_wall_and_report_their_tree(algorithm, sampler):
    log, trees = Logbook(), []
    planner = GoalPlanner(log, algorithm, sampler=sampler, seed=5, inflation_radius=0.2, max_iter=3000,
                          on_tree=lambda nodes, parent: trees.append((nodes, parent)))
    planner.set_map(room())
    planner.set_pose((0.5, 0.5, 0.0))
    path = planner.set_goal((3.5, 0.5))
    assert path is not None, log
    assert tuple(path[0]) == (0.5, 0.5) and tuple(path[-1]) == (3.5, 0.5)
    assert path[:, 1].max() > 2.0 + 0.2  # through the gap above the wall
    assert clearance(room(), path) >= 0.2 - 1e-9
    (nodes, parent), = trees
    assert parent[0] == -1 and np.all((parent[1:] >= 0) & (parent[1:] < len(nodes)))
    assert tuple(nodes[0]) == (0.5, 0.5)
    assert all(np.any(np.all(nodes == p, axis=1)) for p in path[:-1])  # the path runs along the tree
    again = GoalPlanner(Logbook(), algorithm, sampler=sampler, seed=5, inflation_radius=0.2, max_iter=3000)
    again.set_map(room())
    again.set_pose((0.5, 0.5, 0.0))
    assert np.array_equal(again.set_goal((3.5, 0.5)), path)  # same seed, same path, bit for bit


def test_a_tree_planner_that_fails_still_reports_its_tree():
    log, trees = Logbook(), []
    blocked = np.zeros((30, 40), bool)
    blocked[:, 20] = True  # a wall from bottom to top: no way through
    planner = GoalPlanner(log, "rrt", seed=1, inflation_radius=0.0, max_iter=200,
                          on_tree=lambda nodes, parent: trees.append((nodes, parent)))
    planner.set_map(OccupancyGrid(blocked, 0.1, (0.0, 0.0, 0.0)))
    planner.set_pose((0.5, 0.5, 0.0))
    assert planner.set_goal((3.5, 0.5)) is None
    assert log[-1][0] == "error" and "(rrt)" in log[-1][1]
    (nodes, _), = trees
    assert len(nodes) > 1 and nodes[:, 0].max() < 2.0  # it grew, on its own side of the wall


def test_every_argument_of_navlab_plan_is_refused_as_a_planner_setting():
    """(review, session 21: 'source' was missing from the node's list, and plan() got it twice)"""
    import inspect

    from navlab import planning
    from navlab.ros.core import _NOT_SETTINGS

    own = [name for name, p in inspect.signature(planning.plan).parameters.items() if p.kind != p.VAR_KEYWORD]
    assert sorted(_NOT_SETTINGS) == sorted(own)
    with pytest.raises(ValueError, match="parameter 'source' is not a planner setting: the node plans on /map"):
        GoalPlanner(Logbook(), algorithm="astar", source="clutter")


@pytest.mark.parametrize("settings, message", [
    (dict(algorithm="rrt_star", sampler="integraton"), "Did you mean 'integration'"),
    (dict(algorithm="rrt_star", max_itr=5), "Did you mean 'max_iter'"),
    (dict(algorithm="astar", heuristc="octile"), "Did you mean 'heuristic'"),
    (dict(algorithm="rrt_star", heuristic="octile"), "unknown parameter 'heuristic'"),
    (dict(algorithm="astar", sampler="gaussian"), "is a grid search"),
    (dict(algorithm="rrt_str"), "Did you mean 'rrt_star'"),
    # values of the wrong kind (ROS parameters are loosely typed) are refused at start-up too
    (dict(algorithm="rrt_star", max_iter="abc"), "max_iter"),
    (dict(algorithm="rrt_star", max_time=-1.0), "max_time"),
    (dict(algorithm="rrt_star", seed="x"), "seed must be a non-negative whole number"),
    (dict(algorithm="rrt_star", sampler="integration", weights=5), "weights"),
    # names navlab.plan takes itself (attack, session 21: "plan() got multiple values for keyword argument")
    (dict(algorithm="astar", planner="rrt"), "parameter 'planner' is not a planner setting: the node's parameter is 'algorithm'"),
    (dict(algorithm="rrt_star", robot_radius=0.2), "parameter 'robot_radius' is not a planner setting: the "
                                                   "node's parameter is 'inflation_radius'"),
    (dict(algorithm="rrt_star", goal=[1, 1]), "parameter 'goal' is not a planner setting: goals come on /goal_pose"),
])
def test_unknown_names_and_bad_values_are_refused_at_start_up(settings, message):
    with pytest.raises(ValueError, match=message):
        GoalPlanner(Logbook(), **settings)


def test_drive_follows_then_stops_once_at_the_goal():
    log = Logbook()
    drive = Drive(GotoWaypoint(), log, odom_timeout=0.5)
    assert drive.on_odom(0.0, (0.0, 0.0, 0.0), now=0.0) is None  # idle: no command
    drive.set_target((1.0, 0.0), np.array([[0.0, 0.0], [1.0, 0.0]]))
    vx, vy, omega = drive.on_odom(0.1, (0.0, 0.0, 0.0), now=0.1)
    assert vx > 0 and vy == 0 and omega == pytest.approx(0.0)
    assert drive.on_odom(5.0, (0.99, 0.0, 0.0), now=5.0) == STOP
    assert "goal reached" in log[-1][1]
    assert drive.on_odom(5.1, (0.99, 0.0, 0.0), now=5.1) is None and drive.watchdog(99.0) is None


def test_drive_stops_the_robot_when_odometry_is_lost_and_resumes():
    log = Logbook()
    drive = Drive(GotoWaypoint(), log, odom_timeout=0.5)
    drive.set_target((5.0, 0.0), np.array([[0.0, 0.0], [5.0, 0.0]]))
    assert drive.on_odom(0.0, (0.0, 0.0, 0.0), now=10.0)[0] > 0
    assert drive.watchdog(10.4) is None
    assert drive.watchdog(10.6) == STOP and log[-1][0] == "warn" and "no odometry" in log[-1][1]
    assert drive.watchdog(10.8) == STOP and log.levels().count("warn") == 1  # repeated stop, one warning
    assert drive.on_odom(0.1, (0.0, 0.0, 0.0), now=11.0)[0] > 0 and "back" in log[-1][1]


def test_empty_path_stops_a_moving_robot_and_hold_stands_still():
    log = Logbook()
    drive = Drive(PotentialField(), log)
    assert drive.set_target(None, np.zeros((0, 2))) is None  # idle already: nothing to stop
    drive.set_target((3.0, 0.0))
    assert drive.hold(now=1.0) == STOP and drive.active
    assert drive.set_target(None, np.zeros((0, 2))) == STOP and not drive.active
    assert "empty path" in log[-1][1]


def test_drive_reports_a_stall():
    log = Logbook()
    drive = Drive(PotentialField(stall_window=1.0), log)
    drive.set_target((3.0, 0.0))
    for i in range(40):
        out = drive.on_odom(0.1 * i, (0.0, 0.0, 0.0), now=0.1 * i)
    assert out is None and not drive.active and any("no progress" in t for _, t in log)


def test_bad_drive_settings():
    with pytest.raises(ValueError, match="odom_timeout"):
        Drive(GotoWaypoint(), Logbook(), odom_timeout=0.0)


@pytest.mark.parametrize("value", ["astar", "/tmp/a map.yaml", "{goal: 0.2}", "1.5", "true", "it's", 'say "hi"',
                                   {"goal": 0.1, "uniform": 0.9}, 3, 0.5, True])
def test_node_parameters_reach_ros_as_the_value_given(value):
    """``-p name:=VALUE`` is read as YAML: strings stay strings (a path, a
    number-like text, YAML mapping text), a mapping arrives as its YAML text."""
    import yaml

    from navlab.ros.launch import ros_value

    read = yaml.safe_load(ros_value(value))
    if isinstance(value, dict):
        assert isinstance(read, str) and yaml.safe_load(read) == value
    else:
        assert read == value and type(read) is type(value)


def test_a_pose_planner_keeps_the_goal_heading_and_the_odometry_heading():
    """hybrid_astar (and trees with motion=reeds_shepp) plan between poses: the path
    starts at the odometry's pose and ends at the goal's, headings included."""
    log = Logbook()
    empty = OccupancyGrid(np.zeros((40, 60), bool), 0.1, (0.0, 0.0, 0.0))
    for algorithm, extra in (("hybrid_astar", {}), ("rrt_star", {"motion": "reeds_shepp", "max_iter": 3000})):
        planner = GoalPlanner(log, algorithm, inflation_radius=0.2, turning_radius=0.5, **extra)
        planner.set_map(empty)
        planner.set_pose((1.0, 2.0, 0.0))
        path = planner.set_goal((4.0, 2.0, math.pi))
        assert path is not None and path.shape[1] == 3, log
        assert np.allclose(path[0], (1.0, 2.0, 0.0)) and np.allclose(path[-1][:2], (4.0, 2.0))
        assert abs(math.remainder(path[-1][2] - math.pi, 2 * math.pi)) < 1e-9
        assert "rad)" in log[-1][1]  # the log names the poses with their headings
    # a point planner drops the heading, as before
    planner = GoalPlanner(log, "astar", inflation_radius=0.2)
    planner.set_map(empty)
    planner.set_pose((1.0, 2.0, 0.0))
    assert planner.set_goal((4.0, 2.0, math.pi)).shape[1] == 2
    with pytest.raises(ValueError, match="sampler 'gaussian' is for the tree planners"):
        GoalPlanner(log, "hybrid_astar", sampler="gaussian")
    with pytest.raises(ValueError, match="turning_radius"):
        GoalPlanner(log, "hybrid_astar", turning_radius=-1.0)


@pytest.mark.parametrize("value", [1, [1], "yes"])
def test_a_tree_planner_publishing_its_tree_checks_keep_tree(value):
    """keep_tree:=1 and [1] started the node: it set keep_tree true over whatever was given (attack, session 25)."""
    with pytest.raises(ValueError, match="keep_tree must be true or false"):
        GoalPlanner(Logbook(), algorithm="rrt", on_tree=lambda *_: None, keep_tree=value)


def test_keep_tree_false_with_the_tree_published_is_refused_and_without_it_taken():
    with pytest.raises(ValueError, match="publish_tree:=false"):
        GoalPlanner(Logbook(), algorithm="rrt", on_tree=lambda *_: None, keep_tree=False)
    assert GoalPlanner(Logbook(), algorithm="rrt", keep_tree=False).query["params"]["keep_tree"] is False
    assert GoalPlanner(Logbook(), algorithm="rrt", on_tree=lambda *_: None, keep_tree=True).query["params"]["keep_tree"]
