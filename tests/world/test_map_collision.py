"""Exact collision checking on occupancy maps, against shapely (independent truth).

Blocked cells are closed squares in the map frame (origin = outer corner of
cell (0, 0), rotated by the origin's yaw); a point or segment is free when it
lies on the map and its distance to every blocked square exceeds the robot
radius.
"""

import math

import numba
import numpy as np
import pytest
import shapely

from navlab.grid.occupancy import OccupancyGrid
from navlab.world import Bounds, Circle, World


def cell_squares(grid, mask):
    """Shapely squares of the cells in ``mask``, placed by the grid's origin and yaw."""
    ox, oy, yaw = grid.origin
    c, s = math.cos(yaw), math.sin(yaw)
    res = grid.resolution

    def world(u, v):
        return (ox + u * c - v * s, oy + u * s + v * c)

    squares = [shapely.Polygon([world(i * res, j * res), world((i + 1) * res, j * res),
                                world((i + 1) * res, (j + 1) * res), world(i * res, (j + 1) * res)])
               for j, i in zip(*np.nonzero(mask))]
    extent = shapely.Polygon([world(0, 0), world(grid.width * res, 0), world(grid.width * res, grid.height * res),
                              world(0, grid.height * res)])
    return shapely.union_all(squares), extent


def random_grid(rng, shape=(24, 32), density=0.08, origin=(0.0, 0.0, 0.0), resolution=0.1, unknown=0.0):
    blocked = rng.random(shape) < density
    unk = (rng.random(shape) < unknown) & ~blocked
    return OccupancyGrid(blocked, resolution, origin, unk)


def expected_free(geom, extent, blocked_union, radius):
    """shapely's verdict, or None when the distance is within 1e-9 m of the radius."""
    if not extent.covers(geom):
        return False
    d = shapely.distance(geom, blocked_union) if not blocked_union.is_empty else np.inf
    if abs(d - radius) < 1e-9 and not (radius == 0 and d == 0):
        return None
    return d > radius


@pytest.mark.parametrize("origin", [(0.0, 0.0, 0.0), (-1.3, 2.1, 0.0), (0.7, -0.4, 0.6), (1.0, 1.0, -2.4)])
@pytest.mark.parametrize("radius", [0.0, 0.07, 0.23])
def test_segments_and_points_match_shapely(origin, radius):
    rng = np.random.default_rng(int(1000 * radius) + int(10 * abs(origin[2])) + 7)
    density = {0.0: 0.08, 0.07: 0.04, 0.23: 0.01}[radius]  # leave free room around inflated cells
    grid = random_grid(rng, origin=origin, density=density, unknown=density / 3)
    world = World.from_grid(grid, (0, 0), (0, 0), robot_radius=radius)
    checker = world.checker()
    union, extent = cell_squares(grid, grid.blocked | grid.unknown)
    b = world.bounds
    a = rng.uniform([b.xmin, b.ymin], [b.xmax, b.ymax], (1500, 2))
    # short and long segments, so both the exact windows and the jumps are used
    b_pts = a + rng.normal(0, 1.0, (1500, 2)) * rng.choice([0.05, 0.4, 2.0], size=(1500, 1))
    got = checker.segments_free(a, b_pts)
    decided = 0
    for k in range(len(a)):
        exp = expected_free(shapely.LineString([a[k], b_pts[k]]), extent, union, radius)
        if exp is not None:
            assert got[k] == exp, (a[k], b_pts[k])
            decided += 1
    assert decided > 1450 and 0.1 < got.mean() < 0.9
    pts = rng.uniform([b.xmin, b.ymin], [b.xmax, b.ymax], (1500, 2))
    free = checker.points_free(pts)
    clear = checker.clearance(pts)
    for k in range(len(pts)):
        p = shapely.Point(pts[k])
        exp = expected_free(p, extent, union, radius)
        if exp is not None:
            assert free[k] == exp, pts[k]
        if extent.covers(p):
            assert clear[k] == pytest.approx(shapely.distance(p, union), abs=1e-9)
    assert checker.point_checks == 1500 and checker.segment_checks == 1500


@pytest.mark.parametrize("radius", [0.0, 0.2])
def test_long_segments_in_sparse_large_map(radius):
    # few obstacles in a big map: the walk jumps ahead in open space, so a
    # jump that skipped a wall would show here
    rng = np.random.default_rng(11)
    grid = random_grid(rng, shape=(300, 400), density=0.002, resolution=0.05, origin=(-3.0, 4.0, 0.0))
    world = World.from_grid(grid, (0, 0), (0, 0), robot_radius=radius)
    union, extent = cell_squares(grid, grid.blocked)
    b = world.bounds
    a = rng.uniform([b.xmin, b.ymin], [b.xmax, b.ymax], (800, 2))
    c = rng.uniform([b.xmin, b.ymin], [b.xmax, b.ymax], (800, 2))
    got = world.checker().segments_free(a, c)
    for k in range(len(a)):
        exp = expected_free(shapely.LineString([a[k], c[k]]), extent, union, radius)
        if exp is not None:
            assert got[k] == exp
    assert 0.05 < got.mean() < 0.95


@pytest.mark.parametrize("radius", [0.0, 0.3])
@pytest.mark.parametrize("sign", [-1, 1])
def test_near_touching_by_a_nanometre(radius, sign):
    # one blocked cell: square [1.0, 1.5] x [1.0, 1.5] (origin 0.5 m, 0.5 m cells)
    blocked = np.zeros((6, 6), dtype=bool)
    blocked[1, 1] = True
    grid = OccupancyGrid(blocked, 0.5, (0.5, 0.5, 0.0))
    checker = World.from_grid(grid, (0.6, 0.6), (3, 3), robot_radius=radius).checker()
    gap = radius + sign * 1e-9  # distance from the square: > radius is free
    free = sign > 0
    x = 1.0 - gap
    cases = [
        ([[x, 0.6], [x, 3.4]], "vertical, past the left side"),
        ([[0.6, 1.5 + gap], [3.4, 1.5 + gap]], "horizontal, above the top"),
    ]
    # diagonal passing the corner (1.5, 1.5) at distance gap
    d = gap / math.sqrt(2)
    cases.append(([[1.5 + d - 1.0, 1.5 + d + 1.0], [1.5 + d + 1.0, 1.5 + d - 1.0]], "diagonal past a corner"))
    for (p, q), label in cases:
        assert checker.segments_free([p], [q])[0] == free, label
        # the same point as a degenerate segment and as a point
    assert checker.points_free([[1.5 + gap, 1.2]])[0] == free
    if radius > 0:
        # the inflated corner is round: a point diagonal from the corner at distance gap
        assert checker.points_free([[1.5 + d, 1.5 + d]])[0] == free


def test_touching_a_cell_at_radius_zero_collides():
    blocked = np.zeros((8, 8), dtype=bool)
    blocked[2, 2] = True  # square [1.0, 1.5] x [1.0, 1.5]
    checker = World.from_grid(OccupancyGrid(blocked, 0.5), (0.1, 0.1), (3.9, 3.9)).checker()
    assert not checker.segments_free([[1.0, 0.0]], [[1.0, 2.0]])[0]  # along its left side
    assert not checker.segments_free([[0.5, 2.5]], [[2.5, 0.5]])[0]  # through its corner (1.5, 1.5) only
    assert checker.segments_free([[0.5, 2.5 + 1e-9]], [[2.5, 0.5 + 1e-9]])[0]
    assert not checker.points_free([[1.5, 1.5]])[0]  # a corner
    assert checker.points_free([[1.5 + 1e-9, 1.5]])[0]


def test_points_off_the_map_are_not_free():
    grid = OccupancyGrid(np.zeros((10, 10), dtype=bool), 0.1, (0.0, 0.0, math.pi / 4))
    world = World.from_grid(grid, (0.0, 0.5), (0.0, 1.0))
    checker = world.checker()
    b = world.bounds
    corner = (b.xmin + 0.01, b.ymin + 0.01)  # inside the bounds, outside the rotated map
    assert world.bounds.contains(np.array(corner))[0]
    assert list(checker.points_free([corner, (0.0, 0.7), (b.xmax + 1, 0.7)])) == [False, True, False]
    assert checker.clearance([corner])[0] == 0.0
    assert checker.clearance([(0.0, 0.7)])[0] == np.inf  # nothing blocked
    # a segment between two on-map points stays on the (convex) map
    assert checker.segments_free([(0.0, 0.2)], [(0.0, 1.3)])[0]


def test_unknown_cells_block_unless_allowed():
    blocked = np.zeros((5, 5), dtype=bool)
    unknown = np.zeros((5, 5), dtype=bool)
    unknown[2, :] = True  # a row of unknown cells across the map
    grid = OccupancyGrid(blocked, 1.0, (0.0, 0.0, 0.0), unknown)
    a, b = [[2.5, 0.5]], [[2.5, 4.5]]
    assert not World.from_grid(grid, (0.5, 0.5), (4.5, 4.5)).checker().segments_free(a, b)[0]
    assert World.from_grid(grid, (0.5, 0.5), (4.5, 4.5), allow_unknown=True).checker().segments_free(a, b)[0]


def test_shapes_and_map_together():
    rng = np.random.default_rng(5)
    grid = random_grid(rng, shape=(20, 20), density=0.05)
    base = World.from_grid(grid, (0, 0), (0, 0), robot_radius=0.05)
    circle = Circle((1.0, 1.0), 0.3)
    world = World("both", base.bounds, (0, 0), (0, 0), (circle,), robot_radius=0.05, occupancy=grid)
    union, extent = cell_squares(grid, grid.blocked)
    union = shapely.union(union, shapely.Point(1.0, 1.0).buffer(0.3, quad_segs=256))
    a = rng.uniform(0, 2, (1000, 2))
    c = a + rng.normal(0, 0.4, (1000, 2))
    got = world.checker().segments_free(a, c)
    for k in range(len(a)):
        exp = expected_free(shapely.LineString([a[k], c[k]]), extent, union, 0.05)
        # the buffered circle is a polygon: allow its approximation error
        seg = shapely.LineString([a[k], c[k]])
        if exp is not None and abs(shapely.distance(seg, shapely.Point(1, 1)) - 0.35) > 1e-4:
            assert got[k] == exp


def test_one_geometry_type_for_every_world():
    # kernels compile once: a shape world, a map world and both pack to one numba type
    grid = random_grid(np.random.default_rng(0), shape=(8, 8))
    shapes = World("s", Bounds(0, 1, 0, 1), (0.1, 0.1), (0.9, 0.9), (Circle((0.5, 0.5), 0.1),))
    on_map = World.from_grid(grid, (0.1, 0.1), (0.7, 0.7), robot_radius=0.1)
    both = World("b", on_map.bounds, (0.1, 0.1), (0.7, 0.7), (Circle((0.5, 0.5), 0.1),), occupancy=grid)
    types = {numba.typeof(w.checker().geometry) for w in (shapes, on_map, both)}
    assert len(types) == 1


def test_read_only_grid_arrays_are_accepted():
    blocked = np.zeros((6, 6), dtype=bool)
    blocked[3, 3] = True
    blocked.setflags(write=False)
    grid = OccupancyGrid(blocked, 0.5)
    grid.blocked.setflags(write=False)
    checker = World.from_grid(grid, (0.1, 0.1), (2.9, 2.9)).checker()
    assert list(checker.points_free([[1.75, 1.75], [0.2, 0.2]])) == [False, True]
