"""Exact collision checking against shapely distances (independent truth)."""

import numpy as np
import pytest
import shapely

import navlab
from navlab.world import Bounds, Circle, Polygon, Rectangle, World
from helpers import true_clearance

OBSTACLES = (
    Circle((3.0, 3.0), 1.0),
    Rectangle((6.0, 1.0), (8.0, 2.5)),
    Polygon(((1.0, 6.0), (4.0, 6.5), (2.0, 9.0), (2.5, 7.0))),  # non-convex
    Polygon(((6.0, 6.0), (9.0, 6.0), (9.0, 9.0), (8.0, 9.0), (8.0, 7.0), (6.0, 7.0))),  # L shape
)


@pytest.mark.parametrize("radius", [0.0, 0.1, 0.45])
def test_segments_match_shapely_distance(radius, rng):
    world = World("t", Bounds(0, 10, 0, 10), (0.1, 0.1), (9.9, 9.9), OBSTACLES, robot_radius=radius)
    checker = world.checker()
    a = rng.uniform(0, 10, (3000, 2))
    b = a + rng.normal(0, 2.0, (3000, 2))
    b = np.clip(b, 0, 10)
    got = checker.segments_free(a, b)
    compared = 0
    for i in range(len(a)):
        seg = shapely.LineString([a[i], b[i]]) if np.any(a[i] != b[i]) else shapely.Point(a[i])
        clear = true_clearance(world, seg)
        if abs(clear - radius) < 1e-9 and not (radius == 0 and clear == 0):
            continue  # touching: either answer is within tolerance
        expected = clear > radius if radius > 0 else clear > 0
        assert got[i] == expected, (a[i], b[i], clear)
        compared += 1
    assert compared > 2900
    assert 0.2 < got.mean() < 0.9  # both outcomes are exercised
    assert checker.segment_checks == 3000 and checker.calls == 1


def test_points_and_clearance_match_shapely(rng):
    world = World("t", Bounds(0, 10, 0, 10), (0.1, 0.1), (9.9, 9.9), OBSTACLES, robot_radius=0.3)
    checker = world.checker()
    pts = rng.uniform(0, 10, (2000, 2))
    clear = checker.clearance(pts)
    truth = np.array([max(true_clearance(world, shapely.Point(p)), 0.0) for p in pts])
    np.testing.assert_allclose(clear, truth, atol=1e-9)
    free = checker.points_free(pts)
    decided = np.abs(truth - 0.3) > 1e-9
    np.testing.assert_array_equal(free[decided], (truth > 0.3)[decided])
    assert checker.point_checks == 2000


def test_grazing_segment_is_exact_not_sampled():
    # A long edge passing 0.799 from a circle's surface with robot radius 0.8:
    # a check at points spaced along the edge would miss the violation.
    world = World("t", Bounds(-10, 10, -10, 10), (-9, 0), (9, 0), (Circle((0.0, 1.8), 1.0),), robot_radius=0.8)
    checker = world.checker()
    assert not checker.segments_free([[-9, 0.001]], [[9, 0.001]])[0]
    assert checker.segments_free([[-9, -0.0001]], [[9, -0.0001]])[0]


def test_out_of_bounds_is_invalid():
    world = World("t", Bounds(0, 1, 0, 1), (0.5, 0.5), (0.6, 0.6))
    checker = world.checker()
    assert list(checker.points_free([[0.5, 0.5], [1.5, 0.5], [0.5, -0.01]])) == [True, False, False]
    assert not checker.segments_free([[0.5, 0.5]], [[1.2, 0.5]])[0]


def test_bad_query_shapes():
    checker = navlab.load_world("clutter").checker()
    with pytest.raises(ValueError, match="shape"):
        checker.points_free(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="differ"):
        checker.segments_free(np.zeros((3, 2)), np.zeros((2, 2)))
