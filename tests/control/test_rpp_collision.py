"""RPP's collision look-ahead is Nav2's: the footprint's outline against LETHAL cells (judged with shapely)."""

import numpy as np
import pytest
import shapely

from navlab.control import make_controller
from navlab.robots import make_robot
from navlab.sim import Simulation
from navlab.world import Bounds, Circle, World
from navlab.world.costmap import build_costmap
from navlab.world.footprint import Footprint

JACKAL = Footprint.polygon([[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]])
POST = 0.075  # [m] a BARN cylinder's radius


def _fence_with_gap(gap: float) -> World:
    """A row of touching BARN cylinders across x = 2 with one opening ``gap`` metres wide (edge to edge)."""
    ys = [y for y in np.arange(-2.4, 2.4 + 1e-9, 2 * POST) if abs(y) > gap / 2 + POST - 1e-9]
    ys += [-(gap / 2 + POST), gap / 2 + POST]
    return World("fence", Bounds(-1, 5, -2.2, 2.2), (0, 0), (4, 0), tuple(Circle((2.0, y), POST) for y in ys))


def test_collision_look_ahead_agrees_with_shapely_away_from_the_cell_rounding():
    rng = np.random.default_rng(7)
    rpp = make_controller("rpp")
    rpp.reset((5, 0), np.array(((0, 0), (5, 0))))
    checked = {True: 0, False: 0}
    for _ in range(300):
        post = Circle((rng.uniform(0.0, 1.2), rng.uniform(-0.5, 0.5)), POST)
        world = World("post", Bounds(-1, 3, -2, 2), (0, 0), (2, 0), (post,))
        rpp.set_costmap(build_costmap(world, JACKAL, inflation_radius=0.55), JACKAL)
        pose = np.array((0.0, 0.0, rng.uniform(-0.3, 0.3)))
        v, w = 0.5, rng.uniform(-1.0, 1.0)
        blocked = rpp.collision_ahead(pose, v, w, 0.5)
        # the truth: the footprint swept along the same arc (poses every 5 mm), against the disc itself
        t = np.linspace(0.0, 1.0, 101)
        th = pose[2] + w * t
        x = np.where(abs(w) > 1e-9, (np.sin(th) - np.sin(pose[2])) * v / max(abs(w), 1e-9) * np.sign(w), v * t)
        y = np.where(abs(w) > 1e-9, (np.cos(pose[2]) - np.cos(th)) * v / max(abs(w), 1e-9) * np.sign(w), 0 * t)
        sweep = shapely.union_all([shapely.Polygon(JACKAL.at(p)) for p in np.column_stack((x, y, th))])
        centre = shapely.Point(post.center)
        if sweep.intersects(centre.buffer(POST - 0.01, 64)):
            assert blocked, (post.center, pose, w)  # the body would reach 1 cm into the post
            checked[True] += 1
        elif sweep.distance(centre) - POST > 0.08:  # beyond a cell's diagonal (the post's rasterisation)
            assert not blocked, (post.center, pose, w)
            checked[False] += 1
    assert checked[True] > 30 and checked[False] > 30


@pytest.mark.parametrize("creep", [False, True])
def test_a_jackal_passes_a_gap_six_centimetres_wider_than_itself(creep):
    # 0.45 m between two cylinders: the old INSCRIBED test (the outline within 0.165 m of an obstacle) stopped here
    world = _fence_with_gap(0.45)
    robot = make_robot("jackal")
    ctrl = make_controller("rpp", creep_when_blocked=creep)
    from navlab.sim.runner import costmap_path

    path = costmap_path(world, robot, ctrl, (0, 0, 0), (4, 0))
    result = Simulation(world, robot, ctrl, (0, 0, 0), (4, 0), path=path, max_time=60).run(seed=0)
    assert result.status.name == "REACHED", result.reason
    body = shapely.union_all([shapely.Polygon(JACKAL.at(p)) for p in result.true_poses])
    posts = shapely.union_all([shapely.Point(o.center).buffer(o.radius, 64) for o in world.obstacles])
    assert body.distance(posts) > 0


def test_no_gap_narrower_than_the_jackal_is_driven_into():
    world = _fence_with_gap(0.30)  # narrower than the 0.33 m body: the costmap A* finds no way through
    robot = make_robot("jackal")
    from navlab.sim.runner import NoPathError, costmap_path

    with pytest.raises(NoPathError):
        costmap_path(world, robot, make_controller("rpp"), (0, 0, 0), (4, 0))
