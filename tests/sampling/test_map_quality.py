"""RRT* on a real SLAM map (the Willow Garage office floor, tests/data/maps).

A light version of benchmarks/bench_map_rrt.py's quality run (10 seeds x
20 000 iterations there): a few seeds at fewer iterations, every path checked
independently against the map's blocked squares with shapely.
"""

from pathlib import Path

import numpy as np
import pytest
import shapely

from navlab.grid import planner as grid_planner
from navlab.grid.mapio import load_map
from navlab.grid.occupancy import OccupancyGrid
from navlab.sampling.planners import RRTStar
from navlab.world import World

MAP = Path(__file__).resolve().parent.parent / "data" / "maps" / "willow-full.yaml"
RADIUS = 0.2  # [m]
START, GOAL = (10.0, 9.6), (31.5, 20.5)  # [m] 24.1 m apart, two corridors between them


@pytest.fixture(scope="module")
def willow():
    grid = load_map(MAP)
    world = World.from_grid(grid, START, GOAL, robot_radius=RADIUS)
    j, i = np.nonzero(grid.blocked | grid.unknown)
    res, (ox, oy, _) = grid.resolution, grid.origin
    boxes = shapely.box(ox + i * res, oy + j * res, ox + (i + 1) * res, oy + (j + 1) * res)
    closed = OccupancyGrid(grid.blocked | grid.unknown, grid.resolution, grid.origin)
    reference = grid_planner.plan_world(closed.inflate(RADIUS), START, GOAL, algorithm="astar",
                                        heuristic="octile", connectivity=8)
    assert reference.status.name == "EXACT"
    ref_path = np.vstack((START, reference.path, GOAL))
    ref_len = float(np.sum(np.linalg.norm(np.diff(ref_path, axis=0), axis=1)))
    return world, boxes, shapely.STRtree(boxes), ref_len


def test_the_shipped_map_is_the_office_floor(willow):
    world, boxes, _, ref_len = willow
    grid = world.occupancy
    assert (grid.width, grid.height, grid.resolution) == (584, 526, 0.1)
    assert 0.02 < grid.blocked.mean() < 0.03
    assert np.hypot(GOAL[0] - START[0], GOAL[1] - START[1]) == pytest.approx(24.1, abs=0.05)
    assert 1.15 < ref_len / 24.1 < 1.3  # the corridors make a detour


@pytest.mark.parametrize("sampler, seed", [("uniform", 0), ("uniform", 1), ("integration", 0), ("integration", 1)])
def test_rrt_star_paths_on_the_office_map_are_exact_and_clear(willow, sampler, seed):
    world, boxes, tree, ref_len = willow
    result = RRTStar(sampler=sampler, max_iter=6000).plan(world, seed)
    assert result.status.name == "EXACT", result.reason
    path = result.path
    np.testing.assert_array_equal(path[0], START)
    np.testing.assert_array_equal(path[-1], GOAL)
    line = shapely.LineString(path)
    near = tree.query(line, predicate="dwithin", distance=RADIUS + 0.5)
    assert shapely.distance(line, boxes[near]).min() > RADIUS  # independent of navlab's kernels
    # any-angle and near the octile grid path already at 6 000 iterations
    assert np.hypot(GOAL[0] - START[0], GOAL[1] - START[1]) < result.cost < 1.08 * ref_len
