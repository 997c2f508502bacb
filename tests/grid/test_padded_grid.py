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


def test_a_grid_built_without_unknown_cells_is_not_read_for_them():
    """OccupancyGrid(blocked) knows it has no unknown cells (``_no_unknown``), and so do the grids made
    from it and its pickled copies: the search never reads its all-False ``unknown`` array (0.9 ms of a
    fresh 4096² grid's first query). A grid given an ``unknown`` array is read as before."""
    import pickle

    import pytest

    from navlab.errors import ParameterError

    rng = np.random.default_rng(13)
    blocked = rng.random((25, 30)) < 0.25
    unknown = rng.random((25, 30)) < 0.1
    plain = OccupancyGrid(blocked)
    for grid in (plain, plain.replace(), plain.with_blocked(blocked.copy()), pickle.loads(pickle.dumps(plain)),
                 plain.replace(resolution=0.5)):
        assert grid._no_unknown and not grid.unknown.any()
        assert pool_for(grid, False).grid.unknown is None
    for grid in (plain.with_unknown(unknown), OccupancyGrid(blocked, unknown=unknown),
                 OccupancyGrid(blocked, unknown=np.zeros_like(blocked))):
        assert not grid._no_unknown
        assert (pool_for(grid, False).grid.unknown is None) == (not grid.unknown.any())
    for grid in (plain, OccupancyGrid(blocked, unknown=np.zeros_like(blocked))):  # either way, alike
        with pytest.raises(ParameterError, match="unknown has shape"):
            grid.with_blocked(np.zeros((3, 3), bool))
    free = np.argwhere(~(blocked | unknown))
    s, t = tuple(int(v) for v in free[0][::-1]), tuple(int(v) for v in free[-1][::-1])
    for algorithm in ("astar", "jps", "theta_star"):  # the same answers as a grid told its unknown cells are none
        a = plan(plain, s, t, algorithm=algorithm)
        b = plan(OccupancyGrid(blocked, unknown=np.zeros_like(blocked)), s, t, algorithm=algorithm)
        assert a.status == b.status and a.cost == b.cost
