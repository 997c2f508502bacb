"""The fuzz suite's independent checks catch wrong answers (a check that cannot fail is a defect)."""

import numpy as np
import pytest

from navlab.result import Result, Status
from navlab.world import world_from_dict

from fuzz.checks import check_grid_result, check_world_result

WORLD = world_from_dict({"bounds": {"x": [0, 10], "y": [0, 10]}, "start": [1, 1], "goal": [9, 9],
                         "obstacles": [{"type": "circle", "center": [5, 5], "radius": 1}]})


def test_world_check_accepts_a_right_path():
    path = np.array([[1, 1], [1, 9], [9, 9]], float)
    check_world_result(WORLD, Result(Status.EXACT, path, 16.0))


@pytest.mark.parametrize("result", [
    Result(Status.EXACT, np.array([[1, 1], [9, 9]], float), 8 * 2 ** 0.5),  # through the circle
    Result(Status.EXACT, np.array([[1, 1], [1, 9]], float), 8.0),  # does not reach the goal
    Result(Status.EXACT, np.array([[1, 1], [1, 9], [9, 9]], float), 15.0),  # wrong cost
    Result(Status.EXACT, np.array([[2, 1], [1, 9], [9, 9]], float), 17.0),  # not from the start
    Result(Status.INVALID_START),  # the start is free
    Result(Status.EXACT),  # success without a path
])
def test_world_check_rejects_wrong_answers(result):
    with pytest.raises(AssertionError):
        check_world_result(WORLD, result)


PASSABLE = np.array([[1, 1, 1], [0, 0, 1], [1, 1, 1]], bool)  # [y, x]; diagonals round the wall cut corners
OPEN = np.ones((3, 3), bool)


def test_grid_check_accepts_the_optimum():
    cells = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [2, 2], [1, 2], [0, 2]])
    check_grid_result(PASSABLE, (0, 0), (0, 2), Result(Status.EXACT, cost=6.0, cells=cells), "astar")
    check_grid_result(OPEN, (0, 0), (2, 2), Result(Status.EXACT, cost=2 * 2 ** 0.5, cells=np.array([[0, 0], [1, 1], [2, 2]])),
                      "astar")


@pytest.mark.parametrize("grid, cells, cost, status", [
    (PASSABLE, [[0, 0], [0, 1], [0, 2]], 2.0, Status.EXACT),  # through a blocked cell
    (PASSABLE, [[0, 0], [1, 0], [2, 1], [1, 2], [0, 2]], 2 + 2 * 2 ** 0.5, Status.EXACT),  # cuts corners
    (OPEN, [[0, 0], [1, 0], [2, 0], [2, 1], [2, 2]], 4.0, Status.EXACT),  # not optimal
    (OPEN, [[0, 0], [1, 1], [2, 2]], 2.0, Status.EXACT),  # cost is not the path's length
    (OPEN, [[0, 0], [2, 2]], 2 * 2 ** 0.5, Status.EXACT),  # jumps
    (PASSABLE, None, float("inf"), Status.FAILED),  # a path exists
])
def test_grid_check_rejects_wrong_answers(grid, cells, cost, status):
    result = Result(status, cost=cost, cells=None if cells is None else np.array(cells))
    with pytest.raises(AssertionError):
        check_grid_result(grid, (0, 0), (0, 2) if grid is PASSABLE else (2, 2), result, "astar")
