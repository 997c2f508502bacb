"""The strip layout A*, Dijkstra and Theta* search (kernels.strip_shape): every padded cell has one
index, which the kernels' arithmetic maps back to the cell, and each move's step (constant but across
a strip's edge) reaches the neighbour the move names. Checked cell by cell against the layout written
out with numpy, on grids from one column to several strips of 128."""

import numpy as np
import pytest

from navlab.grid import kernels as K
from navlab.grid.planner import PaddedGrid


@pytest.mark.parametrize("h, w", [(1, 1), (7, 1), (1, 9), (12, 14), (30, 200), (4, 1030), (3, 2100)])
def test_indices_steps_and_coordinates_agree_with_the_layout(h, w):
    grid = PaddedGrid(np.zeros((h, w), bool))
    rows, stride, bits, SH = grid.rows, grid.stride, grid.bits, grid.strip_height
    assert bits == K.strip_bits(stride) and (bits == K.STRIP_BITS or stride < (2 << bits) * 8)
    # the layout by numpy: padded rows cut into strips 2**bits wide, each stored row after row
    strips = -(-stride // (1 << bits))
    ids = np.arange(grid.strip_size).reshape(strips, rows, 1 << bits).transpose(1, 0, 2).reshape(rows, -1)
    assert np.array_equal(K.to_rows(np.arange(grid.strip_size), rows, stride), ids[:, :stride])
    magic, shift = K.divider(SH, grid.strip_size)
    for y in range(rows):
        for x in range(stride):
            u = ids[y, x]
            assert K.strip_index(x, y, SH, bits) == u == grid.strip_index(x - 1, y - 1)
            assert K.strip_xy(u, SH, bits, magic, shift) == (x, y)
            if 0 < x < stride - 1 and 0 < y < rows - 1:
                east, west = K.strip_sides(u, SH, bits)
                for k in range(8):
                    assert K.strip_step(u, k, bits, east, west) == ids[y + K.MOVES_Y[k], x + K.MOVES_X[k]]
                    assert K.strip_step_back(u, k, bits, east, west) == ids[y - K.MOVES_Y[k], x - K.MOVES_X[k]]


@pytest.mark.parametrize("d", [1, 2, 3, 7, 128, 4098 * 128, 1003 * 64, 10_002 * 128, 2**31 - 1])
def test_the_reciprocal_divides_exactly(d):
    """kernels.divider's multiply-and-shift is u // d for every u below n, up to 2**31 (checked at every
    multiple of d and its neighbours up to 10⁵ of them, and at 10⁵ random u)."""
    rng = np.random.default_rng(d)
    for n in {d, d + 1, 2 * d + 5, 1 << 20, 2**31}:
        if not d <= n <= 2**31:  # (its domain)
            continue
        magic, shift = K.divider(d, n)
        multiples = np.arange(0, min(n, d * 100_000), d, dtype=np.uint64)
        u = np.concatenate([multiples, multiples + np.uint64(d - 1), multiples - np.uint64(1),
                            rng.integers(0, n, 100_000).astype(np.uint64), np.array([n - 1], np.uint64)])
        u = u[u < np.uint64(n)]  # (0 - 1 wrapped)
        assert np.array_equal((u * np.uint64(magic)) >> np.uint64(shift), u // np.uint64(d))
