"""Exact distance and collision kernels, compiled with numba.

Obstacles are packed into flat arrays (a *geometry tuple*) that compiled
planner loops receive directly:

``(circles, rects, poly_verts, poly_offsets, poly_boxes, params)``

- ``circles``: (nc, 3) ``x, y, r + robot_radius`` (already inflated)
- ``rects``: (nr, 4) ``xmin, ymin, xmax, ymax`` (not inflated)
- ``poly_verts``: (nv, 2) all polygon vertices, polygon k owning rows
  ``poly_offsets[k]:poly_offsets[k + 1]``
- ``poly_boxes``: (np, 4) polygon bounding boxes grown by the robot radius
- ``params``: ``[robot_radius**2, xmin, xmax, ymin, ymax]``

A point or segment collides with an obstacle when its exact Euclidean
distance to the (un-inflated) obstacle is below the robot radius; with a zero
radius, touching counts as collision (obstacles are closed sets). Nothing is
discretised: segment–circle, segment–rectangle and segment–polygon distances
are computed analytically, so a valid edge keeps clearance ≥ robot radius
along its whole length.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .shapes import Circle, Polygon, Rectangle


def pack_geometry(obstacles, robot_radius: float, bounds_array: np.ndarray):
    """Pack shapes into the geometry tuple the kernels take."""
    circles = [(*o.center, o.radius + robot_radius) for o in obstacles if isinstance(o, Circle)]
    rects = [(*o.min, *o.max) for o in obstacles if isinstance(o, Rectangle)]
    polys = [np.asarray(o.points, dtype=float) for o in obstacles if isinstance(o, Polygon)]
    verts = np.concatenate(polys) if polys else np.empty((0, 2))
    offsets = np.cumsum([0] + [len(p) for p in polys]).astype(np.int64)
    boxes = np.array(
        [(p[:, 0].min() - robot_radius, p[:, 1].min() - robot_radius,
          p[:, 0].max() + robot_radius, p[:, 1].max() + robot_radius) for p in polys]
    ).reshape(-1, 4)
    params = np.concatenate(([robot_radius**2], bounds_array)).astype(float)
    return (
        np.asarray(circles, dtype=float).reshape(-1, 3),
        np.asarray(rects, dtype=float).reshape(-1, 4),
        np.ascontiguousarray(verts, dtype=float),
        offsets,
        np.ascontiguousarray(boxes, dtype=float),
        params,
    )


@njit(cache=True, inline="always")
def point_segment_dist2(px, py, ax, ay, bx, by):
    """Squared distance from point p to segment ab."""
    dx = bx - ax
    dy = by - ay
    length2 = dx * dx + dy * dy
    t = 0.0
    if length2 > 0.0:
        t = ((px - ax) * dx + (py - ay) * dy) / length2
        if t < 0.0:
            t = 0.0
        elif t > 1.0:
            t = 1.0
    ex = ax + t * dx - px
    ey = ay + t * dy - py
    return ex * ex + ey * ey


@njit(cache=True, inline="always")
def _orient(ax, ay, bx, by, cx, cy):
    v = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if v > 0.0:
        return 1
    if v < 0.0:
        return -1
    return 0


@njit(cache=True, inline="always")
def _on_segment(ax, ay, bx, by, cx, cy):
    # c is collinear with ab: is it within ab's box?
    return min(ax, bx) <= cx <= max(ax, bx) and min(ay, by) <= cy <= max(ay, by)


@njit(cache=True)
def segments_intersect(ax, ay, bx, by, cx, cy, dx, dy):
    """Whether closed segments ab and cd share a point (orientation test)."""
    o1 = _orient(ax, ay, bx, by, cx, cy)
    o2 = _orient(ax, ay, bx, by, dx, dy)
    o3 = _orient(cx, cy, dx, dy, ax, ay)
    o4 = _orient(cx, cy, dx, dy, bx, by)
    if o1 != o2 and o3 != o4:
        return True
    if o1 == 0 and _on_segment(ax, ay, bx, by, cx, cy):
        return True
    if o2 == 0 and _on_segment(ax, ay, bx, by, dx, dy):
        return True
    if o3 == 0 and _on_segment(cx, cy, dx, dy, ax, ay):
        return True
    if o4 == 0 and _on_segment(cx, cy, dx, dy, bx, by):
        return True
    return False


@njit(cache=True)
def segment_segment_dist2(ax, ay, bx, by, cx, cy, dx, dy):
    """Squared distance between segments ab and cd (0 when they cross)."""
    if segments_intersect(ax, ay, bx, by, cx, cy, dx, dy):
        return 0.0
    d = point_segment_dist2(ax, ay, cx, cy, dx, dy)
    d = min(d, point_segment_dist2(bx, by, cx, cy, dx, dy))
    d = min(d, point_segment_dist2(cx, cy, ax, ay, bx, by))
    return min(d, point_segment_dist2(dx, dy, ax, ay, bx, by))


@njit(cache=True)
def point_in_polygon(px, py, verts, start, stop):
    """Crossing-number test (boundary points may go either way; callers
    combine it with an exact boundary distance)."""
    inside = False
    j = stop - 1
    for i in range(start, stop):
        xi, yi = verts[i, 0], verts[i, 1]
        xj, yj = verts[j, 0], verts[j, 1]
        if (yi > py) != (yj > py):
            x_cross = xi + (py - yi) * (xj - xi) / (yj - yi)
            if px < x_cross:
                inside = not inside
        j = i
    return inside


@njit(cache=True)
def point_rect_dist2(px, py, xmin, ymin, xmax, ymax):
    ex = max(xmin - px, 0.0, px - xmax)
    ey = max(ymin - py, 0.0, py - ymax)
    return ex * ex + ey * ey


@njit(cache=True)
def segment_rect_dist2(ax, ay, bx, by, xmin, ymin, xmax, ymax):
    """Squared distance from segment ab to a filled rectangle."""
    if point_rect_dist2(ax, ay, xmin, ymin, xmax, ymax) == 0.0:
        return 0.0
    d = segment_segment_dist2(ax, ay, bx, by, xmin, ymin, xmax, ymin)
    d = min(d, segment_segment_dist2(ax, ay, bx, by, xmax, ymin, xmax, ymax))
    d = min(d, segment_segment_dist2(ax, ay, bx, by, xmax, ymax, xmin, ymax))
    return min(d, segment_segment_dist2(ax, ay, bx, by, xmin, ymax, xmin, ymin))


@njit(cache=True)
def segment_polygon_dist2(ax, ay, bx, by, verts, start, stop):
    """Squared distance from segment ab to a filled simple polygon."""
    if point_in_polygon(ax, ay, verts, start, stop):
        return 0.0
    d = np.inf
    j = stop - 1
    for i in range(start, stop):
        d = min(d, segment_segment_dist2(ax, ay, bx, by, verts[j, 0], verts[j, 1], verts[i, 0], verts[i, 1]))
        if d == 0.0:
            return 0.0
        j = i
    return d


@njit(cache=True, inline="always")
def _hits(d2, r2):
    return d2 < r2 or d2 == 0.0


@njit(cache=True)
def in_bounds(x, y, geom):
    p = geom[5]
    return p[1] <= x <= p[2] and p[3] <= y <= p[4]


@njit(cache=True)
def segment_free(ax, ay, bx, by, geom):
    """Whether segment ab (a point when a == b) keeps clearance everywhere."""
    circles, rects, verts, offsets, boxes, params = geom
    r2 = params[0]
    if not (in_bounds(ax, ay, geom) and in_bounds(bx, by, geom)):
        return False
    for k in range(circles.shape[0]):
        cr = circles[k, 2]
        if point_segment_dist2(circles[k, 0], circles[k, 1], ax, ay, bx, by) < cr * cr:
            return False
    r = np.sqrt(r2)
    sxmin, sxmax = min(ax, bx), max(ax, bx)
    symin, symax = min(ay, by), max(ay, by)
    for k in range(rects.shape[0]):
        if sxmax < rects[k, 0] - r or sxmin > rects[k, 2] + r or symax < rects[k, 1] - r or symin > rects[k, 3] + r:
            continue
        if _hits(segment_rect_dist2(ax, ay, bx, by, rects[k, 0], rects[k, 1], rects[k, 2], rects[k, 3]), r2):
            return False
    for k in range(boxes.shape[0]):
        if sxmax < boxes[k, 0] or sxmin > boxes[k, 2] or symax < boxes[k, 1] or symin > boxes[k, 3]:
            continue
        if _hits(segment_polygon_dist2(ax, ay, bx, by, verts, offsets[k], offsets[k + 1]), r2):
            return False
    return True


@njit(cache=True)
def clearance(px, py, geom):
    """Distance from a point to the nearest (un-inflated) obstacle surface
    (0 inside an obstacle; ``inf`` with no obstacles)."""
    circles, rects, verts, offsets, boxes, params = geom
    r = np.sqrt(params[0])
    best = np.inf
    for k in range(circles.shape[0]):
        d = np.hypot(px - circles[k, 0], py - circles[k, 1]) - (circles[k, 2] - r)
        best = min(best, max(d, 0.0))
    for k in range(rects.shape[0]):
        best = min(best, np.sqrt(point_rect_dist2(px, py, rects[k, 0], rects[k, 1], rects[k, 2], rects[k, 3])))
    for k in range(offsets.shape[0] - 1):
        best = min(best, np.sqrt(segment_polygon_dist2(px, py, px, py, verts, offsets[k], offsets[k + 1])))
    return best


@njit(cache=True)
def segments_free_batch(a, b, geom):
    out = np.empty(a.shape[0], dtype=np.bool_)
    for i in range(a.shape[0]):
        out[i] = segment_free(a[i, 0], a[i, 1], b[i, 0], b[i, 1], geom)
    return out


@njit(cache=True)
def points_free_batch(p, geom):
    out = np.empty(p.shape[0], dtype=np.bool_)
    for i in range(p.shape[0]):
        out[i] = segment_free(p[i, 0], p[i, 1], p[i, 0], p[i, 1], geom)
    return out


@njit(cache=True)
def clearance_batch(p, geom):
    out = np.empty(p.shape[0])
    for i in range(p.shape[0]):
        out[i] = clearance(p[i, 0], p[i, 1], geom)
    return out
