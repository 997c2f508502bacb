"""Independent checks of paths between poses: the exact curve re-traced at
1 mm from the segments a planner reports, its footprint against the world's
shapes with shapely, and the curvature bound."""

import math

import numpy as np
import shapely

from helpers import shapely_of
from navlab.sampling.curves import CurvePath
from navlab.world.shapes import Circle


def retrace(result):
    """The exact path from the segments the planner reports, traced at 1 mm."""
    start = tuple(result.params["start"])
    path = CurvePath(start, result.stats["word"], tuple(result.stats["segments"]), result.params["turning_radius"])
    return path, path.sample(0.001)[0]


def footprints(world, poses):
    v = np.asarray(world.footprint.points, float)
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    xs = poses[:, :1] + c * v[:, 0] - s * v[:, 1]
    ys = poses[:, 1:2] + s * v[:, 0] + c * v[:, 1]
    return shapely.polygons(np.stack([xs, ys], axis=-1))


def assert_clear_of_the_world(world, poses):
    """No footprint along ``poses`` touches an obstacle or leaves the bounds (shapely; touching counts)."""
    shapes = footprints(world, poses)
    b = world.bounds
    assert shapely.covered_by(shapes, shapely.box(b.xmin, b.ymin, b.xmax, b.ymax)).all()
    for o in world.obstacles:
        if isinstance(o, Circle):
            assert (shapely.distance(shapes, shapely_of(o)) > o.radius).all()
        else:
            assert not shapely.intersects(shapes, shapely_of(o)).any()


def assert_curvature(poses, radius):
    """Between 1 mm samples, the chord over the heading change never implies a radius below ``radius``."""
    steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
    turn = np.abs((np.diff(poses[:, 2]) + math.pi) % (2 * math.pi) - math.pi)
    arcs = (turn > 1e-12) & (steps > 0)
    assert (steps[arcs] / (2 * np.sin(turn[arcs] / 2)) >= radius * (1 - 1e-6)).all()
