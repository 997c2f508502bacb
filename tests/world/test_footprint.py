"""Footprints: validation, radii, and the simulator's exact and swept collision test against shapely."""

import math

import numpy as np
import pytest
import shapely

from navlab.grid.occupancy import OccupancyGrid
from navlab.robots import make_robot
from navlab.sim.scene import Scene
from navlab.world import Bounds, Circle, Polygon, Rectangle, World
from navlab.world.footprint import Footprint, FootprintError

JACKAL = [[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]]
L_SHAPE = [[-0.2, -0.2], [0.3, -0.2], [0.3, 0.0], [0.0, 0.0], [0.0, 0.25], [-0.2, 0.25]]


@pytest.mark.parametrize("points, words", [
    ([[0, 0], [1, 1]], "at least 3 points"),
    ([[0, 0], [0, 0], [0, 0]], "at least 3 distinct points, got 1 among its 3"),
    ([[-1, -1], [1, 1], [1, -1], [-1, 1]], "self-intersecting"),
    ([[0.1, 0.1], [1, 0.1], [1, 1]], "does not contain the robot's origin"),
    ([[-1, -1], [float("nan"), 1], [1, -1]], "finite"),
    ([[-1, -1], [1, 1], [2, 2]], "no area"),
    ("[[0, 0], [1", "cannot read"),
    ([["a", 1], [1, 2], [3, 4]], "numbers"),
])
def test_bad_footprints_are_refused_naming_what_is_wrong(points, words):
    with pytest.raises(FootprintError, match="footprint") as info:
        Footprint.from_value(points)
    assert words in str(info.value)


def test_bad_footprint_through_a_robot_names_the_field():
    with pytest.raises(ValueError, match="footprint needs at least 3 points"):
        make_robot("diff", footprint=[[0, 0], [1, 0]])


def test_radii_of_the_jackal_rectangle_by_hand():
    fp = Footprint.polygon(JACKAL)
    assert fp.inscribed_radius == pytest.approx(0.165)
    assert fp.circumscribed_radius == pytest.approx(math.hypot(0.21, 0.165))
    assert fp.area == pytest.approx(0.42 * 0.33)
    # stored counter-clockwise whichever way it was given
    assert Footprint.polygon(JACKAL[::-1]) == fp
    assert shapely.LinearRing(fp.vertices).is_ccw


def test_jackal_preset_and_discs_kept():
    jackal = make_robot("jackal")
    assert jackal.shape == Footprint.polygon(JACKAL)
    assert (jackal.max_speed, jackal.max_turn_rate) == (2.0, 4.0)
    assert jackal.max_accel > 0 and jackal.max_angular_accel > 0
    assert make_robot("diff").shape == Footprint.disc(0.105)
    assert make_robot("omni3").shape.is_disc


def test_at_many_places_the_vertices():
    fp = Footprint.polygon(JACKAL)
    placed = fp.at((1.0, 2.0, math.pi / 2))
    expected = np.array([[1 - y, 2 + x] for x, y in fp.vertices])
    np.testing.assert_allclose(placed, expected, atol=1e-12)


def _random_world(rng, n=12):
    obstacles = []
    for _ in range(n):
        kind = rng.integers(3)
        x, y = rng.uniform(-2, 2, 2)
        if kind == 0:
            obstacles.append(Circle((x, y), rng.uniform(0.02, 0.3)))
        elif kind == 1:
            w, h = rng.uniform(0.02, 0.5, 2)
            obstacles.append(Rectangle((x, y), (x + w, y + h)))
        else:
            phi = (np.arange(5) + rng.uniform(0, 0.8, 5)) * 2 * np.pi / 5
            r = rng.uniform(0.1, 0.4, 5)
            obstacles.append(Polygon(np.column_stack((x + r * np.cos(phi), y + r * np.sin(phi)))))
    return World("random", Bounds(-3, 3, -3, 3), (0, 0), (1, 1), tuple(obstacles))


def _shapely(o):
    if isinstance(o, Rectangle):
        return shapely.box(*o.min, *o.max)
    return shapely.Polygon(o.points)


def _truth(world, fp, pose):
    """Independent answer: shapely's exact distances (circles by centre distance, not a polygonised disc)."""
    body = shapely.Polygon(fp.at(pose))
    margin = math.inf
    hit = False
    for o in world.obstacles:
        if isinstance(o, Circle):
            d = body.distance(shapely.Point(o.center)) - o.radius
            deep = d < -1e-9
        else:
            d = body.distance(_shapely(o))
            deep = body.intersection(_shapely(o)).area > 1e-12
        if not deep:
            margin = min(margin, abs(d))
        hit |= d <= 0
    b = world.bounds
    out = not shapely.box(b.xmin, b.ymin, b.xmax, b.ymax).covers(body)
    return hit or out, margin


@pytest.mark.parametrize("shape", [JACKAL, L_SHAPE])
def test_footprint_at_a_pose_agrees_with_shapely(shape):
    rng = np.random.default_rng(7)
    fp = Footprint.polygon(shape)
    checked = hits = 0
    for trial in range(40):
        world = _random_world(rng)
        scene = Scene(world, 0.1, fp)
        for pose in np.column_stack((rng.uniform(-2.5, 2.5, (25, 2)), rng.uniform(-np.pi, np.pi, 25))):
            truth, margin = _truth(world, fp, pose)
            if margin < 1e-9:
                continue  # a touch within rounding: covered by the exact touching cases below
            assert scene.free(pose) == (not truth), (trial, pose)
            checked += 1
            hits += truth
    assert checked > 900 and 0.2 < hits / checked < 0.9


def test_touching_counts_and_a_hair_apart_is_free():
    fp = Footprint.polygon(JACKAL)
    # the front edge (x = 0.21 in the body) exactly on a rectangle's side, then a nanometre short of it
    world = World("touch", Bounds(-2, 2, -2, 2), (0, 0), (1, 1), (Rectangle((0.5, -0.5), (1.0, 0.5)),
                                                                   Circle((-0.5, 1.0), 0.2)))
    scene = Scene(world, 0.1, fp)
    assert not scene.free((0.5 - 0.21, 0.0, 0.0))
    assert scene.free((0.5 - 0.21 - 1e-9, 0.0, 0.0))
    # a corner exactly on the circle: the corner (0.21, 0.165) at distance 0.2 from the centre
    corner = np.array((0.21, 0.165))
    direction = np.array((0.6, 0.8))
    centre = np.array((-0.5, 1.0))
    pose = (*(centre - 0.2 * direction - corner), 0.0)
    assert not scene.free(pose)
    assert scene.free((pose[0] - 1e-9 * 0.6, pose[1] - 1e-9 * 0.8, 0.0))


def test_a_spinning_corner_cannot_pass_through_a_cylinder_between_steps():
    """At 4 rad/s for 0.2 s the Jackal turns 0.8 rad: both end poses are clear of a 6 cm post that
    the front-left corner sweeps through in between (1 cm deep)."""
    fp = Footprint.polygon(JACKAL)
    reach = fp.circumscribed_radius
    corner_angle = math.atan2(0.165, 0.21)
    mid = corner_angle + 0.4  # halfway through the turn
    cylinder = Circle(((reach + 0.02) * math.cos(mid), (reach + 0.02) * math.sin(mid)), 0.03)
    world = World("spin", Bounds(-2, 2, -2, 2), (0, 0), (1, 1), (cylinder,))
    scene = Scene(world, 0.1, fp)
    a, b = np.array((0.0, 0.0, 0.0)), np.array((0.0, 0.0, 0.8))
    assert scene.free(a) and scene.free(b)
    message = scene.hit(a, b, 0.0, 0.2, twist=(0.0, 0.0, 4.0))
    assert message is not None and "obstacle 0 (circle)" in message
    # a straight dash past it: ends clear on both sides, the body crosses it
    world = World("dash", Bounds(-2, 2, -2, 2), (0, 0), (1, 1), (Circle((0.0, 0.5), 0.075),))
    scene = Scene(world, 0.1, fp)
    a, b = np.array((-0.5, 0.5, 0.0)), np.array((0.5, 0.5, 0.0))
    assert scene.free(a) and scene.free(b)
    assert scene.hit(a, b, 0.0, 0.2, twist=(5.0, 0.0, 0.0)) is not None
    # without the cylinder in the way the same motions are free
    assert scene.hit(a + (0, 0.4, 0), b + (0, 0.4, 0), 0.0, 0.2, twist=(5.0, 0.0, 0.0)) is None


def test_footprint_on_a_map_agrees_with_shapely_squares():
    rng = np.random.default_rng(3)
    blocked = rng.random((40, 40)) < 0.04
    grid = OccupancyGrid(blocked, resolution=0.1, origin=(-2.0, -2.0, 0.0))
    fp = Footprint.polygon(L_SHAPE)
    scene = Scene(grid, 0.1, fp)
    cells = [shapely.box(-2 + 0.1 * x, -2 + 0.1 * y, -2 + 0.1 * (x + 1), -2 + 0.1 * (y + 1))
             for y, x in zip(*np.nonzero(blocked))]
    union = shapely.union_all(cells)
    area = shapely.box(-2, -2, 2, 2)
    checked = 0
    for pose in np.column_stack((rng.uniform(-1.6, 1.6, (300, 2)), rng.uniform(-np.pi, np.pi, 300))):
        body = shapely.Polygon(fp.at(pose))
        d = body.distance(union)
        if d < 1e-9 and not body.intersects(union):
            continue
        truth = body.intersects(union) or not area.covers(body)
        assert scene.free(pose) == (not truth), pose
        checked += 1
    assert checked > 250


def _drive_past(post_y, robot):
    from navlab.control import make_controller
    from navlab.sim import Simulation

    world = World("post", Bounds(-1, 3, -1, 1), (0, 0), (2.5, 0), (Circle((1.0, post_y), 0.075),),
                  meta={"obstacle_names": ["post"]})
    ctrl = make_controller("goto_waypoint", speed=1.0)
    return Simulation(world, robot, ctrl, (0, 0, 0), (2.5, 0.0), path=np.array(((0, 0), (2.5, 0.0)))).run()


def test_collided_names_the_obstacle_and_the_rectangle_is_not_a_disc():
    # the post's edge 0.02 m inside the Jackal's side: a collision, named
    hit = _drive_past(0.165 + 0.075 - 0.02, make_robot("jackal"))
    assert hit.status.name == "COLLIDED"
    assert "footprint touched obstacle 0 (circle 'post')" in hit.reason
    # 0.06 m clear of the side: the rectangle passes where its circumscribed disc (0.267 m) would not
    assert _drive_past(0.165 + 0.075 + 0.06, make_robot("jackal")).status.name == "REACHED"
    disc = make_robot("diff", radius=make_robot("jackal").shape.circumscribed_radius, max_speed=1.0)
    assert _drive_past(0.165 + 0.075 + 0.06, disc).status.name == "COLLIDED"
