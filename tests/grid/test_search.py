"""Grid search against brute-force truth (scipy's Dijkstra on the explicit graph)."""

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra as scipy_dijkstra

from navlab import Status
from navlab.grid import OccupancyGrid, line_of_sight, plan, plan_world
from navlab.grid.planner import pool_for


def explicit_graph(blocked, connectivity):
    h, w = blocked.shape
    rows, cols, costs = [], [], []
    moves = [(1, 0), (-1, 0), (0, 1), (0, -1)]
    if connectivity == 8:
        moves += [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    for y in range(h):
        for x in range(w):
            if blocked[y, x]:
                continue
            for dx, dy in moves:
                nx, ny = x + dx, y + dy
                if not (0 <= nx < w and 0 <= ny < h) or blocked[ny, nx]:
                    continue
                if dx and dy and (blocked[y, x + dx] or blocked[y + dy, x]):
                    continue
                rows.append(y * w + x)
                cols.append(ny * w + nx)
                costs.append(math.sqrt(2) if dx and dy else 1.0)
    return coo_matrix((costs, (rows, cols)), shape=(h * w, h * w)).tocsr()


def random_grid(rng, h=24, w=31, p=0.3):
    return OccupancyGrid(rng.random((h, w)) < p)


def corner_query(grid):
    """The first and last free cells (row-major) as (x, y) start and goal."""
    free = np.argwhere(~grid.blocked)
    (sy, sx), (gy, gx) = free[0], free[-1]
    return (int(sx), int(sy)), (int(gx), int(gy))


CASES = [("astar", "octile", 8), ("astar", "euclidean", 8), ("astar", "chebyshev", 8), ("dijkstra", "octile", 8),
         ("jps", "octile", 8), ("astar", "manhattan", 4), ("astar", "octile", 4), ("dijkstra", "octile", 4)]


@pytest.mark.parametrize("algorithm, heuristic, connectivity", CASES)
def test_optimal_against_brute_force(algorithm, heuristic, connectivity):
    rng = np.random.default_rng(4)
    checked = 0
    for _ in range(12):
        grid = random_grid(rng)
        free = np.argwhere(~grid.blocked)
        dist = scipy_dijkstra(explicit_graph(grid.blocked, connectivity), indices=[
            int(free[k, 0]) * grid.width + int(free[k, 1]) for k in range(4)])
        for k in range(4):
            sy, sx = free[k]
            for gy, gx in free[rng.choice(len(free), 15, replace=False)]:
                truth = dist[k, gy * grid.width + gx]
                r = plan(grid, (sx, sy), (gx, gy), algorithm=algorithm, heuristic=heuristic,
                         connectivity=connectivity)
                if np.isinf(truth):
                    assert r.status is Status.FAILED
                else:
                    assert r.success and r.cost == pytest.approx(truth, abs=1e-9)
                    checked += 1
    assert checked > 300


def test_inadmissible_and_weighted_are_valid_but_bounded():
    rng = np.random.default_rng(8)
    worse = 0
    for _ in range(30):
        grid = random_grid(rng, 30, 30, 0.25)
        (sx, sy), (gx, gy) = corner_query(grid)
        best = plan(grid, (sx, sy), (gx, gy))
        if not best.success:
            continue
        manhattan = plan(grid, (sx, sy), (gx, gy), heuristic="manhattan")
        weighted = plan(grid, (sx, sy), (gx, gy), weight=2.0)
        assert manhattan.cost >= best.cost - 1e-9
        assert best.cost - 1e-9 <= weighted.cost <= 2.0 * best.cost + 1e-9
        worse += manhattan.cost > best.cost + 1e-9
    assert worse > 0  # Manhattan on 8-connected grids does lose optimality


def test_theta_star_is_any_angle_and_valid():
    rng = np.random.default_rng(2)
    for _ in range(20):
        grid = random_grid(rng, 30, 30, 0.2)
        (sx, sy), (gx, gy) = corner_query(grid)
        astar = plan(grid, (sx, sy), (gx, gy))
        theta = plan(grid, (sx, sy), (gx, gy), algorithm="theta_star")
        assert theta.status is astar.status
        if astar.success:
            assert theta.cost <= astar.cost + 1e-9
            assert theta.cost >= math.dist((sx, sy), (gx, gy)) - 1e-9
            for a, b in zip(theta.cells[:-1], theta.cells[1:]):
                assert line_of_sight(grid, a, b)


def test_open_grid_theta_star_is_straight():
    grid = OccupancyGrid(np.zeros((20, 30), dtype=bool))
    r = plan(grid, (0, 0), (29, 7), algorithm="theta_star")
    assert r.cost == pytest.approx(math.hypot(29, 7)) and len(r.cells) == 2


def test_smoothing_keeps_line_of_sight_and_shortens():
    rng = np.random.default_rng(6)
    for _ in range(20):
        grid = random_grid(rng, 40, 40, 0.2)
        (sx, sy), (gx, gy) = corner_query(grid)
        raw = plan(grid, (sx, sy), (gx, gy))
        sm = plan(grid, (sx, sy), (gx, gy), smooth=True)
        if not raw.success:
            continue
        assert sm.cost <= raw.cost + 1e-9 and sm.stats["raw_cost_cells"] == pytest.approx(raw.cost)
        assert tuple(sm.cells[0]) == (sx, sy) and tuple(sm.cells[-1]) == (gx, gy)
        for a, b in zip(sm.cells[:-1], sm.cells[1:]):
            assert line_of_sight(grid, a, b, method="bresenham")


def test_line_of_sight_cases():
    blocked = np.zeros((5, 5), dtype=bool)
    blocked[2, 2] = True
    grid = OccupancyGrid(blocked)
    assert not line_of_sight(grid, (0, 2), (4, 2))
    assert line_of_sight(grid, (0, 0), (4, 1))
    assert not line_of_sight(grid, (0, 0), (4, 4))  # through the blocked centre
    corner = np.zeros((2, 2), dtype=bool)
    corner[0, 1] = corner[1, 0] = True
    g2 = OccupancyGrid(corner)
    for method in ("supercover", "bresenham"):
        assert not line_of_sight(g2, (0, 0), (1, 1), method=method)  # no squeezing between corners
    with pytest.raises(ValueError, match="method"):
        line_of_sight(grid, (0, 0), (1, 1), method="dda")


@pytest.mark.parametrize("start, goal, status", [
    ((-1, 0), (3, 3), Status.INVALID_START), ((0, 0), (3, 9), Status.INVALID_GOAL),
    ((2, 2), (0, 0), Status.INVALID_START), ((0, 0), (2, 2), Status.INVALID_GOAL),
])
def test_invalid_queries(start, goal, status):
    blocked = np.zeros((5, 5), dtype=bool)
    blocked[2, 2] = True
    r = plan(OccupancyGrid(blocked), start, goal)
    assert r.status is status and r.reason and len(r.cells) == 0


def test_unreachable_fails_and_unknown_cells():
    blocked = np.zeros((6, 6), dtype=bool)
    blocked[:, 3] = True
    unknown = np.zeros_like(blocked)
    unknown[2, 3] = True
    blocked[2, 3] = False
    grid = OccupancyGrid(blocked, unknown=unknown)
    assert plan(grid, (0, 0), (5, 5)).status is Status.FAILED
    assert plan(grid, (0, 0), (5, 5), allow_unknown=True).success


@pytest.mark.parametrize("weight", [2, 2.0, np.int64(2), np.float32(2.0)])
def test_weight_takes_any_real_number(weight):
    # numpy's numbers are numbers (np.int64(2) was refused until session 14; attack check)
    r = plan(OccupancyGrid(np.zeros((3, 3), dtype=bool)), (0, 0), (2, 2), weight=weight)
    assert r.success and r.params["weight"] == 2.0


@pytest.mark.parametrize("kwargs, field", [({"algorithm": "astr"}, "astar"), ({"heuristic": "manhatan"}, "manhattan"),
                                           ({"connectivity": 6}, "connectivity"), ({"weight": 0.5}, "weight"),
                                           ({"algorithm": "jps", "connectivity": 4}, "jps")])
def test_bad_parameters(kwargs, field):
    with pytest.raises(ValueError, match=field):
        plan(OccupancyGrid(np.zeros((3, 3), dtype=bool)), (0, 0), (2, 2), **kwargs)


@pytest.mark.parametrize("start", [(True, 1), (1, np.bool_(False)), (1.5, 1), (float("nan"), 1), (1,), "a1",
                                   {1, 2}, {1: 0, 2: 0}])
def test_a_cell_that_is_not_two_integers_is_named(start):
    # a bool is no coordinate: True was taken as cell 1 until session 14 (newcomer check)
    with pytest.raises(ValueError, match="start must be an integer cell"):
        plan(OccupancyGrid(np.zeros((3, 3), dtype=bool)), start, (2, 2))


def test_world_variant_and_frames():
    grid = OccupancyGrid(np.zeros((10, 20), dtype=bool), resolution=0.5, origin=(-2.0, 1.0, 0.0))
    r = plan_world(grid, (-1.9, 1.1), (7.9, 5.9))
    assert tuple(r.cells[0]) == (0, 0) and tuple(r.cells[-1]) == (19, 9)
    np.testing.assert_allclose(r.path[0], (-1.75, 1.25))
    assert r.cost == r.stats["length_m"] == pytest.approx(r.stats["cost_cells"] * 0.5)  # metres
    assert r.cost == pytest.approx(np.sum(np.linalg.norm(np.diff(r.path, axis=0), axis=1)))


def test_every_status_carries_the_same_stats_keys():
    from navlab.grid.planner import STATS_KEYS

    blocked = np.zeros((6, 6), dtype=bool)
    blocked[:, 3] = True
    grid = OccupancyGrid(blocked, resolution=0.25)
    results = [plan(grid, (0, 0), (2, 5)), plan(grid, (0, 0), (5, 5)), plan(grid, (3, 0), (0, 0)),
               plan(grid, (0, 0), (3, 3)), plan(grid, (-1, 0), (0, 0)), plan(grid, (0, 0), (9, 9)),
               plan(grid, (0, 0), (2, 5), smooth=True)]
    assert [r.status for r in results] == [Status.EXACT, Status.FAILED, Status.INVALID_START, Status.INVALID_GOAL,
                                           Status.INVALID_START, Status.INVALID_GOAL, Status.EXACT]
    for r in results:
        assert set(r.stats) == set(STATS_KEYS), r.status
        assert (r.cost == r.stats["length_m"] == r.stats["cost_cells"] * 0.25) or not r.success
    assert all(math.isinf(r.cost) and math.isinf(r.stats["cost_cells"]) for r in results[1:6])


def test_large_grid_reuses_search_state():
    grid = OccupancyGrid(np.zeros((5000, 5000), dtype=bool))
    r1 = plan(grid, (10, 10), (60, 40))
    (searcher,) = pool_for(grid, False)._idle
    r2 = plan(grid, (4000, 4000), (4010, 4990), algorithm="jps")
    arrays = [id(a) for a in (searcher.state, searcher.g, searcher.lo)]
    r3 = plan(grid, (4000, 10), (10, 4000))
    r4 = plan(grid, (10, 4000), (4000, 4900), algorithm="jps")
    assert all(r.success for r in (r1, r2, r3, r4)) and r2.stats["expanded"] < 100
    assert pool_for(grid, False)._idle == [searcher]
    assert arrays == [id(a) for a in (searcher.state, searcher.g, searcher.lo)]


def test_open_lists_grow_when_full_and_the_query_is_rerun():
    """An open list or stack that fills up mid-query is grown and the query
    rerun: the answer is the same optimum as with room to spare."""
    blocked = np.random.default_rng(3).random((60, 60)) < 0.3
    blocked[30, :] = blocked[:, 2] = blocked[:, 57] = False
    for algo in ("astar", "dijkstra", "jps", "theta_star"):
        roomy = plan(OccupancyGrid(blocked), (2, 5), (57, 55), algorithm=algo)
        cramped = OccupancyGrid(blocked)
        with pool_for(cramped, False).lease() as s:
            s.stack = s.stack[:2]
            s._pool(3)
        r = plan(cramped, (2, 5), (57, 55), algorithm=algo)
        assert roomy.status == r.status == Status.EXACT and np.array_equal(r.cells, roomy.cells)
        assert s.key.size > 3 and s.stack.size > 2  # it did run out of room


def test_a_search_stopped_by_unknown_cells_says_so():
    blocked = np.zeros((10, 10), bool)
    unknown = np.zeros((10, 10), bool)
    unknown[:, 5] = True  # a column of unknown cells cuts the map in two
    grid = OccupancyGrid(blocked, unknown=unknown)
    closed = plan(grid, (1, 1), (8, 8))
    assert closed.status == Status.FAILED and "10 unknown cells were closed" in closed.reason
    assert "--allow-unknown" in closed.reason
    assert plan(grid, (1, 1), (8, 8), allow_unknown=True).status == Status.EXACT
    walled = plan(OccupancyGrid(unknown), (1, 1), (8, 8))  # the same column blocked: no hint
    assert walled.status == Status.FAILED and "unknown" not in walled.reason


@pytest.mark.parametrize("algorithm, own", [("dijkstra", "none"), ("jps", "octile"), ("theta_star", "euclidean")])
def test_the_params_name_the_heuristic_and_weight_the_search_used(algorithm, own):
    """Dijkstra, JPS and Theta* search with their own heuristic and no weight; their params said
    'manhattan' and 3.0 when given those (session 16's left-alone list). The answer is the one
    they give without them."""
    blocked = np.zeros((12, 12), dtype=bool)
    blocked[2:10, 5] = True
    grid = OccupancyGrid(blocked)
    given = plan(grid, (1, 6), (10, 6), algorithm=algorithm, heuristic="manhattan", weight=3.0)
    plain = plan(grid, (1, 6), (10, 6), algorithm=algorithm)
    assert given.params["heuristic"] == plain.params["heuristic"] == own
    assert given.params["weight"] == plain.params["weight"] == 1.0
    assert given.cost == plain.cost and np.array_equal(given.cells, plain.cells)
    astar = plan(grid, (1, 6), (10, 6), heuristic="manhattan", weight=3.0)
    assert astar.params["heuristic"] == "manhattan" and astar.params["weight"] == 3.0
