"""Planning between poses through navlab.plan and `navlab plan` (issue 21):
the heading scenes, checked with independent geometry (shapely at 1 mm, the
curvature bound, the Reeds–Shepp lower bound), and bad input."""

import json
import math
import re

import numpy as np
import pytest
import shapely
from click.testing import CliRunner

import navlab
from helpers import true_clearance
from pose_helpers import assert_clear_of_the_world, assert_curvature, retrace
from navlab.cli import main
from navlab.result import Status
from navlab.sampling import dubins, reeds_shepp
from navlab.world import World, world_from_dict

HEADING_SCENES = ["narrow_aisle", "parking", "trap_car"]


@pytest.mark.parametrize("scene", HEADING_SCENES)
def test_hybrid_astar_solves_each_heading_scene_clear_of_its_exact_shapes(scene):
    world = navlab.load_world(scene)
    r = navlab.plan(scene, planner="hybrid_astar")
    assert r.status is Status.EXACT, r.reason
    radius = world.meta["turning_radius"]
    assert r.params["turning_radius"] == radius and r.params["footprint"] == [list(p) for p in world.footprint.points]
    start, goal = (*world.start, world.start_heading), (*world.goal, world.goal_heading)
    np.testing.assert_allclose(r.path[0], start, atol=1e-12)
    path, poses = retrace(r)
    assert np.allclose(path.end[:2], goal[:2], atol=1e-9)
    assert abs((path.end[2] - goal[2] + math.pi) % (2 * math.pi) - math.pi) < 1e-9
    assert_clear_of_the_world(world, poses)
    assert_curvature(poses, radius)
    assert r.cost == pytest.approx(path.length, rel=1e-12)
    assert r.cost >= reeds_shepp.distance(start, goal, radius) - 1e-9
    assert r.path.shape[1] == 3 and len(r.direction) == len(r.path)


def test_parking_needs_reverse_and_dubins_says_so():
    backed = navlab.plan("parking", planner="hybrid_astar", motion="reeds_shepp")
    assert backed.status is Status.EXACT and backed.stats["cusps"] >= 1 and (backed.direction == -1).any()
    forward = navlab.plan("parking", planner="hybrid_astar", motion="dubins")
    assert forward.status is Status.FAILED and "reverse" in forward.reason


def test_a_search_cut_short_says_to_raise_its_budget_not_to_reverse():
    # trap_car's goal is reachable driving forward (23.08 m with 30 000 iterations): running out of budget
    # is not evidence that only reversing reaches it
    short = navlab.plan("trap_car", planner="hybrid_astar", motion="dubins", max_expansions=100)
    assert short.status is Status.FAILED and "raise max_expansions" in short.reason and "reverse" not in short.reason
    assert navlab.plan("trap_car", planner="hybrid_astar", motion="dubins").status is Status.EXACT
    tree = navlab.plan("trap_car", planner="rrt_star", motion="dubins", max_iter=200)
    assert tree.status is Status.FAILED and "more iterations or time may reach it" in tree.reason


def test_headings_default_to_the_direction_from_start_to_goal():
    r = navlab.plan("trap", planner="hybrid_astar", start=(2.0, 2.0), goal=(5.0, 5.0), turning_radius=0.5)
    assert r.status is Status.EXACT, r.reason
    assert r.params["start"][2] == pytest.approx(math.pi / 4) and r.params["goal"][2] == pytest.approx(math.pi / 4)
    # a disc of the world's robot radius when neither the query nor the world gives a footprint
    assert r.params["footprint"] == 0.15
    _, poses = retrace(r)
    clearance = min(true_clearance(navlab.load_world("trap"), shapely.LineString(poses[i:i + 400, :2]))
                    for i in range(0, len(poses) - 1, 399))
    assert clearance > 0.15


def test_the_scenes_own_point_keeps_its_heading_and_a_derived_heading_is_named():
    scene = navlab.plan("parking", planner="hybrid_astar")
    again = navlab.plan("parking", planner="hybrid_astar", start=(3.0, 9.0), goal=(16.4, 2.0))  # the scene's points
    assert again.status is Status.EXACT and again.cost == scene.cost and again.params["goal"][2] == math.pi / 2
    moved = navlab.plan("parking", planner="hybrid_astar", goal=(16.4, 2.5))  # another point: start to goal
    assert moved.status is Status.INVALID_GOAL
    assert moved.params["goal"][2] == pytest.approx(math.atan2(2.5 - 9.0, 16.4 - 3.0))
    assert "heading points from start to goal; give the goal as X Y THETA" in moved.reason
    given = navlab.plan("trap_car", planner="hybrid_astar", goal=(0.2, 6.0, 0.0))  # a pose: no such note
    assert given.status is Status.INVALID_GOAL and "X Y THETA" not in given.reason


def test_an_open_floor_costs_the_exact_curve_distance():
    """No obstacle in reach: Hybrid A*'s analytic expansion is the exact shortest curve."""
    world = World(name="open", bounds=navlab.load_world("trap").bounds, start=(4.0, 6.0, 0.0), goal=(6.0, 6.5, 2.5))
    for motion, solver in (("reeds_shepp", reeds_shepp), ("dubins", dubins)):
        r = navlab.plan(world, planner="hybrid_astar", motion=motion, turning_radius=1.0, smooth=False)
        assert r.cost == pytest.approx(solver.distance((4.0, 6.0, 0.0), (6.0, 6.5, 2.5), 1.0), rel=1e-9)


def test_every_setting_of_plan_hybrid_passes_through_navlab_plan():
    import inspect

    from navlab.grid.hybrid_astar import plan_hybrid
    from navlab.pose_queries import HYBRID_PARAMS

    # the map, the poses and the robot radius come from the world; every other setting is the user's
    own = set(inspect.signature(plan_hybrid).parameters) - {"grid", "start", "goal", "robot_radius"}
    assert own <= set(HYBRID_PARAMS), own - set(HYBRID_PARAMS)
    # Smac's analytic-expansion schedule on a scene: a certified path (its own tests check the schedule)
    r = navlab.plan("narrow_aisle", planner="hybrid_astar", analytic_expansion_ratio=3.5)
    assert r.success


def test_a_start_pose_whose_footprint_touches_an_obstacle_names_it():
    r = navlab.plan("trap_car", planner="hybrid_astar", start=(7.2, 6.0, 0.0))
    assert r.status is Status.INVALID_START and "obstacle 2 (rectangle)" in r.reason
    r = navlab.plan("trap_car", planner="hybrid_astar", goal=(0.2, 6.0, 0.0))
    assert r.status is Status.INVALID_GOAL and "bounds" in r.reason
    # a pose never inside does not "leave" them, and the bounds are named (review, session 31)
    b = navlab.load_world("trap_car").bounds
    assert f"crosses the world's bounds x=[{b.xmin:g}, {b.xmax:g}] y=[{b.ymin:g}, {b.ymax:g}]" in r.reason


@pytest.mark.parametrize("kwargs, field", [
    ({"turning_radius": 0}, "turning_radius"), ({"turning_radius": -1}, "turning_radius"),
    ({"turning_radius": math.inf}, "turning_radius"), ({"motion": "holonomic"}, "motion"),
    ({"turning_radius": 1e6}, "turning_radius 1e.06 m: one heading step"),
    ({"turning_radius": 1e-6}, "turning_radius 1e-06 m is too small"),
    ({"motion": "dubin"}, "Did you mean 'dubins'"), ({"start": (1, 1, math.nan)}, "start theta"),
    ({"footprint": [[0, 0], [1, 1]]}, "footprint"), ({"expand_dis": 1}, "unknown parameter 'expand_dis'"),
    ({"goal_tolerance": 0.5}, "goal_tolerance"),
])
def test_bad_pose_settings_are_named(kwargs, field):
    with pytest.raises(ValueError, match=field):
        navlab.plan("parking", planner="hybrid_astar", **kwargs)


def test_a_point_robot_planner_asked_for_car_motion_names_the_planners_that_can():
    with pytest.raises(ValueError, match="hybrid_astar"):
        navlab.plan("trap", planner="astar", motion="reeds_shepp")
    assert navlab.plan("trap", planner="rrt", motion="holonomic", max_iter=200).params["planner"] == "rrt"


def test_world_files_carry_poses_and_a_footprint():
    world = navlab.load_world("parking")
    again = world_from_dict(world.to_dict())
    assert again.start_heading == world.start_heading and again.goal_heading == pytest.approx(math.pi / 2)
    assert again.footprint == world.footprint
    moved = world.with_query(start=(3.0, 8.5))  # a new point drops the old heading
    assert moved.start_heading is None and moved.goal_heading == world.goal_heading
    same = world.with_query(start=(3, 9))  # the same point keeps it
    assert same.start_heading == world.start_heading and same.start == world.start


def test_the_command_line_takes_a_pose(tmp_path):
    out = CliRunner().invoke(main, ["plan", "narrow_aisle", "--planner", "hybrid_astar", "--start", "1.2", "1.55",
                                    "0.1", "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert data["params"]["start"] == [1.2, 1.55, 0.1] and len(data["path"][0]) == 3
    picture = tmp_path / "p.png"
    out = CliRunner().invoke(main, ["plan", "parking", "--planner", "hybrid_astar", "--plot", str(picture)])
    assert out.exit_code == 0 and re.search(r"\b1 cusp,", out.output) and picture.stat().st_size > 0  # parking: one
    # a point and a pose both parse; anything else is one line naming the flag
    assert CliRunner().invoke(main, ["plan", "trap", "--planner", "astar", "--start", "6", "6"]).exit_code == 0
    bad = CliRunner().invoke(main, ["plan", "trap", "--start", "6", "--goal", "1", "2"])
    assert bad.exit_code == 2 and "'--start'" in bad.output and "Traceback" not in bad.output
    bad = CliRunner().invoke(main, ["plan", "trap", "--planner", "hybrid_astar", "--param", "motion=sideways"])
    assert bad.exit_code == 2 and "motion must be one of dubins, reeds_shepp, got 'sideways'" in bad.output
    # a tree planner takes all three
    bad = CliRunner().invoke(main, ["plan", "trap", "--planner", "rrt", "--param", "motion=sideways"])
    assert bad.exit_code == 2 and "motion must be one of holonomic, dubins, reeds_shepp, got 'sideways'" in bad.output


def test_the_summary_counts_in_words_and_a_failure_has_no_cusps():
    res = CliRunner().invoke(main, ["plan", "parking", "--planner", "hybrid_astar", "--param", "max_expansions=1"])
    assert res.exit_code == 1 and ", 1 expansion, planning" in res.output and "cusp" not in res.output
    res = CliRunner().invoke(main, ["plan", "parking", "--planner", "hybrid_astar"])
    assert res.exit_code == 0 and re.search(r"\d+ expansions, 1 cusp, planning", res.output)
    assert "heuristic weight" not in res.output  # (said only when weighted: newcomer, session 24)
    res = CliRunner().invoke(main, ["plan", "parking", "--planner", "hybrid_astar", "--param", "weight=5"])
    assert res.exit_code == 0 and "turning radius 4.5 m, heuristic weight 5, 48 expansions" in res.output


def test_a_robot_radius_a_footprint_scene_would_drop_is_refused():
    """narrow_aisle's robot has a footprint, which a pose planner uses: a robot radius given with it was
    dropped without a word (the path was the footprint's); now one line says how to plan for a disc."""
    for call in (lambda: navlab.plan("narrow_aisle", planner="hybrid_astar", robot_radius=0.3),
                 lambda: navlab.plan("narrow_aisle", planner="rrt_star", motion="reeds_shepp", max_iter=10,
                                     robot_radius=0.3)):
        with pytest.raises(ValueError, match="robot_radius: narrow_aisle's robot has its own footprint.*footprint=0.3"):
            call()
    bad = CliRunner().invoke(main, ["plan", "narrow_aisle", "--planner", "hybrid_astar", "--robot-radius", "0.3"])
    assert bad.exit_code == 2 and "give footprint=0.3 instead" in bad.output
    with pytest.raises(ValueError, match="robot_radius: give footprint or robot_radius, not both"):
        navlab.plan("trap", planner="hybrid_astar", robot_radius=0.5, footprint=0.3)  # the radius was dropped
    with pytest.raises(ValueError, match="footprint.*leave robot_radius out"):  # footprint=0 is no disc
        navlab.plan("narrow_aisle", planner="hybrid_astar", robot_radius=0)
    disc = navlab.plan("narrow_aisle", planner="hybrid_astar", footprint=0.3)  # the way to a disc robot
    assert disc.success
    point = navlab.plan("narrow_aisle", planner="astar", robot_radius=0.1)  # a point planner takes the radius
    assert point.success and point.params["robot_radius"] == 0.1


def test_the_command_says_when_a_path_ends_near_the_goal_pose_not_at_it(tmp_path):
    """Without the analytic expansion the path ends in the goal's cell within k - 1 heading bins, and the
    output said only EXACT (newcomer check, session 16): it says how far from the goal pose it ends."""
    world = tmp_path / "e.yaml"
    world.write_text("bounds: {x: [0, 8], y: [0, 6]}\nstart: [1, 1, 0]\ngoal: [5.05, 3.05, 0.0873]\n")
    args = ["plan", str(world), "--planner", "hybrid_astar", "--param", "turning_radius=0.5"]
    near = CliRunner().invoke(main, args + ["--param", "analytic_expansion=false"])
    assert near.exit_code == 0 and re.search(r"\n  ends 0\.0\d\d m and \d+\.\d° from the goal pose", near.output)
    at = CliRunner().invoke(main, args)
    assert at.exit_code == 0 and "from the goal pose" not in at.output
