"""The lazy holonomic field against textbook Dijkstra: a value read lazily, in any order, is the whole field's."""

import numpy as np

from navlab.grid.hybrid_field import SETTLED, field_at, field_start
from grid.test_hybrid_heuristic import heap_field, random_field_problems  # tests/ is on the path (pyproject: pythonpath)


def test_lazy_lookups_in_random_order_equal_heap_dijkstra_bit_for_bit():
    rng = np.random.default_rng(5)
    partial = 0
    for passable, gx, gy, res in random_field_problems(rng, 80):
        h, w = passable.shape
        truth = heap_field(passable, gx, gy, res)
        state, dist, cells, size, cursor = field_start(passable, gx, gy, res)
        for _ in range(rng.integers(1, 3 * h * w)):
            cx, cy = int(rng.integers(0, w)), int(rng.integers(0, h))
            value, cells = field_at(state, dist, cells, size, cursor, w + 2, res, cx, cy)
            assert value == truth[cy, cx] or (np.isinf(value) and np.isinf(truth[cy, cx])), (cx, cy)
        partial += np.count_nonzero(state & SETTLED) < np.count_nonzero(np.isfinite(truth))
    assert partial > 10  # the lazy path was taken: many fields were read before the wave had covered them


def test_an_unreachable_cell_reads_inf_and_a_blocked_one_costs_no_wave():
    passable = np.ones((5, 9), bool)
    passable[:, 4] = False  # a wall splits the map
    state, dist, cells, size, cursor = field_start(passable, 1, 2, 0.5)
    value, cells = field_at(state, dist, cells, size, cursor, 11, 0.5, 4, 2)  # in the wall
    assert np.isinf(value) and np.count_nonzero(state & SETTLED) == 0
    value, cells = field_at(state, dist, cells, size, cursor, 11, 0.5, 2, 2)
    assert value == 0.5
    value, cells = field_at(state, dist, cells, size, cursor, 11, 0.5, 7, 2)  # beyond the wall: the wave runs out
    assert np.isinf(value) and np.count_nonzero(state & SETTLED) == 20
