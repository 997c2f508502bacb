"""Hybrid A* searches one lattice of headings per robot: a start heading between two
of its headings joins it by a short arc, and the path still starts at the exact start."""

import math

import numpy as np
import pytest

from navlab.grid import hybrid_astar
from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.occupancy import OccupancyGrid
from navlab.sampling.curves import CurvePath
from navlab.sampling.footprint_lattice import lattice_for

RES = 0.05
ROBOT = [[-0.25, -0.2], [-0.25, 0.2], [0.25, 0.2], [0.25, -0.2]]


def room():
    blocked = np.zeros((100, 140), bool)
    blocked[:60, 70:72] = True  # a wall to drive round
    return OccupancyGrid(blocked, resolution=RES)


def exact(result, start):
    """The path re-traced from the reported segments, at 1 mm."""
    path = CurvePath(tuple(start), result.stats["word"], tuple(result.stats["segments"]),
                     result.params["turning_radius"])
    return path.sample(0.001)[0]


@pytest.mark.parametrize("motion", ["reeds_shepp", "dubins"])
def test_queries_at_any_start_heading_share_one_lattice_and_start_exactly(motion):
    grid = room()
    lattice_for.cache_clear()
    headings = [0.0, 0.3, -2.1, 1.0 + 1e-7, math.pi / 2]
    for heading in headings:
        start, goal = (2.0, 2.5, heading), (6.0, 1.0, -0.7)
        r = plan_hybrid(grid, start, goal, 0.5, motion=motion, footprint=ROBOT)
        assert r.success, (heading, r.reason)
        assert np.allclose(r.path[0], start, atol=1e-9) and np.allclose(r.path[-1][:2], goal[:2], atol=1e-9)
        poses = exact(r, start)
        assert np.allclose(poses[0], start, atol=1e-12)
        assert abs(np.hypot(*(poses[-1][:2] - goal[:2]))) < 1e-6
        if motion == "dubins":  # forward only, the joining arc too
            assert all(s >= 0 for s in r.stats["segments"])
    # every query searched the one lattice of headings k·2π/72 (theta0 0)
    assert lattice_for.cache_info().currsize == 1


def test_a_start_between_headings_joins_the_nearer_one():
    grid = room()
    r = plan_hybrid(grid, (1.0, 1.0, 0.03), (6.0, 1.0, 0.0), 0.5, footprint=ROBOT, smooth=False)
    assert r.success
    first_kind, first_length = r.stats["word"][0], r.stats["segments"][0]
    # 0.03 rad lies between 0 and 5°: the arc turns right by 0.03 rad (forward), 0.015 m on a 0.5 m radius
    assert first_kind == "R" and first_length == pytest.approx(0.5 * 0.03, abs=1e-12)


def test_without_a_free_arc_the_search_runs_through_the_start_heading(monkeypatch):
    """Where no arc onto the shared lattice is free, the query searches a lattice through its own start
    heading (the planner before the shared lattice), and still finds the path from the exact start."""
    grid = room()
    start, goal = (1.0, 1.0, 0.3), (6.0, 1.0, -0.7)
    asked = []

    def spy(*args):
        asked.append(args[-1])  # theta0
        return lattice_for(*args)

    monkeypatch.setattr(hybrid_astar, "lattice_for", spy)
    monkeypatch.setattr(hybrid_astar, "_start_nodes", lambda *args: [])
    r = plan_hybrid(grid, start, goal, 0.5, footprint=ROBOT)
    assert r.success and np.allclose(r.path[0], start)
    assert asked == [0.0, 0.3]
    assert np.allclose(exact(r, start)[0], start, atol=1e-12)


def test_a_start_heading_a_hair_off_the_lattice_still_ends_at_the_goal():
    """A heading 1e-12..1e-9 rad off a lattice heading joins it by its (tiny) arc: treated as on the
    lattice, 3 km of straight driving missed the goal by 2.7 µm."""
    blocked = np.zeros((60, 3000), bool)
    grid = OccupancyGrid(blocked, resolution=1.0)
    for heading in (9e-10, -9e-10, 1.1e-9, 5e-13):
        start, goal = (10.0, 30.0, heading), (2990.0, 30.0, 0.0)
        r = plan_hybrid(grid, start, goal, 5.0, motion="dubins", robot_radius=0.5, max_expansions=100_000)
        assert r.success
        end = exact(r, start)[-1]
        assert np.hypot(*(end[:2] - goal[:2])) < 1e-8 and abs(end[2]) < 1e-12, heading


def test_an_exhausted_shared_lattice_is_searched_again_through_the_start_heading(monkeypatch):
    """Arcs onto the shared lattice can lead where its poses find no way on (2 of 700 random near-wall
    queries) while a lattice through the start heading has one: the planner then searches that too."""
    blocked = np.zeros((100, 140), bool)
    blocked[70:90, 100:120] = True
    blocked[72:88, 102:118] = False  # a sealed pocket
    grid = OccupancyGrid(blocked, resolution=RES)
    start, goal = (1.0, 1.0, 0.3), (6.0, 1.0, -0.7)
    pocket = (5.5, 4.0, 0, 0.0, hybrid_astar.LEFT, 0.01)  # an arc "ending" in the pocket: its search is exhausted
    monkeypatch.setattr(hybrid_astar, "_start_nodes", lambda *args: [pocket])
    r = plan_hybrid(grid, start, goal, 0.5, footprint=ROBOT)
    assert r.success and np.allclose(exact(r, start)[0], start, atol=1e-12)
    assert np.hypot(*(exact(r, start)[-1][:2] - goal[:2])) < 1e-6
