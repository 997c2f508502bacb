"""Search state reused across queries, paths read back without parents, and the bucket queue's window.

A searcher keeps one packed state per cell for A*, Dijkstra and JPS (one
float64 for Theta*) and zeroes only what the previous query wrote; A* and JPS
read their paths back from those values. These tests check the
answers against scipy's Dijkstra on the explicit graph (tests/grid/test_search.py's
``explicit_graph``) and against fresh grids.
"""

import math

import numpy as np
import pytest
from scipy.sparse.csgraph import dijkstra as scipy_dijkstra

from navlab import Status
from navlab.grid import OccupancyGrid, plan
from navlab.grid import kernels as K
from navlab.grid.planner import pool_for

from grid.test_search import explicit_graph  # tests/ is on the path (pyproject: pythonpath)

ALGORITHMS = [("astar", 8), ("dijkstra", 8), ("jps", 8), ("theta_star", 8), ("astar", 4), ("dijkstra", 4)]


def state_arrays(searcher):
    """Every per-cell state array of a searcher (strip layout and rows)."""
    return [getattr(searcher, name) for name in ("state", "state_wide", "g", "row_state", "row_state_wide")]


def legal_steps(grid, cells, connectivity):
    """Every step moves to a free 8- (or 4-) neighbour without cutting a blocked corner."""
    assert not grid.blocked[cells[:, 1], cells[:, 0]].any()
    step = np.diff(cells, axis=0)
    assert np.all(np.abs(step).max(axis=1) == 1)
    if connectivity == 4:
        assert np.all(np.abs(step).sum(axis=1) == 1)
    diag = np.all(np.abs(step) == 1, axis=1)
    a, s = cells[:-1][diag], step[diag]
    assert not grid.blocked[a[:, 1], a[:, 0] + s[:, 0]].any()
    assert not grid.blocked[a[:, 1] + s[:, 1], a[:, 0]].any()


def test_one_grid_answers_a_mixed_stream_of_queries_like_fresh_grids():
    """Queries of every algorithm, failing ones included (they touch a whole
    component), one after another on one grid: each equals the same query on a
    fresh grid, and the optimal ones equal scipy's distances."""
    rng = np.random.default_rng(11)
    blocked = rng.random((40, 50)) < 0.3
    blocked[:, 25] = True  # two halves: queries across them fail after searching a whole side
    blocked[20, 25] = False
    shared = OccupancyGrid(blocked)
    free = np.argwhere(~blocked)
    truth = {c: scipy_dijkstra(explicit_graph(blocked, c)) for c in (4, 8)}
    for q in range(120):
        (sy, sx), (gy, gx) = free[rng.integers(len(free), size=2)]
        algorithm, connectivity = ALGORITHMS[q % len(ALGORITHMS)]
        kw = dict(algorithm=algorithm, connectivity=connectivity)
        got = plan(shared, (sx, sy), (gx, gy), **kw)
        fresh = plan(OccupancyGrid(blocked), (sx, sy), (gx, gy), **kw)
        assert got.status == fresh.status and got.cost == fresh.cost
        assert np.array_equal(got.cells, fresh.cells)
        d = truth[connectivity][sy * blocked.shape[1] + sx, gy * blocked.shape[1] + gx]
        if math.isinf(d):
            assert got.status is Status.FAILED
        elif algorithm == "theta_star":
            assert got.success and got.cost <= d + 1e-9
        else:
            assert got.success and got.cost == pytest.approx(d, abs=1e-9)
            legal_steps(shared, got.cells, connectivity)
    (s,) = pool_for(shared, False)._idle  # A*, Theta* and JPS write different arrays: only the last one written is dirty
    assert all(not np.any(a) for a in state_arrays(s) if not np.shares_memory(a, s.written))
    assert s.row_state.size == 0 or np.shares_memory(s.row_state, s.state)  # JPS's rows: A*'s memory


def sawtooth(width: int, amplitude: int = 20) -> np.ndarray:
    """A corridor three cells wide zigzagging at 45°: its shortest path is nearly all diagonal moves."""
    x = np.arange(width)
    wave = amplitude - np.abs(x % (2 * amplitude) - amplitude)
    return np.abs(np.arange(amplitude + 3)[:, None] - 1 - wave[None, :]) > 1


@pytest.mark.parametrize("blocked, moves", [(np.zeros((1, 40_000), bool), "straight"), (sawtooth(76_000), "diagonal")])
def test_a_path_too_long_for_the_narrow_state_is_searched_wide(blocked, moves):
    """The 32-bit state counts up to 32 766 straight and 65 535 diagonal moves (kernels.state_layout); a
    longer path stops the search, which runs again in 64 bits: scipy's distance (to its own rounding over
    10⁵ additions), and later queries on that grid start wide, without the narrow array."""
    free = np.argwhere(~blocked)
    start, goal = tuple(int(v) for v in free[0][::-1]), tuple(int(v) for v in free[-1][::-1])
    width = blocked.shape[1]
    truth = scipy_dijkstra(explicit_graph(blocked, 8), indices=start[1] * width + start[0])[goal[1] * width + goal[0]]
    for algorithm in ("astar", "jps"):  # each on a fresh grid: its own narrow search must stop and widen
        grid = OccupancyGrid(blocked)
        got = plan(grid, start, goal, algorithm=algorithm)
        steps = np.abs(np.diff(got.cells, axis=0)).sum(axis=1)
        assert np.count_nonzero(steps == (1 if moves == "straight" else 2)) > (32_766 if moves == "straight"
                                                                                else 65_534)
        assert got.success and got.cost == pytest.approx(truth, rel=1e-11)
        legal_steps(grid, got.cells, 8)
        pool = pool_for(grid, False)
        (s,) = pool._idle
        narrow = s.row_state if algorithm == "jps" else s.state
        assert pool.grid.needs_wide and narrow.size == 0  # the narrow attempt's array went
        assert s.written is (s.row_state_wide if algorithm == "jps" else s.state_wide)
    short = plan(grid, start, tuple(int(v) for v in free[40][::-1]))
    assert short.success and short.cost == plan(OccupancyGrid(blocked), start, tuple(free[40][::-1])).cost
    assert s.written is s.state_wide


@pytest.mark.parametrize("heuristic, weight", [("octile", 1.0), ("euclidean", 1.0), ("manhattan", 3.0),
                                               ("octile", 40.0)])
def test_a_search_that_outgrows_the_narrow_state_goes_on_wide(monkeypatch, heuristic, weight):
    """A* and Dijkstra go on where the narrow search stopped, in the wide state (kernels.widen_state, the
    kernel's resume), rather than start over; optimal at weight 1 (scipy's distance), within the weight
    times the optimum (and √2 more for Manhattan) otherwise, legal either way."""
    moved = []
    widen = K.widen_state
    monkeypatch.setattr(K, "widen_state", lambda *args: moved.append(1) or widen(*args))
    blocked = sawtooth(76_000)
    free = np.argwhere(~blocked)
    start, goal = tuple(int(v) for v in free[0][::-1]), tuple(int(v) for v in free[-1][::-1])
    width = blocked.shape[1]
    truth = scipy_dijkstra(explicit_graph(blocked, 8), indices=start[1] * width + start[0])[goal[1] * width + goal[0]]
    got = plan(OccupancyGrid(blocked), start, goal, heuristic=heuristic, weight=weight)
    legal_steps(OccupancyGrid(blocked), got.cells, 8)
    assert moved == [1] and got.success
    if weight == 1.0:
        assert got.cost == pytest.approx(truth, rel=1e-11)
    else:
        assert truth - 1e-6 <= got.cost <= weight * truth * (math.sqrt(2) if heuristic == "manhattan" else 1.0)


@pytest.mark.parametrize("room", ["for no open cell", "for its open cells only"])
def test_a_resumed_search_out_of_room_starts_over_wide(monkeypatch, room):
    """Open lists too small for a resumed search, whether for the open cells the stopped search hands on
    or for what follows: they grow and the search starts over wide (a resumed search that ran out of
    room may have half-expanded a cell). An open grid, so the octile distance is the truth."""
    grid = OccupancyGrid(np.zeros((60, 40_000), bool))
    pool = pool_for(grid, False)
    with pool.lease() as s:
        pass
    widen, cramped = K.widen_state, []

    def widen_then_cramp(narrow, wide, *records):
        widen(narrow, wide, *records)
        open_cells = int(np.count_nonzero((wide != 0) & (wide < np.uint64(1 << 63))))
        s._pool(2 if room == "for no open cell" else open_cells)
        s.stack = s.stack[:2]  # (a same-f stack of two: the open cells all fit, what follows does not)
        cramped.append(open_cells)

    monkeypatch.setattr(K, "widen_state", widen_then_cramp)
    got = plan(grid, (0, 0), (39_999, 59))
    assert len(cramped) == 1 and cramped[0] > 2 and pool.grid.needs_wide and s.stack.size > 2  # it grew
    assert got.success and got.cost == pytest.approx(39_999 - 59 + 59 * math.sqrt(2), rel=1e-12)
    legal_steps(grid, got.cells, 8)


@pytest.mark.parametrize("algorithm, connectivity", [("astar", 8), ("jps", 8), ("dijkstra", 8), ("astar", 4)])
def test_the_narrow_state_holds_exactly_32766_straight_moves(algorithm, connectivity):
    """The documented bound, to the move: a corridor path of 32 766 moves is searched narrow, one of 32 767
    widens (each on a fresh grid), and both cost their length exactly."""
    for moves, widens in ((32_766, False), (32_767, True)):
        grid = OccupancyGrid(np.zeros((1, moves + 1), bool))
        got = plan(grid, (0, 0), (moves, 0), algorithm=algorithm, connectivity=connectivity)
        assert got.success and got.cost == moves and len(got.cells) == moves + 1
        assert pool_for(grid, False).grid.needs_wide is widens, moves


def test_state_layout_adds_moves_exactly():
    """The packed state's g + 1 is a + b·√2 with one rounding, and each move adds one to its own field."""
    for wide in (False, True):
        dtype, shift, a_mask, b_mask, closed = K.state_layout(wide)
        steps = K.state_steps(wide)
        state = dtype(1) << shift  # the start
        for k in (0, 4, 4, 2, 7):
            state = state + steps[k]
        assert state.dtype == dtype and (state >> shift) == 3 and (state & b_mask) == 3
        closed_mask, g = K.state_costs(np.array([0, state, state | closed], dtype=dtype))
        assert closed_mask.tolist() == [False, False, True]
        assert g[0] == math.inf and g[1] == g[2] == 2 + 3 * math.sqrt(2)
    closed_mask, g = K.state_costs(np.array([0.0, 3.5, -3.5]))  # Theta*'s float64: g + 1, negative once closed
    assert closed_mask.tolist() == [False, False, True] and g.tolist() == [math.inf, 2.5, 2.5]


@pytest.mark.parametrize("algorithm", ["astar", "jps", "theta_star"])
def test_the_next_query_starts_from_all_zero_state(algorithm):
    """What a query wrote is exactly what the next one clears (nothing is left behind)."""
    rng = np.random.default_rng(5)
    grid = OccupancyGrid(rng.random((60, 70)) < 0.25)
    free = np.argwhere(~grid.blocked)
    pool = pool_for(grid, False)
    for _ in range(10):
        (sy, sx), (gy, gx) = free[rng.integers(len(free), size=2)]
        plan(grid, (sx, sy), (gx, gy), algorithm=algorithm)
        (s,) = pool._idle
        assert np.any(s.written != 0)
        s.clear()
        assert not any(np.any(a != 0) for a in state_arrays(s))
        assert np.all(s.lo == s.stride) and np.all(s.hi == -1) and not s.flags.any()


@pytest.mark.parametrize("heuristic, weight", [("octile", 1.5), ("octile", 40.0), ("manhattan", 1.0),
                                               ("manhattan", 7.0), ("euclidean", 3.0), ("chebyshev", 1.0)])
def test_weighted_and_inconsistent_searches_return_legal_bounded_paths(heuristic, weight):
    """The bucket queue's window grows with the weight and covers heuristics
    whose f can drop (Manhattan on 8-connected grids): paths stay legal and
    within weight x optimum (within the optimum for admissible ones at weight 1)."""
    rng = np.random.default_rng(9)
    for _ in range(8):
        blocked = rng.random((30, 36)) < 0.25
        grid = OccupancyGrid(blocked)
        dist = scipy_dijkstra(explicit_graph(blocked, 8))
        free = np.argwhere(~blocked)
        for _ in range(10):
            (sy, sx), (gy, gx) = free[rng.integers(len(free), size=2)]
            d = dist[sy * 36 + sx, gy * 36 + gx]
            r = plan(grid, (sx, sy), (gx, gy), heuristic=heuristic, weight=weight)
            if math.isinf(d):
                assert r.status is Status.FAILED
                continue
            assert r.success and tuple(r.cells[0]) == (sx, sy) and tuple(r.cells[-1]) == (gx, gy)
            legal_steps(grid, r.cells, 8)
            inflation = math.sqrt(2) if heuristic == "manhattan" else 1.0  # Manhattan prices a diagonal 2, not √2
            assert d - 1e-9 <= r.cost <= weight * inflation * d + 1e-9
            if heuristic != "manhattan" and weight == 1.0:
                assert r.cost == pytest.approx(d, abs=1e-9)


@pytest.mark.parametrize("out", [np.zeros(100, np.uint8), np.zeros((12, 12), np.uint8)], ids=["short", "2-D"])
def test_legal_moves_refuses_an_output_array_of_the_wrong_shape(out):
    """The kernel writes its bytes unchecked: a short or 2-D ``out`` must be refused, not overrun."""
    with pytest.raises(ValueError, match="out must be"):
        K.legal_moves(np.zeros((10, 10), np.bool_), np.zeros((0, 0), np.bool_), out)
