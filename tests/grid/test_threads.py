"""Planning on one grid (or world) from many threads gives exactly the single-threaded answers.

Before the search state belonged to the call, 8 threads × 160 queries on one
grid returned 3–18 EXACT answers per run that were wrong (another query's
start, illegal jumps, a cost of 7.83 for an optimum of 304.14).
"""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import navlab
from navlab.grid import OccupancyGrid, plan

THREADS, QUERIES = 8, 160


def queries(grid, count, seed):
    rng = np.random.default_rng(seed)
    free = np.argwhere(~grid.blocked)
    picks = free[rng.integers(0, len(free), (count, 2))]
    return [(tuple(a[::-1]), tuple(b[::-1])) for a, b in picks]


def answer(result):
    return result.status, result.cost, result.cells.tobytes() if result.cells is not None else b""


@pytest.mark.parametrize("algorithm", ["astar", "jps", "dijkstra", "theta_star"])
def test_eight_threads_on_one_grid_equal_the_single_threaded_answers(algorithm):
    blocked = np.random.default_rng(0).random((120, 160)) < 0.25
    for repeat in range(3):
        grid = OccupancyGrid(blocked)  # a fresh grid: the first queries build its searchers concurrently
        qs = queries(grid, QUERIES, seed=repeat)
        alone = [answer(plan(OccupancyGrid(blocked), a, b, algorithm=algorithm)) for a, b in qs]
        with ThreadPoolExecutor(THREADS) as pool:
            together = list(pool.map(lambda q: answer(plan(grid, q[0], q[1], algorithm=algorithm)), qs))
        assert together == alone


def test_tree_planners_on_one_map_from_threads_equal_the_single_threaded_answers():
    blocked = np.zeros((80, 80), bool)
    blocked[20:60, 40] = True
    grid = OccupancyGrid(blocked, resolution=0.1)
    args = [dict(start=(1.0, 4.0), goal=(7.0, 4.0), seed=s, max_iter=1500) for s in range(24)]
    alone = [navlab.plan(grid, planner="rrt_star", **a) for a in args]
    with ThreadPoolExecutor(THREADS) as pool:
        together = list(pool.map(lambda a: navlab.plan(grid, planner="rrt_star", **a), args))
    for x, y in zip(alone, together):
        assert x.status == y.status and x.cost == y.cost and np.array_equal(x.path, y.path)


def test_grid_search_kernels_release_the_gil():
    """Threads planning at once run their searches in parallel (kernels compiled with ``nogil``): the
    searches (A*, Dijkstra, Theta*, JPS, costmap A*), the legal-move masks a new grid builds, the path
    read-back, smoothing and line of sight. Without it each search held the GIL for its whole length and
    threads took turns (two random4096 queries on two threads: 0.40-0.48 s against 0.19-0.23 s)."""
    from navlab.grid import kernels as K
    from navlab.grid.cost_search import costmap_astar
    from navlab.grid.planner import astar_kernel, jps_kernel

    kernels = [astar_kernel(conn, hcode, False, wide)
               for conn, hcode in ((8, K.H_OCTILE), (4, K.H_MANHATTAN), (8, K.H_ZERO)) for wide in (False, True)]
    kernels += [astar_kernel(8, K.H_EUCLIDEAN, True), jps_kernel(False), jps_kernel(True), costmap_astar]
    kernels += [K.legal_moves, K.clear_touched, K.clear_blocks, K.widen_state, K.trace_back, K.trace_jumps,
                K.trace_path, K.smooth_path, K.step_counts, K.los_supercover, K.los_bresenham]
    assert all(kernel.targetoptions.get("nogil") for kernel in kernels)
