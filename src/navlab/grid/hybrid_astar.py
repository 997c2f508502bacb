"""Hybrid A*: heading-aware search on an occupancy grid for car-like robots.

Dolgov, Thrun, Montemerlo and Diebel ("Path planning for autonomous vehicles
in unknown semi-structured environments", IJRR 29(5), 2010; first at the
2008 Urban Challenge workshop) search a lattice of *continuous* poses merged
per discrete state (cell, heading bin): each expansion drives three motion
primitives (straight, full left, full right at the minimum turning radius;
and the same in reverse for Reeds–Shepp motion), so every stored pose is
exactly reachable by the car. Nav2's ``SmacPlannerHybrid`` keeps the same
shape; navlab follows it:

- primitives change the heading by whole bins (72 by default, 5°): an arc
  of radius r turning k bins, k the smallest giving a chord of at least
  √2 cells, and a straight segment of the same length;
- the heuristic is the larger of the obstacle-free non-holonomic distance
  (the exact Dubins or Reeds–Shepp length, :mod:`navlab.sampling.dubins`,
  :mod:`navlab.sampling.reeds_shepp`) and the holonomic-with-obstacles
  distance (an 8-connected Dijkstra field from the goal over the cells the
  robot's inscribed circle fits in); the Reeds–Shepp length is solved only
  where the Dubins length, an upper bound on it, exceeds the field
  (:func:`_heuristic`), so the value is exact at a fraction of the cost;
- travel costs multiply a primitive's length by penalties for turning and
  reversing, and add one for changing direction (Nav2's defaults);
- an analytic expansion tries the exact Dubins/Reeds–Shepp path to the goal
  from nodes near it; the search ends when one is collision-free;
- a smoother replaces stretches of the path with shorter Dubins/Reeds–Shepp
  paths where they are collision-free, so the curvature bound 1/r holds
  exactly after smoothing.

**Collision checking is certified, not sampled.** For every start heading bin
and primitive, the cells any point of the footprint can cover while driving
the primitive are precomputed (:func:`swept_cells`): the footprint is traced at
poses no more than ``δ`` apart (no footprint point moves more than δ between
two), each copy grown by δ/2 (so the union covers the motion between samples)
and by one cell diagonal (the node's pose may lie anywhere in its cell, and a
cell is kept when any part of it can be touched). A primitive is free when
none of those cells is blocked, so a returned path never overlaps a blocked
cell; the check is conservative by at most ``√2·res + δ/2`` (δ = res/2 by
default). Analytic and smoothed segments use per-bin footprints grown also by
``R·sin(Δθ/2)`` (R the footprint's circumscribed radius), which covers any
heading within the bin. Every returned path is checked once more that way.
The footprint's cells and checks live in :mod:`navlab.sampling.footprint_lattice`,
shared with the SE(2) trees.
"""

from __future__ import annotations

import heapq
import math
import time
from typing import Any, Dict, Optional

import numpy as np
from numba import njit, types
from numba.typed import Dict as TypedDict
from shapely.geometry import Point, Polygon

from ..limits import check_length, finite_number
from ..result import Result, Status
from ..sampling import dubins, reeds_shepp
from ..sampling.curves import (LETTERS, MAX_SEGMENTS, NEGLIGIBLE, NOP, CurvePath, check_pose, check_turning_radius,
                              trace_word)
from ..sampling.footprint_lattice import (check_turning_scale, curve_free, first_overlap, free_cells, lattice_for,
                                          robot_outline)
from .occupancy import OccupancyGrid

MOTIONS = ("dubins", "reeds_shepp")
DEFAULTS = {  # Nav2 SmacPlannerHybrid's defaults where it has one
    "heading_bins": 72,
    "reverse_penalty": 2.0,
    "change_penalty": 0.0,
    "non_straight_penalty": 1.2,
    "analytic_expansion_max_length": 3.0,  # [m]
    "max_expansions": 200_000,
}
#: relative slack under which a Dubins length no longer settles that the Reeds–Shepp one is below the field
GATE_MARGIN = 1e-9


# ---------------------------------------------------------------------------
# footprint and its cells
# ---------------------------------------------------------------------------
# ---------------------------------------------------------------------------
# compiled search
# ---------------------------------------------------------------------------
@njit(cache=True)
def holonomic_field(passable: np.ndarray, gx: int, gy: int, res: float) -> np.ndarray:
    """Shortest 8-connected distances [m] from cell (gx, gy) over ``passable``
    cells (Dijkstra; diagonal steps only between two free orthogonal cells).

    Dial's bucket queue instead of a heap: buckets a little narrower than the
    shortest step (one cell), so no cell can improve another of its own bucket
    and each bucket's cells are final in any order. A step is at most √2 cells,
    so a relaxed cell lands one or two buckets ahead and three buckets, reused
    in turn, hold the whole frontier. Every cell ends at the minimum over its
    neighbours of (their distance + step), as with a heap, so the values are
    the same bit for bit.
    """
    h, w = passable.shape
    dist = np.full((h, w), np.inf)
    done = np.zeros((h, w), dtype=np.bool_)
    dist[gy, gx] = 0.0
    width = res * (1.0 - 1e-6)  # below one step even after rounding
    diag = math.sqrt(2.0) * res
    cap = 1024
    cells = np.empty((3, cap), dtype=np.int64)
    size = np.zeros(3, dtype=np.int64)
    cells[0, 0] = gy * w + gx
    size[0] = 1
    pending = 1
    bucket = 0
    while pending > 0:
        slot = bucket % 3
        i = 0
        while i < size[slot]:
            v = cells[slot, i]
            i += 1
            pending -= 1
            y, x = v // w, v % w
            if done[y, x]:  # entered again after an improvement: settled already
                continue
            done[y, x] = True
            d = dist[y, x]
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    nx, ny = x + dx, y + dy
                    if nx < 0 or ny < 0 or nx >= w or ny >= h or done[ny, nx] or not passable[ny, nx]:
                        continue
                    if dx != 0 and dy != 0 and not (passable[y, nx] and passable[ny, x]):
                        continue
                    nd = d + (diag if dx != 0 and dy != 0 else res)
                    if nd < dist[ny, nx]:
                        dist[ny, nx] = nd
                        to = int(nd / width) % 3
                        if size[to] == cap:
                            grown = np.empty((3, 2 * cap), dtype=np.int64)
                            grown[:, :cap] = cells
                            cells, cap = grown, 2 * cap
                        cells[to, size[to]] = ny * w + nx
                        size[to] += 1
                        pending += 1
        size[slot] = 0
        bucket += 1
    return dist


@njit(cache=True)
def _heuristic(field, x, y, theta, gx, gy, gtheta, radius, reverse, seg, kinds, lengths) -> float:
    """The larger of ``field`` (the holonomic distance at the node's cell) and the
    exact obstacle-free Dubins / Reeds–Shepp distance from pose (x, y, θ) to the goal.

    A Reeds–Shepp solve (44 closed forms) costs about twenty Dubins solves, and
    far from the goal the field is usually the larger. Every Dubins path is a
    Reeds–Shepp path, so the Dubins length bounds the Reeds–Shepp length from
    above: when it is no more than the field, the maximum is the field and the
    Reeds–Shepp solve is skipped. The value is the same as always solving, so
    the search expands the same nodes; the relative margin keeps rounding in
    the two closed forms from deciding.
    """
    d, a, b = dubins._normalised(x, y, theta, gx, gy, gtheta, radius)
    _, t, p, q = dubins.solve(d, a, b)
    forward = (t + p + q) * radius
    if not reverse:
        return max(field, forward)
    if forward * (1.0 + GATE_MARGIN) + GATE_MARGIN * radius <= field:
        return field
    dx, dy = gx - x, gy - y
    c, s = math.cos(theta), math.sin(theta)
    return max(field, reeds_shepp._shortest_into((c * dx + s * dy) / radius, (-s * dx + c * dy) / radius,
                                                 gtheta - theta, seg, kinds, lengths) * radius)


@njit(cache=True)
def _search(blocked, res, sx, sy, sbin, gx, gy, gtheta, theta0, step, bins, radius, reverse,
            prim_kind, prim_len, pdx, pdy, pdbin, swept, swept_start, clear, pose_cells, pose_start, ds,
            hfield, penalties, analytic_max, max_expansions, use_analytic):
    """The Hybrid A* loop. Returns (status, nodes arrays, goal node, analytic word, expansions)."""
    h, w = blocked.shape
    nprim = prim_kind.shape[0]
    cap = 1024
    nx = np.empty(cap)
    ny = np.empty(cap)
    nb = np.empty(cap, dtype=np.int64)
    ng = np.empty(cap)
    nparent = np.empty(cap, dtype=np.int64)
    nprim_of = np.empty(cap, dtype=np.int64)
    closed = np.zeros(cap, dtype=np.bool_)
    index = TypedDict.empty(key_type=types.int64, value_type=types.int64)  # discrete state -> node
    seg = np.zeros(MAX_SEGMENTS)
    akinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    alens = np.zeros(MAX_SEGMENTS)
    best_kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    best_lens = np.zeros(MAX_SEGMENTS)
    straight_pen, turn_pen, reverse_pen, change_pen = penalties[0], penalties[1], penalties[2], penalties[3]

    nx[0], ny[0], nb[0], ng[0], nparent[0], nprim_of[0] = sx, sy, sbin, 0.0, -1, -1
    count = 1
    index[(int(sy // res) * w + int(sx // res)) * bins + sbin] = 0
    heap = [(0.0, 0)]
    expansions = 0
    while heap:
        f, v = heapq.heappop(heap)
        if closed[v]:
            continue
        closed[v] = True
        expansions += 1
        x, y, b = nx[v], ny[v], nb[v]
        theta = theta0 + b * step
        # analytic expansion near the goal: the exact obstacle-free path, if it is free
        if use_analytic and math.hypot(gx - x, gy - y) <= analytic_max:
            for i in range(MAX_SEGMENTS):
                akinds[i] = NOP
                alens[i] = 0.0
            if reverse:
                dxg, dyg = gx - x, gy - y
                c, s = math.cos(theta), math.sin(theta)
                reeds_shepp._shortest_into((c * dxg + s * dyg) / radius, (-s * dxg + c * dyg) / radius,
                                           gtheta - theta, seg, best_kinds, best_lens)
                for i in range(MAX_SEGMENTS):
                    akinds[i] = best_kinds[i]
                    alens[i] = best_lens[i] * radius
            else:
                d, a, bb = dubins._normalised(x, y, theta, gx, gy, gtheta, radius)
                word, t, p, q = dubins.solve(d, a, bb)
                for i in range(3):
                    akinds[i] = dubins.WORDS[word, i]
                alens[0], alens[1], alens[2] = t * radius, p * radius, q * radius
            if curve_free(blocked, res, x, y, theta, akinds, alens, radius, ds, theta0, step, bins, pose_cells,
                           pose_start, np.zeros((0, 0)), np.zeros(3)):
                return 1, nx[:count], ny[:count], nb[:count], nparent[:count], nprim_of[:count], v, akinds, alens, \
                    expansions
        elif not use_analytic:
            if int(x // res) == int(gx // res) and int(y // res) == int(gy // res) and \
                    (b - int(round((gtheta - theta0) / step))) % bins == 0:
                return 1, nx[:count], ny[:count], nb[:count], nparent[:count], nprim_of[:count], v, akinds, alens, \
                    expansions
        if expansions >= max_expansions:
            break
        cx, cy = int(x // res), int(y // res)
        # a node whose cell has no blocked cell within the primitives' reach needs no swept-cell checks
        roomy = clear[cy, cx]
        for j in range(nprim):
            x2, y2 = x + pdx[b, j], y + pdy[b, j]
            b2 = (b + pdbin[j]) % bins
            cx2, cy2 = int(x2 // res), int(y2 // res)
            if cx2 < 0 or cy2 < 0 or cx2 >= w or cy2 >= h:
                continue
            length = abs(prim_len[j])
            cost = length * (straight_pen if prim_kind[j] == 2 else turn_pen)
            backwards = prim_len[j] < 0
            if backwards:
                cost *= reverse_pen
            if nprim_of[v] >= 0 and (prim_len[nprim_of[v]] < 0) != backwards:
                cost += change_pen
            g2 = ng[v] + cost
            key = (cy2 * w + cx2) * bins + b2
            u = index[key] if key in index else -1
            if u >= 0 and (closed[u] or ng[u] <= g2):
                continue
            # the collision check last: it is the dearest test, and it decides nothing a cheaper one rejected
            if not roomy and not free_cells(blocked, cx, cy, swept, swept_start[b * nprim + j],
                                            swept_start[b * nprim + j + 1]):
                continue
            if u < 0:
                if count == cap:
                    cap *= 2
                    nx, ny, nb, ng = _grow(nx, cap), _grow(ny, cap), _grow(nb, cap), _grow(ng, cap)
                    nparent, nprim_of, closed = _grow(nparent, cap), _grow(nprim_of, cap), _grow(closed, cap)
                u = count
                count += 1
                index[key] = u
                closed[u] = False
            nx[u], ny[u], nb[u], ng[u], nparent[u], nprim_of[u] = x2, y2, b2, g2, v, j
            h2 = _heuristic(hfield[cy2, cx2], x2, y2, theta0 + b2 * step, gx, gy, gtheta, radius, reverse,
                            seg, best_kinds, best_lens)
            heapq.heappush(heap, (g2 + h2, u))
    return 0, nx[:count], ny[:count], nb[:count], nparent[:count], nprim_of[:count], -1, akinds, alens, expansions


@njit(cache=True)
def _grow(a, cap):
    out = np.empty(cap, dtype=a.dtype)
    out[:a.shape[0]] = a
    return out


# ---------------------------------------------------------------------------
# the planner
# ---------------------------------------------------------------------------
def plan_hybrid(grid: OccupancyGrid, start, goal, turning_radius: float, motion: str = "reeds_shepp",
                footprint=None, robot_radius: Optional[float] = None,
                heading_bins: int = DEFAULTS["heading_bins"], reverse_penalty: float = DEFAULTS["reverse_penalty"],
                change_penalty: float = DEFAULTS["change_penalty"],
                non_straight_penalty: float = DEFAULTS["non_straight_penalty"],
                analytic_expansion: bool = True,
                analytic_expansion_max_length: float = DEFAULTS["analytic_expansion_max_length"],
                max_expansions: int = DEFAULTS["max_expansions"], smooth: bool = True,
                waypoint_spacing: Optional[float] = None) -> Result:
    """Plan a car-like robot's path between poses on an occupancy grid (Hybrid A*).

    Parameters
    ----------
    grid : OccupancyGrid
        Blocked (and unknown) cells are obstacles; so is everything outside it.
    start, goal : (x, y, θ)
        Poses in world coordinates [m, m, rad].
    turning_radius : float
        The robot's minimum turning radius [m].
    motion : {"reeds_shepp", "dubins"}
        Forward and reverse, or forward only.
    footprint : (K, 2) array or Footprint, optional
        The robot's outline in body coordinates [m]; or ``robot_radius`` for a disc.
    heading_bins : int
        Heading resolution (72: 5°, Nav2's default).
    reverse_penalty, change_penalty, non_straight_penalty : float
        Travel-cost factors (≥ 1 for the two multipliers; ≥ 0 for the change penalty).
    analytic_expansion : bool
        Try the exact Dubins/Reeds–Shepp path to the goal from nodes within
        ``analytic_expansion_max_length`` of it [m]. Without it the search ends
        in the goal's cell and heading bin (the path then ends there, not at the goal).
    max_expansions : int
        Give up (``FAILED``) after this many expansions.
    smooth : bool
        Shorten the path with collision-free Dubins/Reeds–Shepp shortcuts.
    waypoint_spacing : float, optional
        Spacing of the returned poses [m]; the grid's resolution by default.

    Returns
    -------
    Result
        ``path`` (N, 3) poses ``(x, y, θ)``, ``direction`` (N,) +1 forward / −1
        reverse, ``cost`` the length driven [m], ``stats`` with ``expansions``,
        ``nodes``, ``cusps``, ``time_s`` and the penalised search cost ``g``.
    """
    t0 = time.perf_counter()
    if motion not in MOTIONS:
        raise ValueError(f"motion must be one of {', '.join(MOTIONS)}, got {motion!r}")
    r = check_turning_radius(turning_radius)
    sx, sy, st = check_pose("start", start)
    gx, gy, gt = check_pose("goal", goal)
    if isinstance(heading_bins, bool) or not isinstance(heading_bins, (int, np.integer)) or not 4 <= heading_bins <= 1440:
        raise ValueError(f"heading_bins must be a whole number from 4 to 1440, got {heading_bins!r}")
    for name, value, low in (("reverse_penalty", reverse_penalty, 1.0), ("non_straight_penalty", non_straight_penalty, 1.0),
                             ("change_penalty", change_penalty, 0.0)):
        if finite_number(name, value) < low:
            raise ValueError(f"{name} must be at least {low:g}, got {value!r}")
    for name, value in (("analytic_expansion", analytic_expansion), ("smooth", smooth)):
        if not isinstance(value, (bool, np.bool_)):  # bool("fals") is True: a typo must not switch it on
            raise ValueError(f"{name} must be true or false, got {value!r}")
    analytic_max = check_length("analytic_expansion_max_length", analytic_expansion_max_length)
    if isinstance(max_expansions, bool) or not isinstance(max_expansions, (int, np.integer)) or max_expansions < 1:
        raise ValueError(f"max_expansions must be a positive whole number, got {max_expansions!r}")
    vertices, disc = robot_outline(footprint, robot_radius)
    res = grid.resolution
    spacing = res if waypoint_spacing is None else check_length("waypoint_spacing", waypoint_spacing, allow_zero=False)
    params: Dict[str, Any] = {"planner": "hybrid_astar", "motion": motion, "turning_radius": r,
                              "heading_bins": int(heading_bins), "reverse_penalty": float(reverse_penalty),
                              "change_penalty": float(change_penalty),
                              "non_straight_penalty": float(non_straight_penalty),
                              "analytic_expansion": bool(analytic_expansion),
                              "analytic_expansion_max_length": analytic_max, "max_expansions": int(max_expansions),
                              "smooth": bool(smooth), "resolution": res}
    # the search runs in the grid's own frame: metres from the corner of cell (0, 0), along its axes
    yaw = grid.origin[2]
    c, s = math.cos(yaw), math.sin(yaw)
    ox, oy = grid.origin[0], grid.origin[1]

    def to_local(x, y, th):
        return c * (x - ox) + s * (y - oy), -s * (x - ox) + c * (y - oy), th - yaw

    lsx, lsy, lst = to_local(sx, sy, st)
    lgx, lgy, lgt = to_local(gx, gy, gt)
    check_turning_scale(r, vertices, disc, res, int(heading_bins), math.hypot(grid.width, grid.height) * res)
    lattice = lattice_for(tuple(map(tuple, vertices.tolist())), disc, r, res, int(heading_bins),
                          motion == "reeds_shepp", lst)
    blocked = np.ascontiguousarray(grid.blocked | grid.unknown)
    stats: Dict[str, Any] = {"expansions": 0, "nodes": 0, "cusps": 0, "time_s": 0.0, "g": math.inf, "word": "",
                             "segments": []}

    def finish(status, reason, path=None, direction=None, cost=math.inf):
        stats["time_s"] = time.perf_counter() - t0
        return Result(status=status, path=np.empty((0, 3)) if path is None else path, cost=cost, stats=stats,
                      reason=reason, params=params,
                      direction=np.empty(0, np.int8) if direction is None else direction)

    common = (res, lattice.theta0, lattice.step, lattice.bins, lattice.pose_cells, lattice.pose_start)
    for label, pose, status in (("start", (lsx, lsy, lst), Status.INVALID_START),
                                ("goal", (lgx, lgy, lgt), Status.INVALID_GOAL)):
        hit = first_overlap(blocked, res, vertices, disc, np.array([pose]), 0.0)
        if hit is not None:
            what = "leaves the map at" if hit[0] in (-1, grid.width) or hit[1] in (-1, grid.height) else \
                "overlaps the blocked or unknown cell"
            return finish(status, f"the robot's footprint at the {label} pose {what} {hit} (x, y)")
    # holonomic heuristic over the cells the inscribed circle fits in (admissible for the centre's path)
    inscribed = Polygon(vertices).exterior.distance(Point(0, 0)) if len(vertices) else disc
    from scipy.ndimage import distance_transform_edt
    clearance = distance_transform_edt(~blocked) * res
    passable = clearance > max(0.0, inscribed - math.sqrt(2.0) * res)
    gcx, gcy = int(lgx // res), int(lgy // res)
    hfield = holonomic_field(passable | _cell_mask(blocked.shape, gcx, gcy), gcx, gcy, res)
    penalties = np.array([1.0, float(non_straight_penalty), float(reverse_penalty), float(change_penalty)])
    found, nx, ny, nb, parent, prim, last, akinds, alens, expansions = _search(
        blocked, res, lsx, lsy, 0, lgx, lgy, lgt, lattice.theta0, lattice.step, lattice.bins, r,
        motion == "reeds_shepp", lattice.prim_kind, lattice.prim_len, lattice.dx, lattice.dy, lattice.dbin,
        lattice.swept, lattice.swept_start, _clear_cells(blocked, lattice.swept), lattice.pose_cells,
        lattice.pose_start, lattice.ds, hfield, penalties, analytic_max, int(max_expansions), bool(analytic_expansion))
    stats["expansions"], stats["nodes"] = int(expansions), int(len(nx))
    if not found:
        why = "the search space is exhausted" if expansions < max_expansions else \
            f"max_expansions ({max_expansions}) reached"
        extra = " (dubins drives forward only: a goal reachable only in reverse needs motion='reeds_shepp')" \
            if motion == "dubins" else ""
        return finish(Status.FAILED, f"no collision-free path: {why}{extra}")
    # the chain of primitives, then the analytic tail, as (kind, signed length) segments from the start
    chain = []
    v = last
    while parent[v] >= 0:
        chain.append(prim[v])
        v = parent[v]
    segments = [(int(lattice.prim_kind[j]), float(lattice.prim_len[j])) for j in reversed(chain)]
    segments += [(int(k), float(s)) for k, s in zip(akinds, alens) if k != NOP and abs(s) > 1e-12 * r]
    g_cost = float(sum(abs(s) for _, s in segments))
    if smooth:
        segments = _shortcut(segments, (lsx, lsy, lst), r, motion, blocked, lattice, common)
    segments = _merged(segments)
    kinds = np.array([k for k, _ in segments], dtype=np.int64)
    lengths = np.array([s for _, s in segments])
    traced, _ = trace_word(lsx, lsy, lst, kinds, lengths, r, lattice.ds)
    hit = first_overlap(blocked, res, vertices, disc, traced, 0.5 * lattice.delta)
    if hit is not None:
        return finish(Status.FAILED, f"internal check: the path found overlaps cell {hit}; please report it")
    poses, direction = trace_word(lsx, lsy, lst, kinds, lengths, r, spacing)
    world = np.column_stack([ox + c * poses[:, 0] - s * poses[:, 1], oy + s * poses[:, 0] + c * poses[:, 1],
                             poses[:, 2] + yaw])
    length = float(np.abs(lengths).sum())
    stats["g"] = g_cost
    stats["word"] = "".join(LETTERS[int(k)] for k in kinds)
    stats["segments"] = lengths.tolist()  # [m], negative in reverse: the exact path, for re-tracing
    stats["cusps"] = int(np.count_nonzero(np.diff(np.sign(lengths[lengths != 0])) != 0)) if len(lengths) else 0
    return finish(Status.EXACT, "", world, direction, length)


def _merged(segments):
    """Consecutive segments of the same kind and direction as one (LLL → L)."""
    out = []
    for kind, length in segments:
        if out and out[-1][0] == kind and (out[-1][1] < 0) == (length < 0):
            out[-1] = (kind, out[-1][1] + length)
        else:
            out.append((kind, length))
    return out


def _clear_cells(blocked: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """Cells with no blocked cell, and no cell beyond the map's edge, within the
    largest Chebyshev reach of ``offsets``: there every swept-cell check passes."""
    from scipy.ndimage import maximum_filter

    reach = int(np.abs(offsets).max()) if len(offsets) else 0
    padded = np.ones((blocked.shape[0] + 2 * reach, blocked.shape[1] + 2 * reach), dtype=bool)
    padded[reach:reach + blocked.shape[0], reach:reach + blocked.shape[1]] = blocked
    near = maximum_filter(padded, size=2 * reach + 1, mode="constant", cval=True)
    return ~near[reach:reach + blocked.shape[0], reach:reach + blocked.shape[1]]


def _cell_mask(shape, x, y) -> np.ndarray:
    mask = np.zeros(shape, dtype=bool)
    if 0 <= y < shape[0] and 0 <= x < shape[1]:
        mask[y, x] = True
    return mask


def _shortcut(segments, start, r, motion, blocked, lattice, common):
    """Greedy smoothing: from each waypoint, jump to the farthest later waypoint
    whose exact Dubins/Reeds–Shepp path is shorter and collision-free."""
    # waypoints: the pose after each segment
    poses = [start]
    for kind, s in segments:
        poses.append(CurvePath(poses[-1], LETTERS[kind], (s,), r).end)
    # cumulative length along the original path
    acc = np.concatenate([[0.0], np.cumsum([abs(s) for _, s in segments])])
    waypoints = np.array(poses, dtype=float)
    kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    lengths = np.zeros(MAX_SEGMENTS)
    out = []
    i, n = 0, len(poses) - 1
    while i < n:
        j, used = _farthest_shortcut(waypoints, acc, i, r, motion == "reeds_shepp", blocked, common[0], lattice.ds,
                                     *common[1:], kinds, lengths)
        if j > 0:
            out.extend(zip(kinds[:used].tolist(), lengths[:used].tolist()))
            i = j
        else:
            out.append(segments[i])
            i += 1
    return out


@njit(cache=True)
def _farthest_shortcut(waypoints, acc, i, radius, reverse, blocked, res, ds, theta0, step, bins, pose_cells,
                       pose_start, kinds, lengths):
    """The farthest waypoint j > i + 1 whose shortest path from waypoint i is
    shorter than the path between them and collision-free, and how many
    segments that path has (written to ``kinds``, ``lengths`` [m], without
    padding and without segments of no length, as :meth:`CurvePath.of_word`
    drops them); (0, 0) when there is none. The same paths and lengths as
    :func:`dubins.shortest` / :func:`reeds_shepp.shortest`, without a Python
    call per candidate."""
    seg = np.zeros(MAX_SEGMENTS)
    word_kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    word_lens = np.zeros(MAX_SEGMENTS)
    x0, y0, t0 = waypoints[i, 0], waypoints[i, 1], waypoints[i, 2]
    for j in range(waypoints.shape[0] - 1, i + 1, -1):
        x1, y1, t1 = waypoints[j, 0], waypoints[j, 1], waypoints[j, 2]
        if reverse:
            lx, ly, phi = reeds_shepp._local(x0, y0, t0, x1, y1, t1, radius)
            reeds_shepp._shortest_into(lx, ly, phi, seg, word_kinds, word_lens)
            for k in range(MAX_SEGMENTS):
                word_lens[k] *= radius
        else:
            d, a, b = dubins._normalised(x0, y0, t0, x1, y1, t1, radius)
            word, t, p, q = dubins.solve(d, a, b)
            for k in range(MAX_SEGMENTS):
                word_kinds[k] = dubins.WORDS[word, k] if k < 3 else NOP
            word_lens[0], word_lens[1], word_lens[2] = t * radius, p * radius, q * radius
        used = 0
        length = 0.0
        for k in range(MAX_SEGMENTS):
            if word_kinds[k] != NOP and abs(word_lens[k]) > NEGLIGIBLE * radius:
                kinds[used], lengths[used] = word_kinds[k], word_lens[k]
                length += abs(word_lens[k])
                used += 1
        if length >= acc[j] - acc[i] - 1e-9:
            continue
        if curve_free(blocked, res, x0, y0, t0, kinds[:used], lengths[:used], radius, ds, theta0, step, bins,
                      pose_cells, pose_start, np.zeros((0, 0)), np.zeros(3)):
            return j, used
    return 0, 0
