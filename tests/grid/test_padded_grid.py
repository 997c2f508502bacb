"""PaddedGrid builds the legal-move masks straight from the grid and the padded
free-cell array only when Theta*, smoothing or line of sight ask for it."""

import numpy as np

from navlab.grid import OccupancyGrid, line_of_sight, plan
from navlab.grid.planner import PaddedGrid, pool_for

from .test_legal_moves import mask_by_rule


def test_unknown_cells_are_closed_in_the_masks_and_the_free_array():
    rng = np.random.default_rng(11)
    blocked = rng.random((19, 26)) < 0.25
    unknown = rng.random((19, 26)) < 0.15
    grid = PaddedGrid(blocked, unknown)
    closed = blocked | unknown
    assert np.array_equal(grid.moves.reshape(21, 28)[1:-1, 1:-1], mask_by_rule(closed))
    free = grid.free.reshape(21, 28)
    assert np.array_equal(free[1:-1, 1:-1], (~closed).astype(np.uint8))
    assert not free[[0, -1], :].any() and not free[:, [0, -1]].any()
    assert [grid.is_free(x, y) for y in range(19) for x in range(26)] == list((~closed).ravel())
    # no unknown cell at all: the same as passing none
    assert np.array_equal(PaddedGrid(blocked, np.zeros_like(blocked)).moves, PaddedGrid(blocked).moves)


def test_astar_dijkstra_and_jps_never_build_the_free_array():
    rng = np.random.default_rng(12)
    grid = OccupancyGrid(rng.random((30, 30)) < 0.2)
    free = np.argwhere(~grid.blocked)
    s, t = tuple(int(v) for v in free[0][::-1]), tuple(int(v) for v in free[-1][::-1])
    padded = pool_for(grid, False).grid
    for algorithm in ("astar", "dijkstra", "jps"):
        assert plan(grid, s, t, algorithm=algorithm).success
    assert plan(grid, s, t, connectivity=4, heuristic="manhattan").success
    assert "free" not in vars(padded)
    assert not plan(grid, s, tuple(int(v) for v in np.argwhere(grid.blocked)[0][::-1])).success  # a blocked goal
    assert "free" not in vars(padded)
    line_of_sight(grid, s, t)
    assert "free" in vars(padded)  # built once asked for
    theta = plan(grid, s, t, algorithm="theta_star")
    assert theta.success and theta.cost <= plan(grid, s, t).cost + 1e-9
