"""Contract tests over every registered planner × sampler, plus focused checks."""

import math

import numpy as np
import pytest
import shapely

import navlab
from navlab import Status
from navlab.sampling import PLANNERS, SAMPLERS
from navlab.world import Bounds, Circle, Rectangle, World
from helpers import true_clearance

PAIRS = [(p, s) for p in PLANNERS.names() for s in SAMPLERS.names()]


def assert_valid_path(world, result):
    path = result.path
    assert path.ndim == 2 and path.shape[1] == 2 and len(path) >= 2
    np.testing.assert_array_equal(path[0], world.start)
    assert np.linalg.norm(path[-1] - np.asarray(world.goal)) <= max(world.goal_tolerance, 1e-12) + 1e-12 \
        or result.params.get("planner") == "growth_ratio_rrt"
    assert world.bounds.contains(path).all()
    # Independent truth: shapely distance from the polyline to every obstacle.
    if world.obstacles:
        assert true_clearance(world, shapely.LineString(path)) >= world.robot_radius - 1e-9
    assert math.isclose(result.cost, float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1))), rel_tol=1e-12)


@pytest.mark.parametrize("planner, sampler", PAIRS)
def test_contract(planner, sampler):
    world = navlab.load_world("squarefield")
    r1 = navlab.plan(world, planner=planner, sampler=sampler, seed=7, max_iter=600)
    r2 = navlab.plan(world, planner=planner, sampler=sampler, seed=7, max_iter=600)
    assert isinstance(r1.status, Status)
    assert r1.status.name in {"EXACT", "APPROXIMATE", "FAILED"}
    np.testing.assert_array_equal(r1.path, r2.path)  # bit for bit
    assert r1.cost == r2.cost and r1.stats["collision_checks"] == r2.stats["collision_checks"]
    for key in ("iterations", "nodes", "collision_checks", "time_s", "first_solution_iteration", "cost_trace"):
        assert key in r1.stats
    assert r1.stats["iterations"] <= 600 and len(r1.stats["cost_trace"]) == r1.stats["iterations"]
    if r1.status is Status.EXACT:
        assert_valid_path(world, r1)
    else:
        assert r1.reason


@pytest.mark.parametrize("planner", PLANNERS.names())
@pytest.mark.parametrize("scene", ["pythonrobotics", "clutter", "squarefield", "trap"])
def test_success_rate_and_valid_paths(planner, scene):
    world = navlab.load_world(scene)
    results = [navlab.plan(world, planner=planner, sampler="goal_bias", seed=s, max_iter=3000) for s in range(10)]
    ok = [r for r in results if r.success]
    assert len(ok) >= 9, [r.status.name for r in results]
    for r in ok:
        assert_valid_path(world, r)


def test_rrt_star_cost_improves_and_bounds_hold():
    world = navlab.load_world("pythonrobotics")
    optimum = 21.9987  # the scene's true optimum (issue 2)
    early, late = [], []
    for seed in range(8):
        r = navlab.plan(world, planner="rrt_star", seed=seed, max_iter=4000)
        trace = r.stats["cost_trace"]
        finite = trace[np.isfinite(trace)]
        assert np.all(np.diff(finite) <= 1e-9)  # best cost never rises
        assert trace[-1] == pytest.approx(r.cost)
        early.append(trace[500] if np.isfinite(trace[500]) else np.inf)
        late.append(r.cost)
        assert r.cost >= optimum - 1e-3
    assert np.median(late) < np.median(early)
    assert np.median(late) < optimum * 1.03


def test_informed_beats_or_matches_plain_rrt_star():
    world = navlab.load_world("pythonrobotics")
    plain = [navlab.plan(world, planner="rrt_star", seed=s, max_iter=2500).cost for s in range(8)]
    informed = [navlab.plan(world, planner="informed_rrt_star", seed=s, max_iter=2500).cost for s in range(8)]
    assert np.median(informed) <= np.median(plain) + 0.05


def test_rrt_stops_at_first_solution():
    r = navlab.plan("squarefield", planner="rrt", seed=1, max_iter=5000)
    assert r.success and r.stats["iterations"] == r.stats["first_solution_iteration"] + 1


def test_growth_ratio_seed003_setup():
    world = navlab.load_world("growth_ratio")
    iters, lengths = [], []
    for seed in range(100):
        r = navlab.plan(world, planner="growth_ratio_rrt", seed=seed, max_iter=5000)
        assert r.success
        assert np.linalg.norm(r.path[-2] - np.asarray(world.goal)) < 0.5  # the node within p_min
        iters.append(r.stats["iterations"])
        lengths.append(r.cost)
    straight = math.dist(world.start, world.goal)
    assert min(lengths) >= straight - 1e-9
    assert np.median(iters) < 5000


def test_growth_ratio_step_is_the_sample_share():
    # With every sample inside the target rectangle the share is 1: each new
    # node lands exactly on its sample.
    from navlab.sampling.tree_kernel import growth_step
    assert growth_step(inside=True, n_in=3, n_out=1, d=2.0, cap=0.0) == pytest.approx(1.5)
    assert growth_step(inside=False, n_in=3, n_out=1, d=2.0, cap=0.0) == pytest.approx(0.5)
    assert growth_step(inside=True, n_in=3, n_out=1, d=2.0, cap=1.0) == pytest.approx(1.0)


@pytest.mark.parametrize("start, goal, status", [
    ((3.0, 3.0), (9.0, 9.0), Status.INVALID_START),   # inside a circle
    ((0.5, 0.5), (3.0, 4.2), Status.INVALID_GOAL),    # within robot radius of the circle
    ((-1.0, 0.5), (9.0, 9.0), Status.INVALID_START),  # outside bounds
    ((0.5, 0.5), (9.0, 10.5), Status.INVALID_GOAL),
])
@pytest.mark.parametrize("planner", PLANNERS.names())
def test_invalid_queries(start, goal, status, planner):
    world = World("t", Bounds(0, 10, 0, 10), start, goal, (Circle((3.0, 3.0), 1.0),), robot_radius=0.3)
    r = navlab.plan(world, planner=planner)
    assert r.status is status and r.reason and len(r.path) == 0 and r.cost == math.inf


def test_unreachable_goal_is_a_status_not_an_exception():
    walls = (Rectangle((4.0, 0.0), (5.0, 10.0)),)
    world = World("t", Bounds(0, 10, 0, 10), (1, 5), (9, 5), walls)
    for planner in PLANNERS.names():
        r = navlab.plan(world, planner=planner, max_iter=300)
        assert r.status is Status.APPROXIMATE and "not reached" in r.reason
        assert r.path[-1][0] <= 4.0


def test_start_equal_goal():
    world = World("t", Bounds(0, 10, 0, 10), (1, 1), (1, 1))
    r = navlab.plan(world, planner="rrt", max_iter=10)
    assert r.success and r.cost == 0.0


@pytest.mark.parametrize("params, field", [
    ({"expand_dis": -1.0}, "expand_dis"),
    ({"max_iter": 0}, "max_iter"),
    ({"connect_circle_dist": 0}, "connect_circle_dist"),
    ({"goal_sample_rate": 1.5}, "goal_sample_rate"),
    ({"expand_distance": 1.0}, "expand_dis"),
])
def test_invalid_planner_parameters(params, field):
    with pytest.raises(ValueError, match=field):
        navlab.plan("pythonrobotics", planner="rrt_star", **params)


def test_unknown_planner_hint():
    with pytest.raises(ValueError, match="Did you mean 'rrt_star'"):
        navlab.plan("pythonrobotics", planner="rrtstar")


def test_goal_sample_rate_composes_with_any_sampler():
    r = navlab.plan("clutter", planner="rrt_star", sampler="gaussian", goal_sample_rate=0.1, max_iter=500)
    assert r.params["goal_sample_rate"] == 0.1


def test_defaults_derive_from_world_extent():
    small = World("s", Bounds(0, 1, 0, 1), (0.1, 0.1), (0.9, 0.9))
    big = World("b", Bounds(0, 100, 0, 100), (1, 1), (99, 99))
    ps = navlab.plan(small, planner="rrt_star", max_iter=50).params
    pb = navlab.plan(big, planner="rrt_star", max_iter=50).params
    assert pb["expand_dis"] == pytest.approx(100 * ps["expand_dis"])
    assert pb["connect_circle_dist"] == pytest.approx(100 * ps["connect_circle_dist"])


def test_keep_tree_returns_consistent_tree():
    r = navlab.plan("clutter", planner="rrt_star", max_iter=800, keep_tree=True)
    nodes, parent = r.tree["nodes"], r.tree["parent"]
    assert len(nodes) == r.stats["nodes"] and parent[0] == -1 and np.all(parent[1:] >= 0)
    assert np.all(parent[1:] < len(nodes))


@pytest.mark.parametrize("name", ["rrt", "rrt_star", "informed_rrt_star"])
def test_a_start_within_the_goal_tolerance_is_answered_at_once(name):
    """RRT* ran its whole budget (5000 iterations) to return the cost-0 path of a start on the goal (newcomer,
    session 30); no path is shorter, so every planner answers without iterating."""
    world = navlab.load_world("trap")
    at_goal = World("at goal", world.bounds, (1.0, 1.0), (1.0, 1.0), world.obstacles)
    result = PLANNERS.get(name)(max_iter=500).plan(at_goal, rng=0)
    assert result.status == Status.EXACT and result.cost == 0.0 and result.stats["iterations"] == 0
