"""RRT, RRT* and Informed RRT* between poses (Dubins / Reeds–Shepp steering),
checked with independent geometry: the exact curve re-traced at 1 mm, its
footprint against the world's shapes with shapely, the curvature bound, the
exact curve distance as a lower bound; seeds and success rates."""

import math

import numpy as np
import pytest

import navlab
from navlab.result import Status
from navlab.sampling import dubins, reeds_shepp
from pose_helpers import assert_clear_of_the_world, assert_curvature, retrace

SAMPLERS = [("uniform", {}), ("uniform", {"goal_sample_rate": 0.1}), ("gaussian", {}), ("boundary", {}),
            ("integration", {})]


@pytest.mark.parametrize("planner", ["rrt", "rrt_star", "informed_rrt_star"])
@pytest.mark.parametrize("motion", ["reeds_shepp", "dubins"])
def test_every_path_is_clear_curvature_bounded_and_exact(planner, motion):
    world = navlab.load_world("trap_car")
    found = 0
    for seed in range(3):
        r = navlab.plan(world, planner=planner, motion=motion, max_iter=3000, seed=seed)
        assert r.status in (Status.EXACT, Status.FAILED), r.reason
        if not r.success:
            assert "not reached" in r.reason
            continue
        found += 1
        start, goal = (*world.start, world.start_heading), (*world.goal, world.goal_heading)
        path, poses = retrace(r)
        np.testing.assert_allclose(path.end, goal, atol=1e-9)
        assert_clear_of_the_world(world, poses)
        assert_curvature(poses, world.meta["turning_radius"])
        assert r.cost == pytest.approx(path.length, rel=1e-12)
        solver = reeds_shepp if motion == "reeds_shepp" else dubins
        assert r.cost >= solver.distance(start, goal, world.meta["turning_radius"]) - 1e-9
        if motion == "dubins":
            assert path.cusps == 0 and (r.direction == 1).all()
    if motion == "reeds_shepp":
        assert found >= 2


@pytest.mark.parametrize("sampler, extra", SAMPLERS)
def test_each_sampler_draws_the_positions(sampler, extra):
    r = navlab.plan("trap_car", planner="rrt_star", sampler=sampler, motion="reeds_shepp", max_iter=2000, seed=4,
                    **extra)
    assert r.status in (Status.EXACT, Status.FAILED)
    assert r.params["sampler"] == sampler and r.stats["iterations"] == 2000
    if extra:
        assert r.params["goal_sample_rate"] == 0.1


def test_the_same_seed_gives_the_same_tree_bit_for_bit():
    a, b, c = (navlab.plan("trap_car", planner="rrt_star", motion="reeds_shepp", max_iter=1500, seed=s, keep_tree=True)
               for s in (7, 7, 8))
    assert a.cost == b.cost and np.array_equal(a.path, b.path) and np.array_equal(a.tree.nodes, b.tree.nodes)
    assert not np.array_equal(a.tree.nodes, c.tree.nodes)


def test_rrt_star_improves_with_iterations_and_reaches_trap_car_almost_always():
    costs = []
    for seed in range(8):
        r = navlab.plan("trap_car", planner="rrt_star", motion="reeds_shepp", max_iter=3000, seed=seed)
        trace = r.stats["cost_trace"]
        finite = trace[np.isfinite(trace)]
        assert np.all(np.diff(finite) <= 1e-12)  # the best cost never rises
        if r.success:
            assert finite[-1] == pytest.approx(r.cost, rel=1e-12)
            costs.append(r.cost)
    assert len(costs) >= 7
    assert min(costs) >= 20.0 and np.median(costs) < 1.25 * 20.788  # the scene's best known cost (docs/scenes.md)


def test_an_open_floor_connects_start_to_goal_by_the_exact_curve():
    world = navlab.World(name="open", bounds=navlab.load_world("trap").bounds, start=(4.0, 6.0, 0.0),
                         goal=(6.0, 6.5, 2.5))
    r = navlab.plan(world, planner="rrt_star", motion="reeds_shepp", turning_radius=1.0, max_iter=300,
                    expand_dis=5.0, seed=0)
    assert r.cost == pytest.approx(reeds_shepp.distance((4.0, 6.0, 0.0), (6.0, 6.5, 2.5), 1.0), rel=1e-9)


def test_dubins_says_when_the_goal_needs_reverse():
    r = navlab.plan("parking", planner="rrt", motion="dubins", max_iter=300, seed=0)
    assert r.status is Status.FAILED and "reeds_shepp" in r.reason


@pytest.mark.parametrize("kwargs, field", [
    ({"planner": "growth_ratio_rrt"}, "planners for reeds_shepp motion"),
    ({"expand_dis_": 1}, "unknown parameter 'expand_dis_'"),
    ({"heading_bins": 3}, "heading_bins"), ({"turning_radius": math.nan}, "turning_radius"),
    ({"turning_radius": 1e-6}, "too small"), ({"turning_radius": 1e6}, "longer than the map"),
])
def test_bad_settings_are_named(kwargs, field):
    args = {"planner": "rrt_star", "motion": "reeds_shepp", **kwargs}
    with pytest.raises(ValueError, match=field):
        navlab.plan("trap_car", **args)
