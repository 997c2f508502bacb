"""Shapes onto cells: which squares of a grid an obstacle (grown by a radius) reaches.

The test is exact: analytic square-to-circle and square-to-rectangle
distances, shapely's exact distance for polygons. Used by the grid planners'
conservative rasteriser (:mod:`navlab.grid.rasterize`) and by the costmaps'
static layer (:mod:`navlab.world.costmap`).
"""

from __future__ import annotations

import math

import numpy as np


def _window(lo: float, hi: float, origin: float, res: float, n: int) -> tuple[int, int]:
    """Index range [i0, i1) of the cells overlapping [lo, hi] along one axis."""
    i0 = max(0, math.floor((lo - origin) / res) - 1)
    i1 = min(n, math.floor((hi - origin) / res) + 2)
    return i0, i1


def block_obstacles(blocked: np.ndarray, origin_xy, resolution: float, obstacles, radius: float,
                    margin: float) -> None:
    """Mark in ``blocked`` ([y, x], unrotated cells from ``origin_xy``) every
    cell whose square is within ``radius`` (+ ``margin``) of an obstacle."""
    import shapely

    from .shapes import Circle, Polygon, Rectangle

    h, w = blocked.shape
    ox, oy = origin_xy
    reach = radius + margin
    for o in obstacles:
        x0, y0, x1, y1 = o.bbox()
        i0, i1 = _window(x0 - reach, x1 + reach, ox, resolution, w)
        j0, j1 = _window(y0 - reach, y1 + reach, oy, resolution, h)
        if i0 >= i1 or j0 >= j1:
            continue
        cx0 = ox + np.arange(i0, i1) * resolution  # cell squares' edges in this window
        cy0 = oy + np.arange(j0, j1) * resolution
        cx1, cy1 = cx0 + resolution, cy0 + resolution
        if isinstance(o, Circle):
            (px, py), limit = o.center, o.radius + reach
            gx = np.maximum(np.maximum(cx0 - px, px - cx1), 0.0)
            gy = np.maximum(np.maximum(cy0 - py, py - cy1), 0.0)
            hit = np.hypot(gx[None, :], gy[:, None]) <= limit
        elif isinstance(o, Rectangle):
            gx = np.maximum(np.maximum(cx0 - o.max[0], o.min[0] - cx1), 0.0)
            gy = np.maximum(np.maximum(cy0 - o.max[1], o.min[1] - cy1), 0.0)
            hit = np.hypot(gx[None, :], gy[:, None]) <= reach
        elif isinstance(o, Polygon):
            shape = shapely.Polygon(o.points)
            shapely.prepare(shape)
            X0, Y0 = np.meshgrid(cx0, cy0)
            boxes = shapely.box(X0, Y0, X0 + resolution, Y0 + resolution)
            hit = shapely.dwithin(boxes, shape, reach)
        else:  # pragma: no cover - a new shape kind must be taught here
            raise TypeError(f"cannot rasterise obstacle {o!r}")
        blocked[j0:j1, i0:i1] |= hit
