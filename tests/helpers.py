"""Independent geometry helpers for tests (shapely, not navlab's kernels)."""

import numpy as np
import shapely

from navlab.world.shapes import Circle, Rectangle


def shapely_of(obstacle):
    """Independent geometry for the same obstacle (shapely, not navlab's kernels)."""
    if isinstance(obstacle, Circle):
        return shapely.Point(obstacle.center)
    if isinstance(obstacle, Rectangle):
        return shapely.box(*obstacle.min, *obstacle.max)
    return shapely.Polygon(obstacle.points)


def true_clearance(world, geometry):
    """Exact distance from a shapely geometry to the nearest obstacle surface."""
    best = np.inf
    for o in world.obstacles:
        d = shapely.distance(geometry, shapely_of(o))
        if isinstance(o, Circle):
            d -= o.radius
        best = min(best, d)
    return best
