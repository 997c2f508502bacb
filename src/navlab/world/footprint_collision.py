"""Polygon footprints against obstacles, at a pose and swept along a motion.

At one pose the test is exact: the footprint polygon and an obstacle (a
circle, an axis-aligned rectangle, a polygon or a map cell, all closed sets)
collide when they share a point — an edge of one meets an edge of the other,
or one holds a vertex (or a circle's centre) of the other — so touching counts.

Swept over a time step the robot moves along an arc at a constant body twist
(and moving obstacles move uniformly). The motion is sampled at poses spaced
so that no point of the footprint moves more than ``spacing`` (default
:data:`SWEEP_SPACING`, 1 mm) relative to any obstacle between two samples,
and each sample is tested exactly. A point of the footprint travels at most
``spacing`` along a curve between two samples, so at any instant it is within
``spacing / 2`` of where it is at one of them: an overlap deeper than
``spacing / 2`` (0.5 mm) cannot be missed. A 0.15 m BARN cylinder, or any
obstacle thicker than a millimetre, cannot pass between two samples.

The bound on a footprint point's displacement over a fraction ``s`` of the
step is ``s · (|v| + |ω| · R + |u|) · dt``: ``|v|`` the centre's speed,
``R`` the circumscribed radius, ``|u|`` the fastest obstacle's speed.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from .geometry import point_in_polygon, point_rect_dist2, point_segment_dist2, segments_intersect

#: [m] largest displacement of any footprint point between two tested samples of a step
SWEEP_SPACING = 1e-3
#: the most samples one step is split into (a 20 m/s step of 0.2 s at 1 mm spacing is 4 000)
MAX_SAMPLES = 1_000_000
KIND_NONE, KIND_CIRCLE, KIND_RECT, KIND_POLY, KIND_BOUNDS, KIND_CELL = -1, 0, 1, 2, 3, 4


@njit(cache=True, inline="always")
def arc_pose(x, y, th, vx, vy, w, t):
    """The pose after ``t`` seconds at body twist (vx, vy, ω) from (x, y, θ) (exact arc)."""
    dth = w * t
    if abs(dth) < 1e-9:
        mid = th + 0.5 * dth
        c, s = math.cos(mid), math.sin(mid)
        return x + (c * vx - s * vy) * t, y + (s * vx + c * vy) * t, th + dth
    s0, c0 = math.sin(th), math.cos(th)
    s1, c1 = math.sin(th + dth), math.cos(th + dth)
    return (x + (vx * (s1 - s0) + vy * (c1 - c0)) / w, y + (vx * (c0 - c1) + vy * (s1 - s0)) / w, th + dth)


@njit(cache=True, inline="always")
def _place(body, x, y, th, out):
    c, s = math.cos(th), math.sin(th)
    for i in range(body.shape[0]):
        out[i, 0] = x + c * body[i, 0] - s * body[i, 1]
        out[i, 1] = y + s * body[i, 0] + c * body[i, 1]


@njit(cache=True)
def polygon_circle_touch(fp, cx, cy, r):
    """Whether the filled polygon ``fp`` (K, 2) and the closed disc meet."""
    k = fp.shape[0]
    if point_in_polygon(cx, cy, fp, 0, k):
        return True
    r2 = r * r
    j = k - 1
    for i in range(k):
        if point_segment_dist2(cx, cy, fp[j, 0], fp[j, 1], fp[i, 0], fp[i, 1]) <= r2:
            return True
        j = i
    return False


@njit(cache=True)
def polygon_polygon_touch(fp, verts, start, stop, dx, dy):
    """Whether the filled polygons ``fp`` and ``verts[start:stop] + (dx, dy)`` meet."""
    k = fp.shape[0]
    # an edge of one crosses or touches an edge of the other
    j = k - 1
    for i in range(k):
        m = stop - 1
        for q in range(start, stop):
            if segments_intersect(fp[j, 0], fp[j, 1], fp[i, 0], fp[i, 1], verts[m, 0] + dx, verts[m, 1] + dy,
                                  verts[q, 0] + dx, verts[q, 1] + dy):
                return True
            m = q
        j = i
    # no edges meet: one holds the other whole, or they are apart
    if point_in_polygon(fp[0, 0] - dx, fp[0, 1] - dy, verts, start, stop):
        return True
    return point_in_polygon(verts[start, 0] + dx, verts[start, 1] + dy, fp, 0, k)


@njit(cache=True)
def polygon_rect_touch(fp, xmin, ymin, xmax, ymax, box):
    """Whether the filled polygon ``fp`` meets the closed rectangle (``box`` a (4, 2) scratch array)."""
    box[0, 0], box[0, 1] = xmin, ymin
    box[1, 0], box[1, 1] = xmax, ymin
    box[2, 0], box[2, 1] = xmax, ymax
    box[3, 0], box[3, 1] = xmin, ymax
    return polygon_polygon_touch(fp, box, 0, 4, 0.0, 0.0)


@njit(cache=True)
def sample_count(vx, vy, w, dt, circumscribed, obstacle_speed, spacing):
    """Samples a step needs so no footprint point moves more than ``spacing`` between two."""
    travel = (math.hypot(vx, vy) + abs(w) * circumscribed + obstacle_speed) * dt
    n = int(math.ceil(travel / spacing))
    return min(max(n, 1), 1_000_000)


@njit(cache=True)
def sweep_first_hit(body, pose, twist, dt, first, n, circles, coff0, coff1, rects, roff0, roff1, verts, voffsets,
                    poff0, poff1, bounds):
    """The first sample of a step at which the footprint touches something.

    Samples ``k = first … n`` sit at times ``k/n · dt`` along the arc from
    ``pose`` at ``twist``; obstacle ``j`` of each kind is displaced by
    ``off0[j] + k/n · (off1[j] − off0[j])``. Returns ``(kind, row, k)``:
    ``KIND_CIRCLE``/``KIND_RECT``/``KIND_POLY`` and the obstacle's row in its
    array, ``KIND_BOUNDS`` when a vertex leaves ``bounds`` (xmin, xmax, ymin,
    ymax), or ``(-1, -1, -1)`` when every sample is free.
    """
    kc = body.shape[0]
    reach = 0.0
    for i in range(kc):
        reach = max(reach, math.hypot(body[i, 0], body[i, 1]))
    # the region the whole step can touch: sample centres' box grown by the reach
    lox, loy, hix, hiy = np.inf, np.inf, -np.inf, -np.inf
    for k in range(first, n + 1):
        x, y, _ = arc_pose(pose[0], pose[1], pose[2], twist[0], twist[1], twist[2], dt * k / n)
        lox, loy, hix, hiy = min(lox, x), min(loy, y), max(hix, x), max(hiy, y)
    lox, loy, hix, hiy = lox - reach, loy - reach, hix + reach, hiy + reach
    cand_c = np.empty(circles.shape[0], np.int64)
    nc = 0
    for j in range(circles.shape[0]):
        r = circles[j, 2]
        x0 = circles[j, 0] + min(coff0[j, 0], coff1[j, 0]) - r
        x1 = circles[j, 0] + max(coff0[j, 0], coff1[j, 0]) + r
        y0 = circles[j, 1] + min(coff0[j, 1], coff1[j, 1]) - r
        y1 = circles[j, 1] + max(coff0[j, 1], coff1[j, 1]) + r
        if x1 >= lox and x0 <= hix and y1 >= loy and y0 <= hiy:
            cand_c[nc] = j
            nc += 1
    cand_r = np.empty(rects.shape[0], np.int64)
    nr = 0
    for j in range(rects.shape[0]):
        x0 = rects[j, 0] + min(roff0[j, 0], roff1[j, 0])
        x1 = rects[j, 2] + max(roff0[j, 0], roff1[j, 0])
        y0 = rects[j, 1] + min(roff0[j, 1], roff1[j, 1])
        y1 = rects[j, 3] + max(roff0[j, 1], roff1[j, 1])
        if x1 >= lox and x0 <= hix and y1 >= loy and y0 <= hiy:
            cand_r[nr] = j
            nr += 1
    npoly = voffsets.shape[0] - 1
    cand_p = np.empty(max(npoly, 0), np.int64)
    npc = 0
    for j in range(npoly):
        a, b = voffsets[j], voffsets[j + 1]
        x0 = verts[a:b, 0].min() + min(poff0[j, 0], poff1[j, 0])
        x1 = verts[a:b, 0].max() + max(poff0[j, 0], poff1[j, 0])
        y0 = verts[a:b, 1].min() + min(poff0[j, 1], poff1[j, 1])
        y1 = verts[a:b, 1].max() + max(poff0[j, 1], poff1[j, 1])
        if x1 >= lox and x0 <= hix and y1 >= loy and y0 <= hiy:
            cand_p[npc] = j
            npc += 1
    fp = np.empty((kc, 2))
    box = np.empty((4, 2))
    for k in range(first, n + 1):
        s = k / n
        x, y, th = arc_pose(pose[0], pose[1], pose[2], twist[0], twist[1], twist[2], dt * s)
        _place(body, x, y, th, fp)
        for i in range(kc):
            if fp[i, 0] < bounds[0] or fp[i, 0] > bounds[1] or fp[i, 1] < bounds[2] or fp[i, 1] > bounds[3]:
                return KIND_BOUNDS, -1, k
        for q in range(nc):
            j = cand_c[q]
            cx = circles[j, 0] + coff0[j, 0] + s * (coff1[j, 0] - coff0[j, 0])
            cy = circles[j, 1] + coff0[j, 1] + s * (coff1[j, 1] - coff0[j, 1])
            if polygon_circle_touch(fp, cx, cy, circles[j, 2]):
                return KIND_CIRCLE, j, k
        for q in range(nr):
            j = cand_r[q]
            dx = roff0[j, 0] + s * (roff1[j, 0] - roff0[j, 0])
            dy = roff0[j, 1] + s * (roff1[j, 1] - roff0[j, 1])
            if polygon_rect_touch(fp, rects[j, 0] + dx, rects[j, 1] + dy, rects[j, 2] + dx, rects[j, 3] + dy, box):
                return KIND_RECT, j, k
        for q in range(npc):
            j = cand_p[q]
            dx = poff0[j, 0] + s * (poff1[j, 0] - poff0[j, 0])
            dy = poff0[j, 1] + s * (poff1[j, 1] - poff0[j, 1])
            if polygon_polygon_touch(fp, verts, voffsets[j], voffsets[j + 1], dx, dy):
                return KIND_POLY, j, k
    return KIND_NONE, -1, -1


@njit(cache=True)
def sweep_first_hit_grid(body, pose, twist, dt, first, n, blocked, origin, resolution):
    """:func:`sweep_first_hit` against a map's blocked cells (closed squares) and its
    edge (leaving the map is a hit). Returns ``(KIND_CELL, iy * W + ix, k)``,
    ``(KIND_BOUNDS, -1, k)`` or ``(-1, -1, -1)``."""
    kc = body.shape[0]
    h, w = blocked.shape
    c0, s0 = math.cos(origin[2]), math.sin(origin[2])
    fp = np.empty((kc, 2))
    box = np.empty((4, 2))
    for k in range(first, n + 1):
        x, y, th = arc_pose(pose[0], pose[1], pose[2], twist[0], twist[1], twist[2], dt * k / n)
        _place(body, x, y, th, fp)
        lox, loy, hix, hiy = np.inf, np.inf, -np.inf, -np.inf
        for i in range(kc):  # into the grid frame, in cells
            rx, ry = fp[i, 0] - origin[0], fp[i, 1] - origin[1]
            gx = (c0 * rx + s0 * ry) / resolution
            gy = (-s0 * rx + c0 * ry) / resolution
            fp[i, 0], fp[i, 1] = gx, gy
            lox, loy, hix, hiy = min(lox, gx), min(loy, gy), max(hix, gx), max(hiy, gy)
        if lox < 0.0 or loy < 0.0 or hix > w or hiy > h:
            return KIND_BOUNDS, -1, k
        for iy in range(max(0, int(math.floor(loy))), min(h, int(math.floor(hiy)) + 1)):
            for ix in range(max(0, int(math.floor(lox))), min(w, int(math.floor(hix)) + 1)):
                if blocked[iy, ix] and polygon_rect_touch(fp, ix, iy, ix + 1.0, iy + 1.0, box):
                    return KIND_CELL, iy * w + ix, k
    return KIND_NONE, -1, -1


#: [cells] :func:`pose_grid_overlap` widens every cell's square by this fraction of a cell on each side, so
#: rounding in the test can only report an overlap that is not there (within 1e-9 cells), never miss one
GRID_SLACK = 1e-9


@njit(cache=True)
def pose_grid_overlap(blocked, res, vertices, disc, x, y, theta, grow, outline, box):
    """Whether a footprint at pose (x, y, θ) in a grid's frame (metres from the corner of cell (0, 0))
    overlaps a blocked cell's square grown by ``grow`` [m] on every side, or leaves the map, and the
    first such cell (row by row; off the map, the ring cell just beyond the edge): (found, x, y).

    ``vertices`` (K, 2) the outline in body coordinates [m], or none and ``disc`` [m] a disc's radius
    (0: a point); ``outline`` (K, 2) and ``box`` (4, 2) are scratch. Exact up to :data:`GRID_SLACK`,
    which only ever reports an overlap that is not there."""
    h, w = blocked.shape
    k = vertices.shape[0]
    slack = GRID_SLACK * res
    reach2 = disc * disc  # the outline lies within sqrt(reach2) of (x, y)
    if k:
        c, s = math.cos(theta), math.sin(theta)
        for i in range(k):
            outline[i, 0] = x + c * vertices[i, 0] - s * vertices[i, 1]
            outline[i, 1] = y + s * vertices[i, 0] + c * vertices[i, 1]
            reach2 = max(reach2, vertices[i, 0] * vertices[i, 0] + vertices[i, 1] * vertices[i, 1])
        x0, x1 = outline[:, 0].min(), outline[:, 0].max()
        y0, y1 = outline[:, 1].min(), outline[:, 1].max()
    else:
        x0, x1, y0, y1 = x - disc, x + disc, y - disc, y + disc
    reach2 *= 1.0 + 1e-9  # rounding may only keep a square for the exact test
    # cell i's grown square [i·res − grow, (i+1)·res + grow] can meet [x0, x1] only for
    # (x0 − grow)/res − 1 ≤ i ≤ (x1 + grow)/res; one more cell each way, tested exactly, costs nothing
    lo_x = max(-1, int(math.floor((x0 - grow) / res)) - 1)
    hi_x = min(w, int(math.floor((x1 + grow) / res)) + 1)
    lo_y = max(-1, int(math.floor((y0 - grow) / res)) - 1)
    hi_y = min(h, int(math.floor((y1 + grow) / res)) + 1)
    for cy in range(lo_y, hi_y + 1):
        for cx in range(lo_x, hi_x + 1):
            if 0 <= cx < w and 0 <= cy < h and not blocked[cy, cx]:
                continue
            bx0, by0 = cx * res - grow - slack, cy * res - grow - slack
            bx1, by1 = (cx + 1) * res + grow + slack, (cy + 1) * res + grow + slack
            # squares beyond the outline's bounding box or its circle about (x, y) cannot meet it: passed
            # over before the exact test, which near a wall would otherwise run on every wall cell around
            if bx1 < x0 or bx0 > x1 or by1 < y0 or by0 > y1:
                continue
            d2 = point_rect_dist2(x, y, bx0, by0, bx1, by1)
            if d2 > reach2:
                continue
            if polygon_rect_touch(outline, bx0, by0, bx1, by1, box) if k else d2 <= disc * disc:
                return True, cx, cy
    # none of the ring's squares met: the footprint leaves the map only by lying wholly beyond
    # them (the map is a rectangle, so the outline's extremes tell); name the nearest ring cell
    if x0 <= grow + slack or y0 <= grow + slack or x1 >= w * res - grow - slack or y1 >= h * res - grow - slack:
        return True, min(max(int(math.floor(x / res)), -1), w), min(max(int(math.floor(y / res)), -1), h)
    return False, 0, 0


def twist_between(a, b, dt: float = 1.0):
    """The constant body twist that moves pose ``a`` to pose ``b`` in ``dt`` along an arc
    (the heading change taken the short way round)."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    dth = math.remainder(float(b[2] - a[2]), 2 * math.pi) if len(b) > 2 and len(a) > 2 else 0.0
    th = float(a[2]) if len(a) > 2 else 0.0
    d = np.asarray(b[:2], float) - a[:2]
    if abs(dth) < 1e-9:
        c, s = math.cos(th), math.sin(th)
        return (c * d[0] + s * d[1]) / dt, (-s * d[0] + c * d[1]) / dt, 0.0
    s0, c0 = math.sin(th), math.cos(th)
    s1, c1 = math.sin(th + dth), math.cos(th + dth)
    m = np.array([[s1 - s0, c1 - c0], [c0 - c1, s1 - s0]])
    v = np.linalg.solve(m, d) * dth
    return float(v[0]) / dt, float(v[1]) / dt, dth / dt
