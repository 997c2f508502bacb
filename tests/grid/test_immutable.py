"""Grids that cannot go stale: a plan always reflects the grid as it is now."""

import dataclasses
import pickle

import numpy as np
import pytest

from navlab import Status
from navlab.grid import OccupancyGrid, plan, plan_world


def open_room():
    return OccupancyGrid(np.zeros((10, 12), bool), resolution=0.5, origin=(1.0, 2.0, 0.0))


def test_a_grid_edited_after_a_plan_gives_the_new_answer():
    grid = open_room()
    before = plan(grid, (0, 5), (11, 5))
    assert before.status == Status.EXACT and len(before.cells) == 12  # straight along row 5
    wall = np.zeros_like(grid.blocked)
    wall[:, 6] = True
    walled = grid.with_blocked(grid.blocked | wall)
    assert plan(walled, (0, 5), (11, 5)).status == Status.FAILED
    gap = wall.copy()
    gap[9, 6] = False
    detour = plan(grid.with_blocked(gap), (0, 5), (11, 5))
    assert detour.status == Status.EXACT and detour.stats["cost_cells"] > before.stats["cost_cells"]
    assert not np.any(detour.cells[:, 0] == 6) or np.all(detour.cells[detour.cells[:, 0] == 6, 1] == 9)
    # the original grid (and its cached search state) still answers for itself
    again = plan(grid, (0, 5), (11, 5))
    assert again.status == Status.EXACT and np.array_equal(again.cells, before.cells)


def test_a_moved_origin_moves_the_path():
    grid = open_room()
    first = plan_world(grid, (1.3, 2.3), (6.2, 6.2))
    moved = grid.with_origin((11.0, -3.0, 0.0))
    second = plan_world(moved, (11.3, -2.7), (16.2, 1.2))
    assert first.success and second.success
    np.testing.assert_allclose(second.path, first.path + [10.0, -5.0])


def test_direct_writes_raise():
    grid = open_room()
    plan(grid, (0, 0), (3, 3))
    with pytest.raises(ValueError, match="read-only"):
        grid.blocked[5, 5] = True
    with pytest.raises(ValueError, match="read-only"):
        grid.unknown[5, 5] = True
    with pytest.raises(dataclasses.FrozenInstanceError):
        grid.origin = (5.0, 5.0, 0.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        grid.blocked = np.ones((10, 12), bool)
    with pytest.raises(ValueError):
        grid.blocked.flags.writeable = True  # a view of a read-only copy cannot be made writeable


def test_the_callers_array_is_copied():
    blocked = np.zeros((4, 4), bool)
    grid = OccupancyGrid(blocked)
    blocked[1, 1] = True
    assert not grid.blocked.any()


@pytest.mark.parametrize("make", [lambda g: g.inflate(0.6), lambda g: pickle.loads(pickle.dumps(g)),
                                  lambda g: g.replace(name="x")])
def test_derived_grids_are_read_only_too(make):
    grid = open_room().with_blocked(np.eye(10, 12, dtype=bool))
    derived = make(grid)
    assert not derived.blocked.flags.writeable and not derived.unknown.flags.writeable
    assert derived._cache == {} or derived is grid


@pytest.mark.parametrize("field", ["blocked", "unknown"])
@pytest.mark.parametrize("cells, words", [
    (np.full((2, 2), 0.5), "got 0.5 at index \\(0, 0\\)"),
    (np.array([[0.0, np.nan]]), "got nan at index \\(0, 1\\)"),
    (np.array([["False", "0"]]), "got dtype <U5"),
    (np.array([[1j, 0]]), "got dtype complex128"),
    (np.array([[0, 2]]), "got 2 at index \\(0, 1\\)"),
])
def test_a_mask_that_is_not_true_or_false_is_refused(field, cells, words):
    """numpy casts any non-zero to True: 0.5, NaN, 2 and the string '0' were silently blocked (or
    unknown) cells (an attack on the API, session 17). Booleans and 0/1 numbers are masks."""
    given = {"blocked": np.zeros(cells.shape, dtype=bool), field: cells}
    with pytest.raises(ValueError, match=f"{field} must be (an array of )?true/false .*{words}"):
        OccupancyGrid(**given)


def test_zero_one_numbers_are_a_mask():
    grid = OccupancyGrid(np.array([[0, 1], [1, 0]], dtype=np.uint8), unknown=np.array([[0.0, 0.0], [0.0, 1.0]]))
    assert grid.blocked.dtype == bool and grid.blocked.tolist() == [[False, True], [True, False]]
    assert grid.unknown.tolist() == [[False, False], [False, True]]
