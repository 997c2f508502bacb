"""navfn (move_base's global planner) against independent truth: its potential against the Euclidean
distance, its paths against straight lines and shapely geometry, its cell weighting against hand sums."""

import math

import numpy as np
import pytest
import shapely

from navlab.control.move_base_navfn import COST_NEUTRAL, navfn_costs, navfn_potential, plan_navfn
from navlab.world.costmap import Costmap

RES = 0.05


def _potential(costs: np.ndarray, robot) -> np.ndarray:
    """navfn's potential over the whole map from cell ``robot`` (x, y), [y, x] without navfn's ring."""
    padded = navfn_costs(costs, True)
    ny, nx = padded.shape
    pot = navfn_potential(padded.ravel().astype(np.int64), nx, (robot[1] + 1) * nx + robot[0] + 1, 0, 10 ** 6)
    return pot.reshape(ny, nx)[1:-1, 1:-1]


def test_the_potential_in_free_space_is_the_euclidean_distance_times_the_neutral_cost():
    pot = _potential(np.zeros((81, 81), np.uint8), (40, 40))
    ys, xs = np.mgrid[0:81, 0:81]
    dist = np.hypot(xs - 40, ys - 40)
    excess = pot / COST_NEUTRAL - dist  # [cells]
    # navfn's interpolation overestimates a little off the axes (it is no exact eikonal solver): measured
    # 1.5 cells at most over these 40, 4.4 % of the distance
    assert excess.min() >= -1e-4 and (excess <= 0.045 * dist + 0.5).all()
    assert pot[40, 80] == pytest.approx(COST_NEUTRAL * 40)  # along an axis it is exact


def test_a_cell_of_cost_c_costs_50_plus_0_8_c():
    costs = np.full((5, 41), 100, np.uint8)
    pot = _potential(costs, (0, 2))
    # along the row, each cell adds its navfn cost (50 + 0.8 · 100 = 130); the robot's own cell is cleared
    assert pot[2, 40] == pytest.approx(40 * (50 + 0.8 * 100))
    assert navfn_costs(np.array([[0, 252, 253, 254, 255]], np.uint8), True)[1, 1:-1].tolist() == [50, 251, 254,
                                                                                                   254, 253]
    assert navfn_costs(np.array([[255]], np.uint8), False)[1, 1] == 254


def test_a_free_space_path_is_the_straight_line():
    costmap = Costmap(np.zeros((80, 100), np.uint8), RES)
    start, goal = np.array((0.3, 0.4)), np.array((4.6, 3.7))
    path = plan_navfn(costmap, start, goal)
    line = shapely.LineString([start, goal])
    assert max(line.distance(shapely.Point(p)) for p in path) <= RES  # within a cell of the straight line
    # the robot's cell, at its corner: NavfnROS::mapToWorld adds no half cell
    assert np.allclose(path[0], costmap.world_to_cell([start])[0] * RES)
    assert np.allclose(path[-1], goal)
    length = float(np.hypot(*np.diff(path, axis=0).T).sum())
    assert length == pytest.approx(float(np.hypot(*(goal - start))), abs=2 * RES)


def test_the_path_keeps_off_walls_and_is_nearly_the_shortest_through_the_gap():
    costs = np.zeros((80, 100), np.uint8)
    costs[38:42, :70] = 254  # a wall across, open for x ≥ 3.5 m
    costmap = Costmap(costs, RES)
    start, goal = np.array((1.0, 0.5)), np.array((1.0, 3.5))
    path = plan_navfn(costmap, start, goal)
    cells = np.rint(path / RES).astype(int)  # navfn's nearest cell to each point (its frame has no half cell)
    assert (costs[cells[:, 1], cells[:, 0]] < 253).all()
    # the shortest way round the wall's end (3.5, 1.9)–(3.5, 2.1), by hand
    shortest = 2 * math.hypot(2.5, 1.4) + 0.2
    length = float(np.hypot(*np.diff(path, axis=0).T).sum())
    assert shortest - 2 * RES <= length <= 1.05 * shortest


@pytest.mark.parametrize("band, detour", [(200, True), (40, False)])
def test_navfns_weighting_decides_between_a_band_and_a_detour(band, detour):
    costs = np.zeros((60, 80), np.uint8)
    costs[:20, 30:34] = band  # 4 cells of ``band`` across the straight way, open above y = 1 m
    costmap = Costmap(costs, RES)
    start, goal = np.array((0.5, 0.5)), np.array((3.5, 0.5))
    # straight: 60 cells, 4 of them at 50 + 0.8·band; round the band's end: its length at 50 a cell
    straight = 56 * 50 + 4 * (50 + 0.8 * band)
    around = 50 * (math.hypot(1.0, 0.5) + 0.2 + math.hypot(1.8, 0.5)) / RES
    assert (around < straight) == detour  # band 200: 3 640 vs 3 186; band 40: 3 128 vs 3 186
    path = plan_navfn(costmap, start, goal)
    cells = np.rint(path / RES).astype(int)
    assert (costs[cells[:, 1], cells[:, 0]] == band).any() != detour


def test_no_path_to_a_walled_in_goal_and_the_robots_own_cell_is_cleared():
    costs = np.zeros((40, 40), np.uint8)
    costs[25:35, 25] = costs[25:35, 34] = costs[25, 25:35] = costs[34, 25:35] = 254
    costmap = Costmap(costs, RES)
    assert plan_navfn(costmap, (0.5, 0.5), (1.5, 1.5)) is None
    costs = np.zeros((40, 40), np.uint8)
    costs[10, 10] = 253  # the robot stands on an INSCRIBED cell: navfn plans from it all the same
    path = plan_navfn(Costmap(costs, RES), (0.525, 0.525), (1.5, 1.5))
    assert path is not None and np.allclose(path[-1], (1.5, 1.5))
