"""World input checks (navlab.limits), the touching rule, and kernels at the range's edge (issue 13)."""

import math

import numpy as np
import pytest

from navlab.grid.occupancy import OccupancyGrid
from navlab.world import Bounds, Circle, Polygon, Rectangle, World

BOX = Bounds(-10, 10, -10, 10)


@pytest.mark.parametrize("field, kwargs", [
    ("start", {"start": (math.nan, 0.0)}),
    ("start", {"start": (0.0, math.inf)}),
    ("start", {"start": (1e8, 0.0)}),
    ("start", {"start": (10**400, 0)}),
    ("start", {"start": {"a": 1}}),
    ("start", {"start": "ab"}),
    ("start", {"start": (1.0, 2.0, 3.0, 4.0)}),
    ("start theta", {"start": (1.0, 2.0, math.nan)}),
    ("goal_heading", {"goal_heading": math.inf}),
    ("start", {"start": None}),
    ("goal", {"goal": (0.0, -math.inf)}),
    ("goal", {"goal": ("x", 1.0)}),
    ("robot_radius", {"robot_radius": math.nan}),
    ("robot_radius", {"robot_radius": -0.1}),
    ("robot_radius", {"robot_radius": 1e-300}),
    ("robot_radius", {"robot_radius": 10**400}),
    ("robot_radius", {"robot_radius": True}),
    ("robot_radius", {"robot_radius": "0.2"}),
    ("goal_tolerance", {"goal_tolerance": math.inf}),
    ("obstacles\\[0\\]", {"obstacles": (Circle((1e154, 0.0), 1e154),)}),
    ("obstacles\\[1\\] radius", {"obstacles": (Circle((0.0, 0.0), 1.0), Circle((0.0, 0.0), 1e-200))}),
    ("obstacles\\[0\\]", {"obstacles": (Rectangle((0.0, 0.0), (2e7, 1.0)),)}),
    ("obstacles\\[0\\]", {"obstacles": ("circle",)}),
    ("allow_unknown", {"allow_unknown": "yes"}),
])
def test_world_rejects_bad_numbers_naming_the_field(field, kwargs):
    args = dict(name="t", bounds=BOX, start=(0.0, 0.0), goal=(1.0, 1.0))
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        World(**args)


@pytest.mark.parametrize("field, bounds", [
    ("bounds.xmin", (math.nan, 1, 0, 1)),
    ("bounds.xmax", (0, math.inf, 0, 1)),
    ("bounds.ymin", (0, 1, -1e8, 1)),
    ("bounds.ymax", (0, 1, 0, 10**400)),
    ("bounds.xmin", ("0", 1, 0, 1)),
    ("max > min", (1, 0, 0, 1)),
])
def test_bounds_reject_bad_numbers_naming_the_field(field, bounds):
    with pytest.raises(ValueError, match=field):
        Bounds(*bounds)


def test_numpy_numbers_are_accepted():
    w = World("t", Bounds(np.float64(0), np.int64(5), 0, 5), np.array([1, 1]), (np.float32(2), 2),
              robot_radius=np.float64(0.1))
    assert w.start == (1.0, 1.0) and w.bounds.xmax == 5.0 and w.robot_radius == 0.1


# -- one touching rule for every shape ----------------------------------------
SHAPES = {
    "circle": Circle((0.0, 0.0), 1.0),
    "rectangle": Rectangle((-1.0, -1.0), (1.0, 1.0)),
    "polygon": Polygon(((-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0))),
}


@pytest.mark.parametrize("shape", sorted(SHAPES))
@pytest.mark.parametrize("radius", [0.0, 0.5])
def test_touching_collides_for_every_shape(shape, radius):
    # each shape's surface passes through (1, 0); free only beyond the radius
    checker = World("t", BOX, (-9, -9), (9, 9), (SHAPES[shape],), robot_radius=radius).checker()
    edge = 1.0 + radius
    assert not checker.points_free([[edge, 0.0]])[0]
    assert checker.points_free([[edge + 1e-9, 0.0]])[0]
    # a vertical segment tangent at (edge, 0) and one a nanometre beyond
    assert not checker.segments_free([[edge, -0.5]], [[edge, 0.0]])[0]
    assert checker.segments_free([[edge + 1e-9, -5.0]], [[edge + 1e-9, 5.0]])[0]
    assert not checker.segments_free([[edge, -5.0]], [[edge, 5.0]])[0]


def test_touching_rule_for_a_tangent_line_at_radius_zero():
    for shape in SHAPES.values():
        checker = World("t", BOX, (-9, -9), (9, 9), (shape,)).checker()
        assert not checker.segments_free([[1.0, -5.0]], [[1.0, 5.0]])[0]  # touches at (1, 0) or along an edge
        assert checker.segments_free([[1.0 + 1e-9, -5.0]], [[1.0 + 1e-9, 5.0]])[0]


# -- kernels at the edge of the supported range -------------------------------

def test_squared_distances_do_not_overflow_at_the_range_edge():
    big = Bounds(-1e7, 1e7, -1e7, 1e7)
    world = World("big", big, (-1e7, 0.5), (1e7, 0.5), (Circle((0.0, 0.0), 1.0),))
    checker = world.checker()
    # a segment across the whole range passes straight through the circle
    assert not checker.segments_free([[-1e7, 0.5]], [[1e7, 0.5]])[0]
    assert checker.segments_free([[-1e7, 1.5]], [[1e7, 1.5]])[0]
    assert checker.clearance([[1e7, 1e7]])[0] == pytest.approx(math.hypot(1e7, 1e7) - 1.0)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, 1e300])
def test_non_finite_or_huge_queries_are_never_free(bad):
    shapes = World("t", BOX, (0, 0), (1, 1), (Circle((5.0, 5.0), 1.0),)).checker()
    grid = World.from_grid(OccupancyGrid(np.zeros((10, 10), dtype=bool), 0.5), (1, 1), (2, 2)).checker()
    for checker in (shapes, grid):
        assert not checker.points_free([[bad, 0.5]])[0]
        assert not checker.points_free([[0.5, bad]])[0]
        assert not checker.segments_free([[0.5, 0.5]], [[bad, 0.5]])[0]
        assert not checker.segments_free([[bad, bad]], [[0.5, 0.5]])[0]


def test_built_in_scenes_polygons_are_simple_by_shapely():
    # the scenes build their fixed outlines with Polygon._known_simple (no shapely at a command's start): shapely,
    # which the constructor asks, must agree that each is simple and has an area
    import shapely

    from navlab.world import SCENES

    seen = 0
    for name in SCENES.names():
        for obstacle in SCENES.get(name)().obstacles:
            if isinstance(obstacle, Polygon):
                shape = shapely.Polygon(obstacle.points)
                assert shape.is_valid and shape.area > 0, (name, obstacle.points)
                assert Polygon(obstacle.points, obstacle.motion) == obstacle  # what the constructor makes
                seen += 1
    assert seen >= 5  # clutter's five at least


def test_known_simple_reads_points_as_the_constructor_does():
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    assert Polygon._known_simple(square) == Polygon(square)
    assert Polygon._known_simple(square).points == ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))
    for bad, message in (([(0, 0), (1, 0)], "at least 3 points"), ([(0, 0), (1, math.nan), (1, 1)], "finite")):
        with pytest.raises(ValueError, match=message):
            Polygon._known_simple(bad)
    with pytest.raises(ValueError, match="not simple"):  # a bow tie from a caller: the constructor still asks shapely
        Polygon([(0, 0), (1, 1), (1, 0), (0, 1)])
