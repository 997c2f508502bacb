"""JPS's open list: a ring of buckets over a span of f (kernels.JPS_SPAN) plus an
overflow list for jumps that raise f by more, checked against scipy's Dijkstra
on the explicit graph. The maps make jumps lead far away from the goal, so
keys land in the overflow list both while the ring holds others and when it
is empty."""

import numpy as np
import pytest
from scipy.sparse.csgraph import dijkstra as scipy_dijkstra

from navlab.grid import OccupancyGrid, plan
from navlab.grid import kernels as K

from grid.test_search import explicit_graph  # tests/ is on the path (pyproject: pythonpath)
from grid.test_search_state import legal_steps


def distance(blocked, s, t):
    w = blocked.shape[1]
    return scipy_dijkstra(explicit_graph(blocked, 8), indices=s[1] * w + s[0])[t[1] * w + t[0]]


def test_a_u_turn_whose_only_jump_raises_f_beyond_the_ring():
    """Start and goal one wall apart: the first jump point, at the far end,
    has f about 200 above the start's (the ring spans JPS_SPAN = 32), and it
    is the only open node then, so it is popped from the overflow list."""
    assert K.JPS_SPAN < 150
    blocked = np.zeros((3, 101), bool)
    blocked[1, 1:] = True  # a wall with one gap at x = 0
    start, goal = (100, 2), (100, 0)
    r = plan(OccupancyGrid(blocked), start, goal, algorithm="jps")
    assert r.success and r.cost == pytest.approx(distance(blocked, start, goal), abs=1e-9)
    assert r.cost == 202.0  # 100 cells west, 2 up through the gap (no corner cutting), 100 east
    legal_steps(OccupancyGrid(blocked), r.cells, 8)


@pytest.mark.parametrize("seed", range(4))
def test_combs_of_long_corridors_equal_scipy(seed):
    """Long walls with random gaps and sparse random blocks: jumps of every
    length, many beyond the ring's span while it holds nearer keys."""
    rng = np.random.default_rng(seed)
    h, w = 61, 160
    blocked = rng.random((h, w)) < 0.01
    for y in range(4, h - 1, 8):
        blocked[y, :] = True
        blocked[y, rng.integers(w, size=2)] = False
    free = np.argwhere(~blocked)
    grid = OccupancyGrid(blocked)
    queries = free[rng.integers(len(free), size=(25, 2))]
    # distances from the 25 starts only (all pairs took ~10 s and 0.8 GB)
    truth = scipy_dijkstra(explicit_graph(blocked, 8), indices=queries[:, 0, 0] * w + queries[:, 0, 1])
    for i, ((sy, sx), (gy, gx)) in enumerate(queries):
        r = plan(grid, (sx, sy), (gx, gy), algorithm="jps")
        d = truth[i, gy * w + gx]
        if np.isinf(d):
            assert not r.success
        else:
            assert r.success and r.cost == pytest.approx(d, abs=1e-9)
            legal_steps(grid, r.cells, 8)
            assert r.stats["expanded"] <= plan(grid, (sx, sy), (gx, gy)).stats["expanded"]
