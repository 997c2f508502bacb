"""Exact distance and collision kernels, compiled with numba.

Obstacles are packed into flat arrays (a *geometry tuple*) that compiled
planner loops receive directly. Every world — shapes, an occupancy map, or
both — packs into the same tuple type, so each kernel compiles once:

``(circles, rects, poly_verts, poly_offsets, poly_boxes, (params, cells, gaps))``

- ``circles``: (nc, 3) ``x, y, r + robot_radius`` (already inflated)
- ``rects``: (nr, 4) ``xmin, ymin, xmax, ymax`` (not inflated)
- ``poly_verts``: (nv, 2) all polygon vertices, polygon k owning rows
  ``poly_offsets[k]:poly_offsets[k + 1]``
- ``poly_boxes``: (np, 4) polygon bounding boxes grown by the robot radius
- ``params``: float slots ``P_*`` below: ``robot_radius**2``, the bounds, and
  the map's frame (origin, yaw, resolution, robot radius in cells)
- ``cells``: (H, W) uint8 map codes, indexed ``[y, x]``: ``BLOCKED``
  (occupied, or unknown unless allowed), ``SURFACE`` (blocked with a free
  4-neighbour), or for a free cell ``FIRST_FREE - 1 + d`` where ``d`` is its
  chessboard distance in cells to the nearest blocked cell (capped at 254:
  a lower bound is all the walk needs); (0, 0) without a map. One byte per
  cell keeps a 1000 x 1000 map in 1 MB of cache.
- ``gaps``: (H, W) uint8, how many cells to the right along its row the next
  ``SURFACE`` cell is (0 on one; capped at 255), so exact tests near a wall
  step from surface cell to surface cell instead of visiting every cell.

The map part sits in one nested slot so the first five slots keep the
layout they always had (ray casting unpacks them).

A point or segment collides with an obstacle when its exact Euclidean
distance to the (un-inflated) obstacle is at most the robot radius: it is
free only when the distance *exceeds* the radius, so at radius 0 touching
counts as collision (obstacles are closed sets) for circles, rectangles,
polygons and map cells alike. Nothing is discretised: segment–circle,
segment–rectangle, segment–polygon and segment–cell-square distances are
computed analytically, so a valid edge keeps clearance > robot radius along
its whole length. Points outside the bounds, or outside the map's (possibly
rotated) rectangle, are never free.

Maps: a segment is walked in the grid frame (cell units). Where the
chessboard distance transform proves the robot disc is at least half a cell
from every blocked square, the walk jumps ahead by that proven margin (sphere
tracing); near a surface it tests a short window of the segment exactly
against the blocked squares around it. Only ``SURFACE`` cells are tested:
a segment that reaches the blocked region's interior must cross its surface,
and the nearest point of the region lies on it. So a check costs a few jumps
in open space plus exact square tests where the segment passes a wall —
independent of the map's size. The chessboard transform (two passes, exact
for that metric) is a valid lower bound on Euclidean clearance and costs a few
milliseconds for 10⁶ cells, so the checker needs no cache that could go stale.

The finite range :mod:`navlab.limits` enforces at the input boundary keeps
every squared distance finite: kernels reject a point outside the bounds
before any square is formed.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from .shapes import Circle, Polygon, Rectangle

# Float parameter slots of the geometry tuple's ``params``.
P_R2, P_XMIN, P_XMAX, P_YMIN, P_YMAX = range(5)
P_HAS_MAP, P_OX, P_OY, P_COS, P_SIN, P_RES, P_RC, P_ANY_BLOCKED = range(5, 13)
N_PARAMS = 13
# Map cell codes: blocked below FIRST_FREE; a free cell stores 1 + its chessboard distance.
BLOCKED, SURFACE, FIRST_FREE = 0, 1, 2
_MAX_CODE = 255
#: [cells] the walk jumps ahead only when it can prove at least this much room
SKIP_MIN = 0.5
#: [cells] length of a segment window tested exactly near a surface
WINDOW = 8.0
#: [cells] spacing of the look-ups that reject a colliding segment early, and their most
PROBE_SPACING = 4.0
MAX_PROBES = 32
_HALF_DIAGONAL = 0.7071067811865476 + 1e-12  # [cells] centre-to-corner of a cell, rounded up


def pack_geometry(obstacles, robot_radius: float, bounds_array: np.ndarray, occupancy=None,
                  allow_unknown: bool = False):
    """Pack shapes (and optionally an occupancy grid) into the geometry tuple.

    Parameters
    ----------
    obstacles : sequence of Circle, Rectangle, Polygon
    robot_radius : float
        Metres; every obstacle and blocked cell is inflated by it.
    bounds_array : ndarray
        ``[xmin, xmax, ymin, ymax]``.
    occupancy : OccupancyGrid, optional
        Only ``blocked``, ``unknown``, ``resolution``, ``origin`` are read.
    allow_unknown : bool
        Treat the grid's unknown cells as free.
    """
    circles = [(*o.center, o.radius + robot_radius) for o in obstacles if isinstance(o, Circle)]
    rects = [(*o.min, *o.max) for o in obstacles if isinstance(o, Rectangle)]
    polys = [np.asarray(o.points, dtype=float) for o in obstacles if isinstance(o, Polygon)]
    verts = np.concatenate(polys) if polys else np.empty((0, 2))
    offsets = np.cumsum([0] + [len(p) for p in polys]).astype(np.int64)
    boxes = np.array(
        [(p[:, 0].min() - robot_radius, p[:, 1].min() - robot_radius,
          p[:, 0].max() + robot_radius, p[:, 1].max() + robot_radius) for p in polys]
    ).reshape(-1, 4)
    params = np.zeros(N_PARAMS)
    params[P_R2] = robot_radius**2
    params[P_XMIN:P_YMAX + 1] = bounds_array
    if occupancy is None:
        cells = np.zeros((0, 0), dtype=np.uint8)
        gaps = np.zeros((0, 0), dtype=np.uint8)
    else:
        cells = pack_map(occupancy, allow_unknown)
        gaps = surface_gaps(cells)
        params[P_ANY_BLOCKED] = float(np.any(cells < FIRST_FREE))
        ox, oy, yaw = (float(v) for v in occupancy.origin)
        res = float(occupancy.resolution)
        params[P_HAS_MAP] = 1.0
        params[P_OX], params[P_OY] = ox, oy
        # an unrotated map keeps cos = 1, sin = 0 exactly, so its frame change is exact
        params[P_COS], params[P_SIN] = (1.0, 0.0) if yaw == 0.0 else (math.cos(yaw), math.sin(yaw))
        params[P_RES] = res
        params[P_RC] = robot_radius / res
    return (
        np.asarray(circles, dtype=float).reshape(-1, 3),
        np.asarray(rects, dtype=float).reshape(-1, 4),
        np.ascontiguousarray(verts, dtype=float),
        offsets,
        np.ascontiguousarray(boxes, dtype=float),
        (params, cells, gaps),
    )


def pack_map(occupancy, allow_unknown: bool = False):
    """The map's cell codes (see the module doc)."""
    blocked = np.array(occupancy.blocked, dtype=bool)  # a private, writable copy
    if not allow_unknown and occupancy.unknown is not None:
        blocked = blocked | np.asarray(occupancy.unknown, dtype=bool)
    blocked = np.ascontiguousarray(blocked)
    # a blocked cell with a free 4-neighbour inside the map is on the surface
    free = ~blocked
    touches = np.zeros_like(blocked)
    touches[1:, :] |= free[:-1, :]
    touches[:-1, :] |= free[1:, :]
    touches[:, 1:] |= free[:, :-1]
    touches[:, :-1] |= free[:, 1:]
    cheb = chessboard_transform(blocked)
    cells = (np.minimum(cheb, _MAX_CODE - FIRST_FREE + 1) + (FIRST_FREE - 1)).astype(np.uint8)
    cells[blocked] = BLOCKED
    cells[blocked & touches] = SURFACE
    return cells


@njit(cache=True)
def surface_gaps(cells):
    """Cells to the next ``SURFACE`` cell at or right of each cell in its row (≤ 255)."""
    h, w = cells.shape
    gaps = np.empty((h, w), dtype=np.uint8)
    for j in range(h):
        gap = _MAX_CODE
        for i in range(w - 1, -1, -1):
            gap = 0 if cells[j, i] == SURFACE else min(gap + 1, _MAX_CODE)
            gaps[j, i] = gap
    return gaps


@njit(cache=True)
def chessboard_transform(blocked):
    """Chessboard distance (cells) from every cell to the nearest blocked one.

    Rosenfeld and Pfaltz's two-pass algorithm, exact for this metric; cells of
    a map without blocked cells get ``H + W`` (farther than anything in it).
    """
    h, w = blocked.shape
    far = h + w
    d = np.empty((h, w), dtype=np.int32)
    for j in range(h):
        for i in range(w):
            best = 0 if blocked[j, i] else far
            if best and j > 0:
                best = min(best, d[j - 1, i] + 1)
                if i > 0:
                    best = min(best, d[j - 1, i - 1] + 1)
                if i + 1 < w:
                    best = min(best, d[j - 1, i + 1] + 1)
            if best and i > 0:
                best = min(best, d[j, i - 1] + 1)
            d[j, i] = best
    for j in range(h - 1, -1, -1):
        for i in range(w - 1, -1, -1):
            best = d[j, i]
            if best and j + 1 < h:
                best = min(best, d[j + 1, i] + 1)
                if i > 0:
                    best = min(best, d[j + 1, i - 1] + 1)
                if i + 1 < w:
                    best = min(best, d[j + 1, i + 1] + 1)
            if best and i + 1 < w:
                best = min(best, d[j, i + 1] + 1)
            d[j, i] = best
    return d


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
    # free only when the distance exceeds the radius: at radius 0, touching collides
    return d2 <= r2


@njit(cache=True)
def in_bounds(x, y, geom):
    """Whether (x, y) lies in the closed bounds (False for NaN)."""
    p = geom[5][0]
    return p[P_XMIN] <= x <= p[P_XMAX] and p[P_YMIN] <= y <= p[P_YMAX]


@njit(cache=True, inline="always")
def _to_grid(x, y, params):
    """World point → grid frame in cell units (rotation about the origin by −yaw)."""
    dx = x - params[P_OX]
    dy = y - params[P_OY]
    c = params[P_COS]
    s = params[P_SIN]
    res = params[P_RES]
    return (dx * c + dy * s) / res, (dy * c - dx * s) / res


@njit(cache=True, inline="always")
def _cell_of(u, v, w, h):
    """Cell (i, j) holding grid point (u, v) of the closed map (edges clamp inward)."""
    i = min(max(int(math.floor(u)), 0), w - 1)
    j = min(max(int(math.floor(v)), 0), h - 1)
    return i, j


@njit(cache=True)
def _window_hits(u0, v0, u1, v1, rc, cells, gaps):
    """Whether segment (u0, v0)–(u1, v1) (grid frame, cell units) comes within
    ``rc`` of a surface cell's closed square (exact).

    A square within ``rc`` of the segment has its centre within
    ``near = rc + half a diagonal``: for each row only the centres within
    ``near`` of the part of the segment lying within ``near`` of the row's
    centre line are visited (a superset of that capsule's row, cheap to
    bound), stepping from surface cell to surface cell with ``gaps``.
    """
    h, w = cells.shape
    rc2 = rc * rc
    near = rc + _HALF_DIAGONAL
    near2 = near * near
    dv = v1 - v0
    du = u1 - u0
    j_lo = max(int(math.floor(min(v0, v1) - near - 0.5)), 0)
    j_hi = min(int(math.ceil(max(v0, v1) + near - 0.5)), h - 1)
    for j in range(j_lo, j_hi + 1):
        vc = j + 0.5
        # the segment's parameter range with |v - vc| <= near
        if dv != 0.0:
            ta = (vc - near - v0) / dv
            tb = (vc + near - v0) / dv
            t_lo = max(min(ta, tb), 0.0)
            t_hi = min(max(ta, tb), 1.0)
            if t_lo > t_hi:
                continue
        else:
            t_lo, t_hi = 0.0, 1.0
        ua = u0 + t_lo * du
        ub = u0 + t_hi * du
        lo = min(ua, ub) - near
        hi = max(ua, ub) + near
        # one spare cell each side absorbs rounding in the interval's ends
        i_lo = max(int(math.floor(max(lo, -2.0) - 0.5)), 0)
        i_hi = min(int(math.ceil(min(hi, w + 2.0) - 0.5)), w - 1)
        i = i_lo
        while i <= i_hi:
            gap = gaps[j, i]
            if gap != 0:
                i += gap  # no surface cell before i + gap
                continue
            i += 1
            dc2 = point_segment_dist2(i - 0.5, j + 0.5, u0, v0, u1, v1)  # cell i - 1
            if dc2 > near2:
                continue  # the square is farther than its centre less half a diagonal
            if dc2 <= rc2:
                return True  # its centre, a point of the square, is within rc
            if _hits(segment_rect_dist2(u0, v0, u1, v1, i - 1.0, float(j), float(i), j + 1.0), rc2):
                return True
    return False


@njit(cache=True)
def _probe_hits(au, av, du, dv, length, rc, cells):
    """Whether a probe point of the segment is certainly in collision.

    Most segments a tree planner checks on a map collide (they cross a wall or
    unknown space). Points spaced ``PROBE_SPACING`` cells apart, midpoint
    first and then ever finer (bit-reversed order), are looked up: a point
    in a blocked cell, or in a cell whose chessboard distance ``d`` to a
    blocked cell has ``d·√2 ≤ rc`` (every point of the cell is then within
    ``d·√2`` of that cell's square), collides. A free segment pays one look-up
    per probe; the exact walk decides everything the probes do not.
    """
    h, w = cells.shape
    n = min(int(length / PROBE_SPACING), MAX_PROBES)
    if n < 1:
        return False
    levels = 1
    while (1 << levels) <= n:
        levels += 1
    size = 1 << levels
    rc2 = rc * rc
    for k in range(1, size):
        # bit-reversed k: 1/2, 1/4, 3/4, 1/8, ...
        r = 0
        x = k
        for _ in range(levels):
            r = (r << 1) | (x & 1)
            x >>= 1
        f = r / size
        i, j = _cell_of(au + f * du, av + f * dv, w, h)
        code = cells[j, i]
        if code < FIRST_FREE:
            return True
        d = code - (FIRST_FREE - 1)
        if code < _MAX_CODE and 2.0 * d * d <= rc2:
            return True
    return False


@njit(cache=True)
def map_segment_free(ax, ay, bx, by, params, cells, gaps):
    """Whether segment ab keeps more than the robot radius from every blocked
    cell's closed square and stays on the map (see the module doc)."""
    h, w = cells.shape
    au, av = _to_grid(ax, ay, params)
    bu, bv = _to_grid(bx, by, params)
    if not (0.0 <= au <= w and 0.0 <= av <= h and 0.0 <= bu <= w and 0.0 <= bv <= h):
        return False  # off the map (the map is convex: inside at both ends is inside throughout)
    i, j = _cell_of(au, av, w, h)
    if cells[j, i] < FIRST_FREE:
        return False
    i, j = _cell_of(bu, bv, w, h)  # a steered edge often ends in a wall: one look rejects it
    if cells[j, i] < FIRST_FREE:
        return False
    rc = params[P_RC]
    du = bu - au
    dv = bv - av
    length = math.sqrt(du * du + dv * dv)
    if _probe_hits(au, av, du, dv, length, rc, cells):
        return False
    t = 0.0
    pu, pv = au, av
    while True:
        i, j = _cell_of(pu, pv, w, h)
        fu = pu - i
        fv = pv - j
        edge = max(min(min(fu, 1.0 - fu), min(fv, 1.0 - fv)), 0.0)
        # every blocked square is ≥ d − 1 + edge away from p in L∞ (d: the cell's
        # chessboard distance; 0 on a blocked cell), hence in L2
        d = max(cells[j, i] - (FIRST_FREE - 1), 0)
        room = d - 1.0 + edge - rc
        if room >= SKIP_MIN:
            t += room * (1.0 - 1e-9)  # the open ball of radius `room` about p is clear
            if t > length:
                return True
            f = t / length
            pu, pv = au + f * du, av + f * dv
            continue
        t2 = t + WINDOW
        if t2 >= length:
            return not _window_hits(pu, pv, bu, bv, rc, cells, gaps)
        f = t2 / length
        qu, qv = au + f * du, av + f * dv
        if _window_hits(pu, pv, qu, qv, rc, cells, gaps):
            return False
        t, pu, pv = t2, qu, qv


@njit(cache=True)
def map_clearance(px, py, params, cells):
    """Distance (m) from a point to the nearest blocked cell's square (0 on
    or in one, or off the map; ``inf`` when nothing is blocked)."""
    h, w = cells.shape
    u, v = _to_grid(px, py, params)
    if not (0.0 <= u <= w and 0.0 <= v <= h):
        return 0.0
    i, j = _cell_of(u, v, w, h)
    if cells[j, i] < FIRST_FREE:
        return 0.0
    if params[P_ANY_BLOCKED] == 0.0:
        return np.inf
    c = cells[j, i] - (FIRST_FREE - 1)
    best = np.inf
    # ring m of cells around (i, j) is at least m − 1 cells away: stop once that exceeds the best
    m = c
    while m < h + w:
        lower = m - 1.0
        if lower > 0.0 and lower * lower >= best:
            break
        for dj in range(-m, m + 1):
            jj = j + dj
            if jj < 0 or jj >= h:
                continue
            # the ring's top and bottom rows in full, its sides at their two ends
            step = 1 if (dj == -m or dj == m) else 2 * m
            for di in range(-m, m + 1, step):
                ii = i + di
                if 0 <= ii < w and cells[jj, ii] == SURFACE:
                    best = min(best, point_rect_dist2(u, v, float(ii), float(jj), ii + 1.0, jj + 1.0))
        m += 1
    return math.sqrt(best) * params[P_RES]


@njit(cache=True)
def segment_free(ax, ay, bx, by, geom):
    """Whether segment ab (a point when a == b) keeps clearance everywhere."""
    circles, rects, verts, offsets, boxes, frame = geom
    params, cells, gaps = frame
    r2 = params[P_R2]
    if not (in_bounds(ax, ay, geom) and in_bounds(bx, by, geom)):
        return False
    for k in range(circles.shape[0]):
        cr = circles[k, 2]
        if point_segment_dist2(circles[k, 0], circles[k, 1], ax, ay, bx, by) <= cr * cr:
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
    if params[P_HAS_MAP] != 0.0:
        return map_segment_free(ax, ay, bx, by, params, cells, gaps)
    return True


@njit(cache=True)
def clearance(px, py, geom):
    """Distance from a point to the nearest (un-inflated) obstacle surface
    (0 inside an obstacle or off the map; ``inf`` with no obstacles)."""
    circles, rects, verts, offsets, boxes, frame = geom
    params, cells, _ = frame
    r = np.sqrt(params[P_R2])
    best = np.inf
    for k in range(circles.shape[0]):
        d = np.hypot(px - circles[k, 0], py - circles[k, 1]) - (circles[k, 2] - r)
        best = min(best, max(d, 0.0))
    for k in range(rects.shape[0]):
        best = min(best, np.sqrt(point_rect_dist2(px, py, rects[k, 0], rects[k, 1], rects[k, 2], rects[k, 3])))
    for k in range(offsets.shape[0] - 1):
        best = min(best, np.sqrt(segment_polygon_dist2(px, py, px, py, verts, offsets[k], offsets[k + 1])))
    if params[P_HAS_MAP] != 0.0:
        best = min(best, map_clearance(px, py, params, cells))
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
