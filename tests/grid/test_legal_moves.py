"""The per-cell legal-move masks A* (and JPS) read instead of the grid bytes.

Checked cell by cell against the rule written out in plain Python: move k from
(x, y) is legal when both cells are free and, diagonally, both cells beside
the move are free (no corner cutting); nothing leaves the map.
"""

import numpy as np
import pytest

from navlab.grid import OccupancyGrid, plan
from navlab.grid import kernels as K
from navlab.grid.planner import PaddedGrid, pool_for


def mask_by_rule(blocked):
    h, w = blocked.shape

    def free(x, y):
        return 0 <= x < w and 0 <= y < h and not blocked[y, x]

    out = np.zeros((h, w), dtype=np.uint8)
    for y in range(h):
        for x in range(w):
            if not free(x, y):
                continue
            for k, (dx, dy) in enumerate(zip(K.MOVES_X, K.MOVES_Y)):
                if free(x + dx, y + dy) and (dx == 0 or dy == 0 or (free(x + dx, y) and free(x, y + dy))):
                    out[y, x] |= 1 << k
    return out


@pytest.mark.parametrize("shape, density, seed", [((1, 1), 0.0, 0), ((1, 7), 0.2, 1), ((9, 1), 0.3, 2),
                                                  ((23, 31), 0.3, 3), ((40, 17), 0.6, 4), ((12, 12), 0.0, 5),
                                                  ((6, 300), 0.3, 6), ((5, 1100), 0.25, 7), ((3, 1023), 0.1, 8)])
def test_masks_equal_the_rule(shape, density, seed):
    """In padded rows (JPS's) and in strips (A*'s, Dijkstra's, Theta*'s: 1 to 128 columns wide here), where
    the columns past the padded grid in the last strip hold no move either."""
    blocked = np.random.default_rng(seed).random(shape) < density
    padded = PaddedGrid(blocked)
    rows, stride = shape[0] + 2, shape[1] + 2
    strips = K.to_rows(padded.strip_moves, rows, stride)
    for got in (padded.moves.reshape(rows, stride), strips):
        assert np.array_equal(got[1:-1, 1:-1], mask_by_rule(blocked))
        assert not got[[0, -1], :].any() and not got[:, [0, -1]].any()  # the border is never entered
    assert int(padded.strip_moves.sum()) == int(strips.sum())  # nothing in the columns past the grid
    assert padded.strip_moves.size == padded.strip_size < 1.125 * rows * stride + 1
    assert not padded.moves.flags.writeable and not padded.strip_moves.flags.writeable


def test_unknown_cells_have_no_moves_unless_allowed():
    blocked = np.zeros((5, 5), bool)
    unknown = np.zeros((5, 5), bool)
    unknown[2, 1:4] = True
    grid = OccupancyGrid(blocked, unknown=unknown)
    closed = pool_for(grid, False).grid.moves.reshape(7, 7)[1:-1, 1:-1]
    opened = pool_for(grid, True).grid.moves.reshape(7, 7)[1:-1, 1:-1]
    assert np.array_equal(closed, mask_by_rule(unknown)) and np.array_equal(opened, mask_by_rule(blocked))
    assert plan(grid, (2, 0), (2, 4)).cost > plan(grid, (2, 0), (2, 4), allow_unknown=True).cost == 4.0


def test_a_changed_grid_gets_its_own_masks():
    """The masks hang on the immutable grid: a grid with one more wall plans around it."""
    grid = OccupancyGrid(np.zeros((6, 6), bool))
    assert plan(grid, (0, 0), (5, 0)).cost == 5.0
    wall = grid.blocked.copy()
    wall[0:5, 3] = True
    walled = grid.with_blocked(wall)
    assert plan(walled, (0, 0), (5, 0)).cost > 5.0
    assert plan(grid, (0, 0), (5, 0)).cost == 5.0


def test_an_end_on_an_unknown_cell_names_the_setting_that_opens_it():
    blocked = np.zeros((5, 5), bool)
    unknown = np.zeros((5, 5), bool)
    unknown[4, 4] = True
    blocked[0, 4] = True
    grid = OccupancyGrid(blocked, unknown=unknown)
    closed = plan(grid, (0, 0), (4, 4))
    assert closed.status.name == "INVALID_GOAL" and closed.reason.endswith(
        "is unknown; allow_unknown=true opens them, as --param allow_unknown=true to navlab plan or --allow-unknown to "
        "navlab grid plan")  # (no parenthesis: the command line puts the reason in one; review, session 20)
    wall = plan(grid, (0, 0), (4, 0))  # a blocked cell is not opened by any setting: no hint
    assert wall.status.name == "INVALID_GOAL" and wall.reason.endswith("is blocked")
    assert plan(grid, (0, 0), (4, 4), allow_unknown=True).cost == 4 * 2 ** 0.5
