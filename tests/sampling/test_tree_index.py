"""The bucket-grid index against the brute-force scan: same queries, same trees."""

import math

import numpy as np
import pytest

import navlab
from navlab.sampling import PLANNERS, SAMPLERS
from navlab.sampling import bucket_grid as G
from navlab.sampling import tree_kernel as K
from navlab.world import Bounds, Circle, Rectangle, World


def _grid(xy, bounds, expected):
    grid = G.BucketGrid(bounds)
    nxt = np.full(len(xy), -1, dtype=np.int64)
    # Index the first half, add the rest one by one: blocks fill up and the
    # later nodes of crowded cells go to the overflow lists.
    cost = np.arange(len(xy), dtype=float)
    grid.rebuild(xy, cost, nxt, np.full(len(xy), -1, dtype=np.int64), len(xy) // 2, expected)
    for k in range(len(xy) // 2, len(xy)):
        G.insert(k, xy, cost, grid.arrays)
    return grid.arrays


def _brute_nearest(xy, q):
    d2 = (xy[:, 0] - q[0]) ** 2 + (xy[:, 1] - q[1]) ** 2
    j = int(np.argmin(d2))  # the first (lowest index) minimum
    return j, d2[j]


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("expected", [200, 400, 5000])
def test_queries_match_brute_force_with_ties_and_outside_points(seed, expected):
    rng = np.random.default_rng(seed)
    bounds = Bounds(-2.0, 15.0, -2.0, 15.0)
    n = 400
    # Lattice points make exact distance ties and points on cell borders;
    # some nodes and queries lie outside the bounds; some nodes repeat.
    xy = np.vstack((rng.integers(-4, 18, (n // 2, 2)).astype(float),
                    rng.uniform(-3.0, 16.0, (n // 2, 2))))
    xy[::37] = xy[1]
    queries = np.vstack((rng.integers(-6, 20, (150, 2)).astype(float) + 0.5 * rng.integers(0, 2, (150, 2)),
                         rng.uniform(-5.0, 20.0, (150, 2))))
    grid = _grid(xy, bounds, expected)
    assert expected > 200 or np.any(grid[0][:, G.M_HEAD] >= 0)  # some overflow lists are in use
    node_cost = np.arange(n, dtype=float)
    for q in queries:
        j, d2, x, y, c = G.nearest(q[0], q[1], xy, node_cost, grid)
        assert (j, d2) == _brute_nearest(xy, q)
        assert (x, y, c) == (xy[j, 0], xy[j, 1], node_cost[j])
        for r in (0.0, 1.0, math.sqrt(2.0), 3.7, 40.0):
            idx, d2, cost, xs, ys = np.zeros(n, dtype=np.int64), np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
            m = G.near(q[0], q[1], r * r, xy, node_cost, grid, idx, d2, cost, xs, ys)
            d2_all = (xy[:, 0] - q[0]) ** 2 + (xy[:, 1] - q[1]) ** 2
            order = np.argsort(idx[:m])
            found = idx[:m][order]
            assert list(found) == list(np.flatnonzero(d2_all <= r * r))
            np.testing.assert_array_equal(d2[:m][order], d2_all[found])
            np.testing.assert_array_equal(cost[:m][order], found)
            np.testing.assert_array_equal(np.column_stack((xs[:m], ys[:m]))[order], xy[found])


@pytest.mark.parametrize("seed", range(4))
def test_node_within_never_claims_a_node_that_is_not_there(seed):
    rng = np.random.default_rng(seed)
    bounds = Bounds(-2.0, 15.0, -2.0, 15.0)
    # Nodes in two clusters, so that many queries are far from every node.
    n = 3000
    xy = np.vstack((rng.uniform(-2.0, 4.0, (n // 2, 2)), rng.uniform(9.0, 15.0, (n // 2, 2))))
    grid = _grid(xy, bounds, 40 * n)  # cells sized for a bigger tree: coarse cells of about 1 m
    queries = rng.uniform(-5.0, 18.0, (400, 2))
    proved = possible = 0
    for q in queries:
        nearest = np.sqrt(((xy - q) ** 2).sum(axis=1)).min()
        for reach in (0.5, 1.0, 2.0, 4.8, 9.0):
            possible += nearest <= reach
            if G.node_within(q[0], q[1], reach, grid):
                assert nearest <= reach
                proved += 1
    assert proved > 0.5 * possible, (proved, possible)  # it does prove something (not at reaches below a coarse cell)


def _popped(m, val, idx, by_cost, rng):
    heap = rng.permutation(m).astype(np.int64)
    K._heap_build(heap, m, val, idx, by_cost)
    return [int(K._heap_pop(heap, k, val, idx, by_cost)) for k in range(m, 0, -1)]


def test_candidates_come_by_cost_then_index():
    rng = np.random.default_rng(3)
    for m in (0, 1, 2, 5, 24, 25, 200):
        val = rng.integers(0, 6, m).astype(float)  # many exact ties
        idx = rng.permutation(10 * m + 1)[:m].astype(np.int64)
        assert _popped(m, val, idx, True, rng) == list(np.lexsort((idx, val)))
        assert _popped(m, val, idx, False, rng) == list(np.argsort(idx))


def _same_tree(world, planner, sampler, seed, max_iter, **params):
    runs = [navlab.plan(world, planner=planner, sampler=sampler, seed=seed, max_iter=max_iter,
                        keep_tree=True, index=index, **params) for index in ("grid", "scan")]
    a, b = runs
    assert a.status is b.status and a.cost == b.cost
    np.testing.assert_array_equal(a.path, b.path)
    np.testing.assert_array_equal(a.tree["nodes"], b.tree["nodes"])
    np.testing.assert_array_equal(a.tree["parent"], b.tree["parent"])
    np.testing.assert_array_equal(a.stats["cost_trace"], b.stats["cost_trace"])
    for key in ("iterations", "nodes", "collision_checks", "rewires", "first_solution_iteration"):
        assert a.stats[key] == b.stats[key], key
    return a


LATTICE = World("lattice", Bounds(0, 8, 0, 8), (1.0, 1.0), (7.0, 7.0),
                (Rectangle((3.0, 0.0), (4.0, 6.0)), Circle((6.0, 4.0), 1.0)), robot_radius=0.1)


@pytest.mark.parametrize("sampler", SAMPLERS.names())
@pytest.mark.parametrize("planner", PLANNERS.names())
def test_grid_and_scan_grow_the_same_tree(planner, sampler):
    for seed, scene in enumerate(("pythonrobotics", "clutter", "trap", "squarefield", "pythonrobotics")):
        _same_tree(navlab.load_world(scene), planner, sampler, seed, 400)
    # A coarse step on a small world: many equal distances and costs.
    _same_tree(LATTICE, planner, sampler, 11, 300, expand_dis=1.0)


def test_grid_and_scan_grow_the_same_tree_at_20k_nodes():
    r = _same_tree(navlab.load_world("pythonrobotics"), "rrt_star", "uniform", 4, 30000)
    assert r.stats["nodes"] > 19000 and r.stats["rewires"] > 0


@pytest.mark.parametrize("planner", ["rrt", "rrt_star"])
def test_blocked_samples_are_skipped_alike_by_grid_and_scan(planner):
    # A long step: the grid's coarse cells soon prove a node within it, so
    # the grid skips blocked samples before any search; the scan decides by
    # its nearest node. Same tree, same counts.
    world = navlab.load_world("trap")
    r = _same_tree(world, planner, "uniform", 3, 6000, expand_dis=0.5 * world.bounds.diagonal)
    assert r.stats["collision_checks"] > r.stats["edge_checks"]  # point checks were made


def test_a_tree_past_the_index_limit_is_refused_before_allocating():
    tree = K.Tree((0.0, 0.0), Bounds(0, 1, 0, 1), max_nodes=2**40)
    tree.istate[K.S_NODES] = G.MAX_NODES - 10
    with pytest.raises(MemoryError, match="2147483647 nodes"):
        tree.reserve(64, 64)
    assert tree.capacity < 10**4  # nothing was allocated


def test_bad_index_name():
    with pytest.raises(ValueError, match="index"):
        navlab.plan("pythonrobotics", planner="rrt_star", index="kdtree")
