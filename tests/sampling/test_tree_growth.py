"""Tree arrays grow with the tree, not with max_iter; results do not depend on it."""

import tracemalloc

import numpy as np
import pytest

import navlab
from navlab import Status
from navlab.sampling import PLANNERS
from navlab.sampling import tree_kernel as K
from navlab.world import Bounds, Circle, World


def test_a_huge_max_iter_allocates_only_what_the_tree_uses():
    tree = K.Tree((0.0, 0.0), Bounds(0, 10, 0, 10), max_nodes=10**12 + 1)
    assert tree.capacity == K.INITIAL_CAPACITY and len(tree.xy) == K.INITIAL_CAPACITY
    assert len(tree.trace_iter) <= 64
    tree.reserve(3000, 3000)
    assert 3001 <= tree.capacity <= 2 * 3001
    assert all(len(getattr(tree, n)) == tree.capacity for n, _ in K.Tree._NODE_ARRAYS)
    assert len(tree.trace_iter) >= 3000
    small = K.Tree((0.0, 0.0), Bounds(0, 10, 0, 10), max_nodes=11)
    small.reserve(64, 64)
    assert small.capacity == 11  # never beyond max_iter + 1


def test_a_tree_reserved_whole_is_allocated_once_and_written_as_it_grows():
    tree = K.Tree((0.0, 0.0), Bounds(0, 10, 0, 10), max_nodes=5000, reserve_all=True)
    record = tree.record
    assert len(tree.xy) == 5000 and tree.capacity == K.INITIAL_CAPACITY
    tree.reserve(3000, 3000)
    assert tree.record is record and 3001 <= tree.capacity <= 5000
    assert np.all(tree.goal_slot[: tree.capacity] == -1)


@pytest.mark.parametrize("planner", PLANNERS.names())
def test_a_tree_reserved_whole_grows_as_a_doubled_one(planner):
    # Without max_time the planner reserves the whole tree; with one, the arrays double.
    world = navlab.load_world("clutter")
    a = navlab.plan(world, planner=planner, seed=4, max_iter=3000, keep_tree=True)
    b = navlab.plan(world, planner=planner, seed=4, max_iter=3000, max_time=1e6, keep_tree=True)
    assert a.stats["iterations"] == b.stats["iterations"] and a.cost == b.cost
    np.testing.assert_array_equal(a.tree["nodes"], b.tree["nodes"])
    np.testing.assert_array_equal(a.tree["parent"], b.tree["parent"])


@pytest.mark.parametrize("planner", PLANNERS.names())
def test_max_iter_far_above_max_time_returns_with_small_memory(planner):
    world = navlab.load_world("pythonrobotics")
    navlab.plan(world, planner=planner, max_iter=64)  # compile outside the measurement
    tracemalloc.start()
    try:
        r = navlab.plan(world, planner=planner, max_iter=10**12, max_time=0.05)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert r.status in (Status.EXACT, Status.APPROXIMATE, Status.FAILED)
    assert len(r.stats["cost_trace"]) == r.stats["iterations"] < 10**12
    # Arrays sized by max_iter would need terabytes; the tree grown in 0.05 s
    # (and the interpreter's own allocations) fit in far less than 200 MB.
    assert peak < 200e6


def test_results_do_not_depend_on_the_initial_capacity(monkeypatch):
    world = navlab.load_world("clutter")
    ref = {p: navlab.plan(world, planner=p, seed=2, max_iter=1500, keep_tree=True) for p in PLANNERS.names()}
    monkeypatch.setattr(K, "INITIAL_CAPACITY", 2)  # grow at every doubling from 2 nodes
    for p, a in ref.items():
        b = navlab.plan(world, planner=p, seed=2, max_iter=1500, keep_tree=True)
        np.testing.assert_array_equal(a.tree["parent"], b.tree["parent"])
        np.testing.assert_array_equal(a.tree["nodes"], b.tree["nodes"])
        np.testing.assert_array_equal(a.stats["cost_trace"], b.stats["cost_trace"])
        assert a.cost == b.cost


def test_cost_trace_from_change_points():
    tree = K.Tree((0.0, 0.0), Bounds(0, 10, 0, 10), max_nodes=100)
    assert list(tree.cost_trace(3)) == [np.inf] * 3
    for it, c in ((2, 5.0), (2, 4.0), (4, 4.0), (6, 3.0)):
        tree.best_cost[0] = c
        tree.record_cost(it)
    np.testing.assert_array_equal(tree.cost_trace(8), [np.inf, np.inf, 4, 4, 4, 4, 3, 3])
    np.testing.assert_array_equal(tree.cost_trace(5), [np.inf, np.inf, 4, 4, 4])
    assert tree.istate[K.S_TRACE] == 2  # same-iteration and unchanged costs are not stored


def test_cost_trace_when_the_start_is_in_the_goal_region():
    world = World("t", Bounds(0, 10, 0, 10), (1, 1), (1.2, 1), goal_tolerance=0.5)
    r = navlab.plan(world, planner="rrt_star", max_iter=50, seed=0)
    # no path beats cost 0: RRT* answers without iterating (session 30), and its trace has no iteration
    assert r.success and r.cost == 0.0 and r.stats["iterations"] == 0 and len(r.stats["cost_trace"]) == 0


@pytest.mark.parametrize("planner", PLANNERS.names())
def test_stats_keys_are_the_same_whatever_the_status(planner):
    free = World("t", Bounds(0, 10, 0, 10), (0.5, 0.5), (9.0, 9.0), (Circle((3.0, 3.0), 1.0),), robot_radius=0.3)
    walled = World("t", Bounds(0, 10, 0, 10), (0.5, 0.5), (9.0, 9.0), (Circle((9.0, 9.0), 3.0),))
    results = {
        "exact": navlab.plan(free, planner=planner, max_iter=3000, seed=0),
        "approximate": navlab.plan(World("t", Bounds(0, 10, 0, 10), (0.5, 0.5), (9.5, 9.5),
                                         (Circle((9.5, 9.5), 0.0001),)), planner=planner, max_iter=5, seed=0),
        "invalid_start": navlab.plan(World("t", Bounds(0, 10, 0, 10), (3.0, 3.0), (9.0, 9.0),
                                           (Circle((3.0, 3.0), 1.0),)), planner=planner),
        "invalid_goal": navlab.plan(walled, planner=planner),
    }
    assert results["exact"].status is Status.EXACT
    assert results["invalid_start"].status is Status.INVALID_START
    assert results["invalid_goal"].status is Status.INVALID_GOAL
    keys = set(results["exact"].stats)
    assert {"time_s", "iterations", "nodes", "cost_trace", "collision_checks"} <= keys
    for name, r in results.items():
        assert set(r.stats) == keys, name
        assert r.stats["time_s"] >= 0 and len(r.stats["cost_trace"]) == r.stats["iterations"]


@pytest.mark.parametrize("planner", PLANNERS.names())
def test_max_iter_beyond_memory_without_max_time_is_refused_by_name(planner, monkeypatch):
    """Only max_iter bounds the tree then: one that could not fit is refused before planning."""
    import navlab.limits

    monkeypatch.setattr(navlab.limits, "available_memory", lambda: 100 * 2**20)  # a 100 MiB machine
    fits = 100 * 2**20 // K.Tree.bytes_per_node() - 1
    with pytest.raises(ValueError, match=r"max_iter=%d with no max_time .* more than the 100 MiB" % (fits + 1)):
        navlab.plan("pythonrobotics", planner=planner, max_iter=fits + 1)
    r = navlab.plan("pythonrobotics", planner=planner, max_iter=fits + 1, max_time=0.01)
    assert r.stats["iterations"] <= fits + 1
    for bad in (None, 0, 65537, 2.5):
        with pytest.raises(ValueError, match="batch_size"):
            navlab.plan("pythonrobotics", planner=planner, max_iter=10, batch_size=bad)
    with pytest.raises(ValueError, match="max_iter must be a whole number from 1 to 4.61e.18, got a number of 401"):
        navlab.plan("pythonrobotics", planner=planner, max_iter=10**400, max_time=0.01)
