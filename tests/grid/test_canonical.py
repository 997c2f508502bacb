"""Canonical successor generation (Sturtevant & Rabin 2016) in the 8-connected
A* and Dijkstra kernels: a cell expands only the moves its arrival move
allows (kernels.CANONICAL), yet every reachable cell must still be closed with
its exact distance. Checked cell by cell against scipy's Dijkstra on the
explicit graph (tests/grid/test_search.py), on random maps of every density,
mazes and corridor combs, where forced neighbours are everywhere.
"""

import math

import numpy as np
import pytest
from scipy.sparse.csgraph import dijkstra as scipy_dijkstra

from navlab.grid import OccupancyGrid, plan
from navlab.grid import kernels as K
from navlab.grid.maze import make_maze
from navlab.grid.planner import SearcherPool

from .test_search import explicit_graph


def settle_everything(blocked, start):
    """navlab's 8-connected Dijkstra from ``start`` (x, y) with a goal it can
    never reach (the padded border), so it closes every reachable cell:
    (closed mask, distances) over the unpadded grid."""
    pool = SearcherPool(blocked)
    h, w = blocked.shape
    with pool.lease() as searcher:
        status, expanded = searcher.search("dijkstra", start, (-1, -1), 8, K.H_ZERO, 1.0)
        assert status == 0
        closed, g = K.state_costs(searcher.written_rows())
    return closed[1:-1, 1:-1], g[1:-1, 1:-1], expanded


def maps():
    rng = np.random.default_rng(22)
    for p in (0.05, 0.15, 0.25, 0.35, 0.45):
        for _ in range(4):
            h, w = rng.integers(8, 40, size=2)
            yield f"random{p}", rng.random((h, w)) < p
    for seed in range(3):
        yield "maze", make_maze(6, 5, seed=seed, cell_size=0.5, wall=0.1, resolution=0.1).blocked
    comb = np.zeros((21, 25), bool)  # long walls with gaps at alternating ends: every turn is a forced one
    comb[2::4, :-2] = True
    comb[4::4, 2:] = True
    yield "comb", comb
    rooms = np.zeros((30, 30), bool)  # walls with single-cell doors, seen from every side
    rooms[10, :] = rooms[20, :] = rooms[:, 10] = rooms[:, 20] = True
    for a, b in ((10, 4), (10, 25), (20, 15), (4, 10), (25, 20), (15, 10), (15, 20)):
        rooms[a, b] = rooms[b, a] = False
    yield "rooms", rooms


@pytest.mark.parametrize("name, blocked", list(maps()))
def test_every_reachable_cell_is_closed_with_its_exact_distance(name, blocked):
    h, w = blocked.shape
    free = np.argwhere(~blocked)
    rng = np.random.default_rng(h * 100 + w)
    graph = explicit_graph(blocked, 8)
    for sy, sx in free[rng.choice(len(free), min(3, len(free)), replace=False)]:
        truth = scipy_dijkstra(graph, indices=int(sy) * w + int(sx)).reshape(h, w)
        closed, dist, expanded = settle_everything(blocked, (int(sx), int(sy)))
        reachable = np.isfinite(truth)
        assert np.array_equal(closed, reachable), name  # no cell lost to pruning
        assert expanded == np.count_nonzero(reachable)  # and none expanded twice
        assert np.allclose(dist[reachable], truth[reachable], rtol=0, atol=1e-9), name


def test_astar_costs_equal_scipy_on_every_density():
    rng = np.random.default_rng(5)
    checked = 0
    for p in (0.1, 0.2, 0.3, 0.4):
        for _ in range(3):
            grid = OccupancyGrid(rng.random((40, 40)) < p)
            free = np.argwhere(~grid.blocked)
            starts = free[rng.choice(len(free), 3, replace=False)]
            dist = scipy_dijkstra(explicit_graph(grid.blocked, 8), indices=starts[:, 0] * 40 + starts[:, 1])
            for k, (sy, sx) in enumerate(starts):
                for gy, gx in free[rng.choice(len(free), 20, replace=False)]:
                    truth = dist[k, gy * 40 + gx]
                    r = plan(grid, (int(sx), int(sy)), (int(gx), int(gy)))
                    assert r.success == np.isfinite(truth)
                    if r.success:
                        assert r.cost == pytest.approx(truth, abs=1e-9)
                        checked += 1
    assert checked > 150


def test_the_successor_table_by_hand():
    """After a diagonal: itself and its two straight parts. After a straight
    move: itself, plus a side and the diagonal ahead on that side when the
    cell beside the one it came from is blocked (the only way past that
    corner). Bits: 0 E, 1 W, 2 N, 3 S, 4 NE, 5 NW, 6 SE, 7 SW."""
    every = 255
    east, north = 0, 2
    assert K.CANONICAL[4 * 256 + every] == 0b00010101  # NE: NE, N, E
    assert K.CANONICAL[7 * 256 + 0] == 0b10001010  # SW: SW, S, W, whatever the previous cell allowed
    assert K.CANONICAL[east * 256 + every] == 0b1  # nothing blocked beside: straight on only
    assert K.CANONICAL[east * 256 + (every & ~0b0100)] == 0b00010101  # north of the previous cell blocked
    assert K.CANONICAL[east * 256 + (every & ~0b1000)] == 0b01001001  # south blocked: S and SE
    assert K.CANONICAL[north * 256 + (every & ~0b0011)] == 0b00110111  # both sides: N, E, W, NE, NW
    assert math.isclose(K._STEP[4], math.sqrt(2))
