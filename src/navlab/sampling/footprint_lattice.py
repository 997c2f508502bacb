"""A robot's footprint on an occupancy grid for heading-aware planners:
certified collision checks of poses and of Dubins / Reeds–Shepp curves.

Shared by Hybrid A* (:mod:`navlab.grid.hybrid_astar`) and the SE(2) trees
(:mod:`navlab.sampling.se2_tree`). For every heading bin the cells a
footprint can touch are precomputed (:class:`Lattice`); a pose is free when
none of its bin's cells, offset to its cell, is blocked. The cells are those
of the footprint grown by one cell diagonal (the pose may lie anywhere in its
cell), by ``δ/2`` (curves are traced at poses no more than δ apart for any
footprint point, so the union covers the motion between them) and by
``R·sin(Δθ/2)`` (any heading within the bin; R the circumscribed radius), so
a curve found free never overlaps a blocked cell. The check is conservative
by at most ``√2·res + δ/2 + R·sin(Δθ/2)``. :func:`first_overlap` is the
independent re-check with shapely.
"""

from __future__ import annotations

import contextlib
import functools
import math
import threading
from typing import Optional, Tuple

import numpy as np
from shapely.geometry import Point, Polygon

from ..errors import ParameterError
from ..jit import njit
from ..limits import check_length, check_memory, shown
from ..world.footprint_collision import pose_grid_overlap
from .curves import NOP, STRAIGHT, advance, trace_word


_FOOTPRINT_FORMS = "footprint must be a disc's radius [m] or 3 or more (x, y) vertices in body coordinates, [[x, y], ...]"


def robot_outline(footprint=None, robot_radius: Optional[float] = None) -> Tuple[np.ndarray, float]:
    """The robot's outline in body coordinates: ``(vertices (K, 2), 0.0)`` for a
    polygon ``footprint`` ((K, 2) vertices, or a Footprint), or ``(empty, radius)``
    for a disc (``footprint`` a number or a disc Footprint, or ``robot_radius``;
    a point robot when both are None)."""
    if footprint is not None and robot_radius is not None:
        raise ParameterError("give footprint or robot_radius, not both")
    if isinstance(footprint, (int, float, np.integer, np.floating)) and not isinstance(footprint, bool):
        # a number is a disc's radius, as for navlab.plan and a world file's footprint
        return np.empty((0, 2)), check_length("footprint", footprint)
    if footprint is not None and hasattr(footprint, "vertices"):  # navlab.world.footprint.Footprint
        if footprint.vertices is None:
            return np.empty((0, 2)), check_length("footprint radius", footprint.radius)
        footprint = footprint.vertices
    if footprint is None:
        return np.empty((0, 2)), check_length("robot_radius", 0.0 if robot_radius is None else robot_radius)
    try:
        vertices = np.asarray(footprint, dtype=float)
    except (TypeError, ValueError, OverflowError):  # (OverflowError: a vertex of 10**400)
        raise ParameterError(f"{_FOOTPRINT_FORMS}, got {shown(footprint)}") from None
    if vertices.ndim != 2 or vertices.shape[1] != 2 or len(vertices) < 3:
        got = shown(footprint) if vertices.ndim == 0 else f"shape {vertices.shape}"
        raise ParameterError(f"{_FOOTPRINT_FORMS}, got {got}")
    if not np.isfinite(vertices).all():
        raise ParameterError(f"footprint vertices must be finite numbers [m], got {shown(vertices.tolist())}")
    _check_polygon(tuple(map(tuple, vertices.tolist())))
    return vertices, 0.0


@functools.lru_cache(maxsize=64)
def _check_polygon(vertices: Tuple[Tuple[float, float], ...]) -> None:
    """Raise unless the outline is a simple polygon covering the origin; cached, as a robot
    plans with one outline many times and shapely's validity test is a good part of a small query."""
    poly = Polygon(vertices)
    if not poly.is_valid or poly.area <= 0:
        raise ParameterError("footprint must be a simple polygon (its edges must not cross)")
    if not poly.covers(Point(0.0, 0.0)):
        raise ParameterError("footprint must contain the robot's origin (0, 0)")


@njit(cache=True)
def _near_outline(px: float, py: float, vertices: np.ndarray, disc: float, margin: float) -> bool:
    """Whether point (px, py) lies within ``margin`` of the outline (inside counts)."""
    if vertices.shape[0] == 0:
        return px * px + py * py <= (disc + margin) ** 2
    inside = False
    k = vertices.shape[0]
    near = margin * margin
    for i in range(k):
        ax, ay = vertices[i, 0], vertices[i, 1]
        bx, by = vertices[(i + 1) % k, 0], vertices[(i + 1) % k, 1]
        ex, ey = bx - ax, by - ay
        t = ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)
        t = min(1.0, max(0.0, t))
        dx, dy = px - ax - t * ex, py - ay - t * ey
        if dx * dx + dy * dy <= near:
            return True  # within the margin of this edge: inside or not, the answer
        if (ay > py) != (by > py) and px < ax + (py - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


@njit(cache=True)
def _cells_touched(vertices: np.ndarray, disc: float, reach: float, poses: np.ndarray, margin: float,
                   res: float) -> np.ndarray:
    """Offsets (dx, dy) of the cells, relative to the cell whose centre is the
    origin, with a centre within ``margin`` of the outline at any of ``poses``.

    Each pose reads only the cells of its own box of half-width ``reach + margin``
    (a cell outside it fails the disc test below for that pose anyway), and a centre
    outside the outline's bounding box grown by the margin is more than the margin from
    the outline, so it is passed over without the edge loop (grown by a further 1e-9 of
    ``far``, so rounding at the boundary leaves the answer to the edge loop, as before)."""
    far = reach + margin
    span = int(math.ceil((far + np.abs(poses[:, :2]).max()) / res)) + 1
    size = 2 * span + 1
    hit = np.zeros((size, size), dtype=np.bool_)
    local = np.empty(2)
    slack = margin + 1e-9 * far
    if vertices.shape[0]:
        box_lo_x, box_hi_x = vertices[:, 0].min() - slack, vertices[:, 0].max() + slack
        box_lo_y, box_hi_y = vertices[:, 1].min() - slack, vertices[:, 1].max() + slack
    else:
        box_lo_x, box_lo_y, box_hi_x, box_hi_y = -disc - slack, -disc - slack, disc + slack, disc + slack
    # the body-frame box's centre and half sizes: at each pose, its world-frame bounding box bounds the
    # loops more tightly than the disc alone (a 4.3 x 2 m car: 2-4x fewer cells visited, the same cells hit)
    mid_x, mid_y = 0.5 * (box_lo_x + box_hi_x), 0.5 * (box_lo_y + box_hi_y)
    half_x, half_y = 0.5 * (box_hi_x - box_lo_x), 0.5 * (box_hi_y - box_lo_y)
    for p in range(poses.shape[0]):
        c, s = math.cos(poses[p, 2]), math.sin(poses[p, 2])
        cx, cy = poses[p, 0] + c * mid_x - s * mid_y, poses[p, 1] + s * mid_x + c * mid_y
        ex, ey = abs(c) * half_x + abs(s) * half_y, abs(s) * half_x + abs(c) * half_y
        lo_x = max(0, int(math.floor((max(cx - ex, poses[p, 0] - far)) / res)) + span - 1)
        hi_x = min(size, int(math.ceil((min(cx + ex, poses[p, 0] + far)) / res)) + span + 2)
        lo_y = max(0, int(math.floor((max(cy - ey, poses[p, 1] - far)) / res)) + span - 1)
        hi_y = min(size, int(math.ceil((min(cy + ey, poses[p, 1] + far)) / res)) + span + 2)
        for iy in range(lo_y, hi_y):
            for ix in range(lo_x, hi_x):
                if hit[iy, ix]:
                    continue
                # the cell centre in the body frame of this pose
                wx, wy = (ix - span) * res - poses[p, 0], (iy - span) * res - poses[p, 1]
                local[0], local[1] = c * wx + s * wy, -s * wx + c * wy
                if local[0] * local[0] + local[1] * local[1] > far ** 2 or not \
                        (box_lo_x <= local[0] <= box_hi_x and box_lo_y <= local[1] <= box_hi_y):
                    continue
                if _near_outline(local[0], local[1], vertices, disc, margin):
                    hit[iy, ix] = True
    ys, xs = np.nonzero(hit)
    out = np.empty((xs.shape[0], 2), dtype=np.int64)
    out[:, 0] = xs - span
    out[:, 1] = ys - span
    return out


@njit(cache=True)
def _ends_table(theta0, step, bins, prim_kind, prim_len, radius, ds):
    """Per (bin, primitive) the primitive's end relative to its start (dx, dy [m]) and per
    primitive the bins it turns, traced as :func:`trace_word` traces it from every bin's heading
    (the search adds them to poses, so they are as exact as a trace)."""
    nprim = prim_kind.shape[0]
    dx, dy = np.empty((bins, nprim)), np.empty((bins, nprim))
    dbin = np.empty(nprim, dtype=np.int64)
    for b in range(bins):
        theta = theta0 + b * step
        for j in range(nprim):
            # trace_word's last pose, computed as it computes it (the segment's length times its
            # pieces over its pieces, which need not round back to the length), without the poses
            pieces = max(1, int(math.ceil(abs(prim_len[j]) / ds)))
            x, y, t = advance(0.0, 0.0, theta, prim_kind[j], prim_len[j] * pieces / pieces, radius)
            dx[b, j], dy[b, j] = x, y
            dbin[j] = round((t - theta) / step)
    return dx, dy, dbin


@njit(cache=True)
def swept_group(flat, used, lo, hi, b, j, vertices, disc, reach, theta0, step, bins, prim_kind, prim_len, radius,
                ds, margin, res):
    """Make sure the cells primitive ``j`` sweeps from bin ``b`` are listed: ``flat[lo[k]:hi[k]]``,
    k = b·nprim + j, the cells :func:`_cells_touched` gives along the traced primitive, outermost
    first (:func:`_outermost_first`). Groups are built the first time a search asks (a query
    touches a few of the bins), appended to ``flat`` (``used`` rows filled; grown when full).
    Returns ``(flat, used)``.

    A quarter turn maps cells onto cells, so when ``bins`` is a multiple of 4
    only the first quarter of the bins is traced: bin ``b + q·bins/4`` is bin
    ``b`` turned q quarter turns, its cells (dx, dy) → (−dy, dx) q times (the
    outline, the primitive and the margin turn with it)."""
    nprim = prim_kind.shape[0]
    k = b * nprim + j
    if lo[k] >= 0:
        return flat, used
    traced = bins // 4 if bins % 4 == 0 else bins
    base, turns = b % traced, b // traced
    kb = base * nprim + j
    if lo[kb] < 0:
        kinds, lengths = np.empty(1, dtype=np.int64), np.empty(1)
        kinds[0], lengths[0] = prim_kind[j], prim_len[j]
        poses, _ = trace_word(0.0, 0.0, theta0 + base * step, kinds, lengths, radius, ds)
        flat, used = _appended(flat, used, lo, hi, kb, _outermost_first(
            _cells_touched(vertices, disc, reach, poses, margin, res)))
    if turns > 0:
        cells = flat[lo[kb]:hi[kb]].copy()
        for _ in range(turns):
            cells = _quarter_turned(cells)
        flat, used = _appended(flat, used, lo, hi, k, cells)
    return flat, used


@njit(cache=True)
def _appended(flat, used, lo, hi, k, cells):
    """``cells`` appended to ``flat`` as group k; (flat, used) after it."""
    n = cells.shape[0]
    if used + n > flat.shape[0]:
        grown = np.empty((max(2 * flat.shape[0], used + n), 2), dtype=np.int64)
        grown[:used] = flat[:used]
        flat = grown
    flat[used:used + n] = cells
    lo[k], hi[k] = used, used + n
    return flat, used + n


@njit(cache=True)
def _outermost_first(cells: np.ndarray) -> np.ndarray:
    """Cell offsets sorted by distance from the origin's cell, farthest first (ties in their order):
    a check can stop at the first offset nearer than the nearest blocked cell (Hybrid A*'s search),
    and a blocked cell is usually met near the outline, so a failing check ends sooner."""
    # a stable counting sort on the whole squared lengths, farthest first: numba's mergesort took 11 us
    # of a swept group's 30 for 180 cells
    n = cells.shape[0]
    key = cells[:, 0] * cells[:, 0] + cells[:, 1] * cells[:, 1]
    top = key.max() if n else 0
    start = np.zeros(top + 2, dtype=np.int64)  # start[top - k + 1]: where squared length k goes
    for i in range(n):
        start[top - key[i] + 1] += 1
    for k in range(1, top + 2):
        start[k] += start[k - 1]
    out = np.empty_like(cells)
    for i in range(n):
        slot = start[top - key[i]]
        start[top - key[i]] += 1
        out[slot, 0], out[slot, 1] = cells[i, 0], cells[i, 1]
    return out


@njit(cache=True)
def _quarter_turned(cells: np.ndarray) -> np.ndarray:
    """Cell offsets turned a quarter turn counter-clockwise about the origin's cell."""
    out = np.empty_like(cells)
    out[:, 0] = -cells[:, 1]
    out[:, 1] = cells[:, 0]
    return out


@njit(cache=True)
def _pose_table(vertices, disc, reach, theta0, step, bins, margin, res):
    """Per bin, the cells :func:`_cells_touched` gives for the outline at the bin's heading, outermost
    first (:func:`_outermost_first`: :func:`_pose_free_near` stops at the first cell nearer than the
    nearest blocked one; quarter turns as in :func:`swept_group`, which keep the order), packed
    (:func:`_packed`)."""
    traced = bins // 4 if bins % 4 == 0 else bins
    groups = []
    pose = np.zeros((1, 3))
    for b in range(bins):
        if b < traced:
            pose[0, 2] = theta0 + b * step
            groups.append(_outermost_first(_cells_touched(vertices, disc, reach, pose, margin, res)))
        else:
            groups.append(_quarter_turned(groups[b - traced]))
    return _packed(groups)


@njit(cache=True)
def _packed(groups):
    """Ragged lists of (K_i, 2) offsets as (flat offsets, start index per group + end)."""
    starts = np.zeros(len(groups) + 1, dtype=np.int64)
    for i in range(len(groups)):
        starts[i + 1] = starts[i] + groups[i].shape[0]
    flat = np.empty((starts[-1], 2), dtype=np.int64)
    for i in range(len(groups)):
        flat[starts[i]:starts[i + 1]] = groups[i]
    return flat, starts


class Lattice:
    """The motion primitives and their swept cells for one robot outline,
    turning radius, resolution, heading count and first heading.

    Built from hashable settings only, so it is cached by content (:func:`lattice_for`).
    The primitives' ends and the per-bin pose cells are computed at once; the swept
    cells of a (bin, primitive) the first time a search needs them (:func:`swept_group`):
    a query expands a few of the bins. Hybrid A* searches one lattice per robot, with ``theta0`` 0,
    joining it from any start heading by a short arc (:func:`navlab.grid.hybrid_astar._start_nodes`).
    """

    def __init__(self, vertices: Tuple[Tuple[float, float], ...], disc: float, turning_radius: float,
                 resolution: float, bins: int, reverse: bool, theta0: float) -> None:
        verts = np.array(vertices, dtype=float).reshape(-1, 2)
        res, r = resolution, turning_radius
        self.bins, self.resolution, self.turning_radius, self.theta0, self.disc = bins, res, r, theta0, disc
        self.step = 2.0 * math.pi / bins
        chord = 2.0 * r * math.sin(self.step / 2.0)
        self.k = max(1, math.ceil(math.sqrt(2.0) * res / chord - 1e-12))  # bins turned per arc primitive
        self.length = r * self.step * self.k  # every primitive's length [m]
        reach = max(disc, float(np.hypot(*verts.T).max()) if len(verts) else 0.0)
        self.circumscribed = reach
        # δ: no footprint point moves more than this between two traced poses
        self.delta = 0.5 * res
        self.ds = self.delta / (1.0 + reach / r)
        diag = math.sqrt(2.0) * res
        directions = (1.0, -1.0) if reverse else (1.0,)
        prims = [(kind, d * self.length) for d in directions for kind in (2, 1, 3)]  # straight, left, right
        self.prim_kind = np.array([p[0] for p in prims], dtype=np.int64)
        self.prim_len = np.array([p[1] for p in prims])
        self.dx, self.dy, self.dbin = _ends_table(theta0, self.step, bins, self.prim_kind, self.prim_len, r, self.ds)
        # the primitives' swept cells, built as searches ask for them (:func:`swept_group`)
        self.vertices = verts
        self.swept_margin = diag + 0.5 * self.delta
        groups = bins * len(prims)
        self._swept_table = (np.empty((1024, 2), dtype=np.int64), 0, np.full(groups, -1, dtype=np.int64),
                             np.full(groups, -1, dtype=np.int64))
        self._swept_lock = threading.Lock()
        # per-bin outlines for any heading within the bin (analytic and smoothed segments)
        margin = diag + 0.5 * self.delta + reach * math.sin(self.step / 2.0)
        self.pose_cells, self.pose_start = _pose_table(verts, disc, reach, theta0, self.step, bins, margin, res)
        # the disc around the footprint's bounding-box centre c0 (body frame) that holds every cell a
        # pose's check reads: those cells' centres lie within margin of the outline placed at the pose's
        # cell centre (≤ diag/2 away) and bin heading (c0 moves ≤ |c0|·Δθ/2), so none is blocked when no
        # blocked cell's centre is within (c0's reach + margin + diag/2 + |c0|·Δθ/2) of c0 in the world,
        # which a distance map between cell centres (one more diag/2 for c0's own cell) tells
        if len(verts):
            c0 = 0.5 * (verts.min(axis=0) + verts.max(axis=0))
            reach0 = float(np.hypot(*(verts - c0).T).max())
        else:
            c0, reach0 = np.zeros(2), disc
        # (+1 µm: the cells are those with centres within margin, boundary included)
        self.clear_disc = np.array([c0[0], c0[1],
                                    reach0 + margin + diag + float(np.hypot(*c0)) * self.step / 2.0 + 1e-6])

    def swept_args(self):
        """The arguments :func:`swept_group` takes after the table, ``b`` and ``j``."""
        return (self.vertices, self.disc, self.circumscribed, self.theta0, self.step, self.bins, self.prim_kind,
                self.prim_len, self.turning_radius, self.ds, self.swept_margin, self.resolution)

    @contextlib.contextmanager
    def swept_cells(self):
        """``with lattice.swept_cells() as table:`` the swept-cell table ``[flat, used, lo, hi]``
        (:func:`swept_group`) to read and extend; kept when the block ends without an error.

        The lattice is cached and shared, so one user at a time appends to it (the lock), and
        the index arrays are copies until the block ends, so an error leaves the table as it was."""
        with self._swept_lock:
            flat, used, lo, hi = self._swept_table
            table = [flat, used, lo.copy(), hi.copy()]
            yield table
            self._swept_table = tuple(table)

    def swept(self, b: int, j: int) -> np.ndarray:
        """(K, 2) the cell offsets primitive ``j`` sweeps from heading bin ``b``, outermost first."""
        with self.swept_cells() as table:
            table[0], table[1] = swept_group(*table, b, j, *self.swept_args())
            k = b * len(self.prim_kind) + j
            return table[0][table[2][k]:table[3][k]].copy()


#: the finest spacing of checked poses, as a fraction of a cell: below it a curve
#: would be traced at millions of poses per metre (a turning radius far below the footprint's size)
FINEST_SPACING = 1e-3


def check_turning_scale(turning_radius: float, vertices: np.ndarray, disc: float, resolution: float, bins: int,
                        extent: float) -> None:
    """Refuse, naming ``turning_radius``, a radius the map cannot be searched at:
    so small that the footprint would be checked at poses less than
    :data:`FINEST_SPACING` of a cell apart, or so large that one heading step of
    arc is longer than the map's diagonal ``extent``. Cached by the values (every
    Hybrid A* query asks, mostly with the same robot and map)."""
    outline = tuple(map(tuple, np.asarray(vertices, float).reshape(-1, 2).tolist()))
    _turning_scale_checked(float(turning_radius), outline, float(disc), float(resolution), int(bins), float(extent))


@functools.lru_cache(maxsize=64)
def _turning_scale_checked(turning_radius: float, vertices, disc: float, resolution: float, bins: int,
                           extent: float) -> None:
    """:func:`check_turning_scale` on hashable values (a refusal is an exception, which is not cached)."""
    reach = max(disc, float(np.hypot(*np.asarray(vertices, float).reshape(-1, 2).T).max()) if len(vertices) else 0.0)
    delta = 0.5 * resolution  # as Lattice spaces poses
    smallest = reach / (delta / (FINEST_SPACING * resolution) - 1.0)
    if turning_radius < smallest:
        raise ParameterError(f"turning_radius {turning_radius:g} m is too small for a footprint reaching {reach:g} m "
                             f"on {resolution:g} m cells: at least {smallest:.3g} m (or plan on finer cells: resolution)")
    check_heading_step(turning_radius, bins, extent)


def check_heading_step(turning_radius: float, bins: int, extent: float, where: str = "the map") -> None:
    """Refuse, naming ``turning_radius``, a radius whose one heading step of arc (2π·r / bins) is longer
    than ``extent`` [m], ``where``'s diagonal: the lattice could not turn inside it."""
    step_arc = turning_radius * 2.0 * math.pi / bins
    if step_arc > extent:
        raise ParameterError(f"turning_radius {turning_radius:g} m: one heading step ({360 / bins:g}°) of arc is "
                             f"{step_arc:.3g} m, longer than {where} ({extent:.3g} m across); use a smaller radius")


@functools.lru_cache(maxsize=64)
def footprint_misfit(vertices: Tuple[Tuple[float, float], ...], disc: float, width: float, height: float,
                     resolution: float, bins: int, field: str) -> Optional[str]:
    """Why a robot fits the ``width`` × ``height`` map [m] in no orientation (its narrowest extent
    is wider than the map's longer side), or None; and a ParameterError naming ``field``
    (``footprint`` or ``robot_radius``) when its lattice of footprint cells (one list per
    heading bin, 16 bytes a cell, about three times that while built) needs more memory than
    the machine has. Both before any table is built: a 100 m disc on a 6 × 8 m map took 19 s
    and 7.7 GB to be told that its start leaves the map. Cached by the values (``vertices`` a
    tuple of pairs), as the lattice is: a robot's later queries pay nothing (the shapely buffer
    and the memory check were a quarter of a 0.5 ms query's time)."""
    if len(vertices):
        points = np.asarray(vertices, float).reshape(-1, 2)
        edges = points[:, None, :] - points[None, :, :]  # the narrowest extent lies across a hull edge's normal
        normals = np.stack([-edges[..., 1], edges[..., 0]], axis=-1).reshape(-1, 2)
        normals = normals[np.hypot(*normals.T) > 0]
        normals /= np.hypot(*normals.T)[:, None]
        spans = points @ normals.T
        narrowest = float((spans.max(axis=0) - spans.min(axis=0)).min())
        area = Polygon(points).buffer(2.0 * resolution).area  # what a pose's cells cover, with their margin
    else:
        narrowest = 2.0 * disc
        area = math.pi * (disc + 2.0 * resolution) ** 2
    if narrowest > max(width, height):
        return (f"the robot's footprint is {narrowest:.4g} m across at its narrowest, {narrowest - max(width, height):.3g}"
                f" m wider than the map's longer side ({width:.4g} x {height:.4g} m): it fits nowhere on it")
    check_memory(int(3 * 16 * bins * area / resolution ** 2),
                 f"{field}: a robot of {area:.3g} m² (with a margin of two cells) on {resolution:g} m cells with "
                 f"{bins} heading bins")
    return None


@functools.lru_cache(maxsize=16)
def lattice_for(vertices: Tuple[Tuple[float, float], ...], disc: float, turning_radius: float, resolution: float,
                bins: int, reverse: bool, theta0: float) -> Lattice:
    """:class:`Lattice` cached by its settings."""
    return Lattice(vertices, disc, turning_radius, resolution, bins, reverse, theta0)


@njit(cache=True)
def free_cells(blocked: np.ndarray, cx: int, cy: int, offsets: np.ndarray, lo: int, hi: int) -> bool:
    h, w = blocked.shape
    for i in range(lo, hi):
        x, y = cx + offsets[i, 0], cy + offsets[i, 1]
        if x < 0 or y < 0 or x >= w or y >= h or blocked[y, x]:
            return False
    return True


@njit(cache=True)
def pose_free(blocked, res, x, y, theta, theta0, step, bins, pose_cells, pose_start) -> bool:
    cx, cy = int(math.floor(x / res)), int(math.floor(y / res))
    b = int(round((theta - theta0) / step)) % bins
    return free_cells(blocked, cx, cy, pose_cells, pose_start[b], pose_start[b + 1])


@njit(cache=True)
def _pose_free_near(blocked, res, x, y, theta, theta0, step, bins, pose_cells, pose_start, clear) -> bool:
    """:func:`pose_free`'s answer, reading fewer cells with a clearance map (:func:`clearance_map`; or none,
    shape (0, 0)): the pose's cells come outermost first, and from the first one whose centre is nearer the
    pose cell's centre than the nearest blocked or off-map cell's, every remaining one is nearer too, so
    none of them can be blocked. Nearer is decided on whole squared cell distances, with the clearance
    lowered by a relative 1e-9 so its rounding cannot let a blocked cell pass."""
    cx, cy = int(math.floor(x / res)), int(math.floor(y / res))
    b = int(round((theta - theta0) / step)) % bins
    h, w = blocked.shape
    inside = 0.0
    if clear.shape[0] and 0 <= cx < w and 0 <= cy < h:
        inside = (clear[cy, cx] / res) ** 2 * (1.0 - 1e-9)
    return free_cells_near(blocked, cx, cy, pose_cells, pose_start[b], pose_start[b + 1], inside)


@njit(cache=True)
def free_cells_near(blocked, cx, cy, offsets, lo, hi, inside) -> bool:
    """:func:`free_cells`' answer (none of the cells ``offsets[lo:hi]`` from cell (cx, cy) blocked or off
    the map), reading fewer cells: the offsets come outermost first, and from the first one whose squared
    length [cells²] is below ``inside`` (the squared distance from (cx, cy) to the nearest blocked or
    off-map cell, or 0 to read them all) every remaining one is nearer too, so none can be blocked."""
    h, w = blocked.shape
    for i in range(lo, hi):
        ox, oy = offsets[i, 0], offsets[i, 1]
        if ox * ox + oy * oy < inside:
            return True
        x, y = cx + ox, cy + oy
        if x < 0 or y < 0 or x >= w or y >= h or blocked[y, x]:
            return False
    return True


def clearance_map(blocked: np.ndarray, res: float) -> np.ndarray:
    """[m] The distance from each cell's centre to the nearest blocked cell's centre,
    cells beyond the map's edge counting as blocked (0 on blocked cells): with
    :attr:`Lattice.clear_disc`, it lets :func:`curve_free` pass poses far from
    everything without reading their cells (the same answers, sooner)."""
    from scipy.ndimage import distance_transform_edt

    padded = np.zeros((blocked.shape[0] + 2, blocked.shape[1] + 2), dtype=bool)
    padded[1:-1, 1:-1] = ~blocked
    return np.ascontiguousarray(distance_transform_edt(padded)[1:-1, 1:-1] * res)


#: no clearance map: :func:`curve_free` reads every pose's cells
NO_CLEARANCE = (np.zeros((0, 0)), np.zeros(3))
#: :func:`curve_free`'s last three arguments for no exact re-check (the cell lists alone decide; a tuple of
#: constants that compiled callers unpack without allocating)
NO_EXACT = (np.zeros((0, 2)), 0.0, -1.0)


@njit(cache=True)
def clear_slack(clear, res, x, y, theta, disc) -> float:
    """How far [m] the footprint's disc centre may move from pose (x, y, θ) with
    every pose's cell check still sure to pass; negative when not known."""
    if clear.shape[0] == 0:
        return -1.0
    cx = x + math.cos(theta) * disc[0] - math.sin(theta) * disc[1]
    cy = y + math.sin(theta) * disc[0] + math.cos(theta) * disc[1]
    i, j = int(math.floor(cx / res)), int(math.floor(cy / res))
    if i < 0 or j < 0 or j >= clear.shape[0] or i >= clear.shape[1]:
        return -1.0
    return clear[j, i] - disc[2]


#: the coarse pass of :func:`curve_free` checks every this many-th pose of a segment first
COARSE_STRIDE = 16


@njit(cache=True)
def _pose_passes(blocked, res, x, y, theta, theta0, step, bins, pose_cells, pose_start, clear, outline, outline_disc,
                 exact_grow, placed, box) -> bool:
    """:func:`curve_free`'s test of one pose: the cell lists (:func:`_pose_free_near`), then, if they reject
    it and ``exact_grow`` ≥ 0, the exact test of the outline at the pose (``placed``, ``box``: its scratch)."""
    if _pose_free_near(blocked, res, x, y, theta, theta0, step, bins, pose_cells, pose_start, clear):
        return True
    return exact_grow >= 0.0 and not pose_grid_overlap(blocked, res, outline, outline_disc, x, y, theta, exact_grow,
                                                       placed, box)[0]


@njit(cache=True)
def curve_free(blocked, res, x, y, theta, kinds, lengths, radius, ds, theta0, step, bins, pose_cells,
               pose_start, clear, clear_disc, outline, outline_disc, exact_grow) -> bool:
    """Whether the footprint is free at every pose :func:`trace_word` gives
    along the word at spacing ``ds`` (exactly those poses, computed the same
    way), the last one first, then coarse to fine: every :data:`COARSE_STRIDE`-th
    pose of each segment, then the rest, so a blocked curve is usually rejected
    after a few poses. Nothing is allocated but the segments' start poses (and the
    exact test's scratch).

    With a clearance map (:func:`clearance_map`, ``clear_disc`` the lattice's
    :attr:`~Lattice.clear_disc`; or :data:`NO_CLEARANCE`), a pose whose disc
    is far from every blocked cell passes without reading its cells, and so
    do the following poses while the disc centre cannot have moved out of
    that room (a pose's centre moves at most ``(1 + |c0| / r)`` times the arc
    length between them), and a pose near one reads only its cells farther out
    than the nearest blocked cell (:func:`_pose_free_near`): exactly the same
    answers, in open space far sooner.

    With ``exact_grow`` ≥ 0, a pose the cell lists reject (they hold every cell
    within a margin of the outline anywhere in the pose's cell and heading bin,
    so they reject poses well clear of a wall) is checked again exactly: the
    outline (``outline`` (K, 2) in body coordinates, or none and the disc radius
    ``outline_disc``) at the pose itself against the blocked cells' squares grown
    by ``exact_grow`` [m] (:func:`~navlab.world.footprint_collision.pose_grid_overlap`).
    Negative: the cell lists alone decide."""
    placed = np.empty((outline.shape[0], 2))  # the exact test's scratch
    box = np.empty((4, 2))
    n = kinds.shape[0]
    start = np.empty((n, 3))
    pieces = np.zeros(n, dtype=np.int64)
    cx, cy, ct = x, y, theta
    for j in range(n):
        start[j, 0], start[j, 1], start[j, 2] = cx, cy, ct
        if kinds[j] == NOP or lengths[j] == 0.0:
            continue
        pieces[j] = max(1, int(math.ceil(abs(lengths[j]) / ds)))
        cx, cy, ct = advance(cx, cy, ct, kinds[j], lengths[j] * pieces[j] / pieces[j], radius)
    if clear_slack(clear, res, x, y, theta, clear_disc) < 0.0 and \
            not _pose_passes(blocked, res, x, y, theta, theta0, step, bins, pose_cells, pose_start, clear, outline,
                             outline_disc, exact_grow, placed, box):
        return False
    # the end first: a tree's curves mostly end in what they hit (a sample inside an obstacle)
    last = n - 1
    while last >= 0 and pieces[last] == 0:
        last -= 1
    if last >= 0:
        ex, ey, et = advance(start[last, 0], start[last, 1], start[last, 2], kinds[last], lengths[last], radius)
        if clear_slack(clear, res, ex, ey, et, clear_disc) < 0.0 and \
                not _pose_passes(blocked, res, ex, ey, et, theta0, step, bins, pose_cells, pose_start, clear, outline,
                                 outline_disc, exact_grow, placed, box):
            return False
    offset = math.hypot(clear_disc[0], clear_disc[1])
    for fine in range(2):
        for j in range(n):
            count = pieces[j]
            if count == 0:
                continue
            # the most the disc centre moves from one traced pose to the next
            move = abs(lengths[j]) / count * (1.0 if kinds[j] == STRAIGHT else 1.0 + offset / radius)
            p = 1
            while p <= count:
                if (p % COARSE_STRIDE == 0) == (fine == 1):
                    p += 1
                    continue  # coarse pass: multiples of the stride; fine pass: the others
                px, py, pt = advance(start[j, 0], start[j, 1], start[j, 2], kinds[j], lengths[j] * p / count, radius)
                room = clear_slack(clear, res, px, py, pt, clear_disc)
                if room >= 0.0:
                    if fine == 1:  # the next poses within the room pass too
                        p += 1 + int(room / move) if move > 0.0 else count
                    else:
                        p += 1
                    continue
                if not _pose_passes(blocked, res, px, py, pt, theta0, step, bins, pose_cells, pose_start, clear,
                                    outline, outline_disc, exact_grow, placed, box):
                    return False
                p += 1
    return True


#: up to this many blocked cells in a path's window, :func:`first_overlap` gives them all to shapely (the
#: distance transform that drops the unreachable ones costs more than their boxes: 0.24 ms against
#: 0.05 ms for 30 boxes on PythonRobotics' map)
FEW_CELLS = 256


def first_overlap(blocked: np.ndarray, res: float, vertices: np.ndarray, disc: float, poses: np.ndarray,
                  grow: float) -> Optional[Tuple[int, int]]:
    """The first cell (x, y) a footprint at any of ``poses`` (grid frame) overlaps,
    grown by ``grow`` metres; None when it overlaps none. Outside the map counts,
    as the cell just beyond the edge.

    Shapely decides (touching counts), on the blocked cells as squares grown by
    ``grow`` on every side: a superset of the footprint's own growth by ``grow``,
    so with poses spaced so no footprint point moves more than 2·grow between
    two, the motion between them is covered too.
    """
    import shapely

    h, w = blocked.shape
    if len(vertices):
        c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
        xs = poses[:, :1] + c * vertices[:, 0] - s * vertices[:, 1]
        ys = poses[:, 1:2] + s * vertices[:, 0] + c * vertices[:, 1]
        shapes = shapely.polygons(np.stack([xs, ys], axis=-1))
        x0, y0, x1, y1 = xs.min(), ys.min(), xs.max(), ys.max()  # the polygons' bounds: their vertices'
    else:
        shapes = shapely.buffer(shapely.points(poses[:, :2]), disc, quad_segs=16) if disc > 0 \
            else shapely.points(poses[:, :2])
        x0, y0, x1, y1 = shapely.total_bounds(shapes)
    # the map's edge as a ring of blocked cells around it
    padded = np.ones((h + 2, w + 2), dtype=bool)
    padded[1:-1, 1:-1] = blocked
    lo_x, lo_y = max(0, int((x0 - grow) // res) + 1 - 1), max(0, int((y0 - grow) // res) + 1 - 1)
    hi_x, hi_y = min(w + 1, int((x1 + grow) // res) + 2), min(h + 1, int((y1 + grow) // res) + 2)
    ys_, xs_ = np.nonzero(padded[lo_y:hi_y + 1, lo_x:hi_x + 1])
    if len(xs_) == 0:
        return None
    cx, cy = xs_ + lo_x - 1, ys_ + lo_y - 1  # cells in the grid's numbering
    # only cells a footprint can reach: its outline lies within `reach` of its pose, so a grown cell
    # it touches has its centre within reach + grow + half a cell diagonal of the pose, and so within
    # reach + grow + a cell diagonal of the pose's cell centre (+1 µm); the others are dropped before
    # shapely builds them. One distance transform from the poses' cells tells which those are; with few
    # cells it costs more than the boxes it saves, and dropping none changes no answer (a dropped cell
    # touches no footprint, and the kept ones keep their order).
    if len(xs_) > FEW_CELLS:
        from scipy.ndimage import distance_transform_edt

        reach = max(disc, float(np.hypot(*vertices.T).max()) if len(vertices) else 0.0)
        limit = reach + grow + res * math.sqrt(2.0) + 1e-6
        window = np.ones((hi_y + 1 - lo_y, hi_x + 1 - lo_x), dtype=bool)
        px = np.clip(np.floor(poses[:, 0] / res).astype(np.int64) + 1 - lo_x, 0, window.shape[1] - 1)
        py = np.clip(np.floor(poses[:, 1] / res).astype(np.int64) + 1 - lo_y, 0, window.shape[0] - 1)
        window[py, px] = False
        keep = distance_transform_edt(window)[ys_, xs_] * res <= limit
        if not keep.any():
            return None
        cx, cy = cx[keep], cy[keep]
    boxes = shapely.box(cx * res - grow, cy * res - grow, (cx + 1) * res + grow, (cy + 1) * res + grow)
    tree = shapely.STRtree(boxes)
    pairs = tree.query(shapes, predicate="intersects")
    if pairs.shape[1] == 0:
        return None
    # the first pose's lowest cell (row by row), whatever order the tree answers in
    first = pairs[1][pairs[0] == pairs[0].min()].min()
    return int(cx[first]), int(cy[first])
