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
  robot's inscribed circle fits in, settled lazily as far as the search reads
  it, as Smac's, :mod:`navlab.grid.hybrid_field`); the Reeds–Shepp length is solved only
  where the Dubins length, an upper bound on it, exceeds the field
  (:func:`~navlab.grid.hybrid_search._heuristic`), so the value is exact at a fraction of the cost, and
  only for queue entries that reach the top (:mod:`navlab.grid.hybrid_search`:
  the same expansions as solving every child);
- travel costs multiply a primitive's length by penalties for turning and
  reversing, and add one for changing direction (Nav2's defaults);
- an analytic expansion tries the exact Dubins/Reeds–Shepp path to the goal
  from nodes near it; the search ends when one is collision-free;
- a smoother replaces stretches of the path with shorter Dubins/Reeds–Shepp
  paths where they are collision-free, so the curvature bound 1/r holds
  exactly after smoothing.

**One lattice per robot.** The search's headings are k·2π/bins whatever the
start heading: the start joins them by an arc of at most half a heading step,
forward and (Reeds–Shepp) in reverse, each a start node where it is free
(:func:`_start_nodes`), so the path still starts at the exact start pose and
every query of a robot reuses one footprint lattice (its swept cells are built
once, as searches first ask for them). Only where neither arc is free does a
query search a lattice through its own start heading.

**Collision checking is certified, not sampled.** For every heading bin
and primitive, the cells any point of the footprint can cover while driving
the primitive are listed, once, the first time the search drives it
(:func:`~navlab.sampling.footprint_lattice.swept_group`): the footprint is traced at
poses no more than ``δ`` apart (no footprint point moves more than δ between
two), each copy grown by δ/2 (so the union covers the motion between samples)
and by one cell diagonal (the node's pose may lie anywhere in its cell, and a
cell is kept when any part of it can be touched). A primitive is free when
none of those cells is blocked, so a returned path never overlaps a blocked
cell; the check is conservative by at most ``√2·res + δ/2`` (δ = res/2 by
default). Analytic and smoothed segments use per-bin footprints grown also by
``R·sin(Δθ/2)`` (R the footprint's circumscribed radius), which covers any
heading within the bin. The footprint's cells and checks live in
:mod:`navlab.sampling.footprint_lattice`, shared with the SE(2) trees.

Those lists hold every cell near the footprint from anywhere in the pose's cell (and bin), so they
also reject poses well clear of a wall. An analytic or smoothed pose they reject is checked again
exactly: the outline at the pose itself against the blocked squares grown by δ
(:func:`~navlab.world.footprint_collision.pose_grid_overlap`); such a pose leaves every pose within
δ/2 of travel at least δ/2 from them, the final check's margin below. Primitives are checked that way
only after the search has exhausted its space on the swept cells (``exact_retry``): the nodes that had
one rejected are opened again and the search goes on, in the same budget, checking those exactly (near
walls an exact check costs several expansions' time, so it waits until the lists have failed).

Every returned path is checked once more, independently of those cell lists
(:mod:`navlab.grid.hybrid_certify`): the outline placed at poses traced along
the final path, no footprint point moving more than δ between two, against
every blocked cell's square grown by δ/2, by an exact polygon–rectangle test.
"""

from __future__ import annotations

import functools
import math
import time
from typing import Any, Dict, Optional

import numpy as np
from shapely.geometry import Point, Polygon

from ..errors import ParameterError
from ..jit import njit
from ..limits import MAX_COUNT, check_count, check_flag, check_length, check_weight, finite_number
from ..registry import suggest
from ..result import Result, Status
from ..sampling import dubins, reeds_shepp, reeds_shepp_length
from ..sampling.curves import (LEFT, LETTERS, MAX_SEGMENTS, NEGLIGIBLE, NOP, RIGHT, _wrap_compiled, advance,
                               check_pose, check_turning_radius, trace_word, word_poses)
from ..sampling.footprint_lattice import (check_turning_scale, curve_free, footprint_misfit, lattice_for,
                                          pose_free, robot_outline)
from ..wording import counted
from .hybrid_certify import first_overlap_compiled, first_overlap_exact
from .hybrid_field import field_at, field_from_clearance, field_start
from .hybrid_search import Scratch, search
from . import hybrid_table
from .occupancy import OccupancyGrid, check_grid

MOTIONS = ("dubins", "reeds_shepp")
DEFAULTS = {  # Nav2 SmacPlannerHybrid's defaults where it has one
    "heading_bins": 72,
    "reverse_penalty": 2.0,
    "change_penalty": 0.0,
    "non_straight_penalty": 1.2,
    "analytic_expansion_max_length": None,  # [m] None: ANALYTIC_MIN_LENGTH or ANALYTIC_RADII turning radii
    "max_expansions": 200_000,
    "weight": 1.0,  # (Smac has none: its keys are g + h)
}
#: the most poses a returned path holds (``waypoint_spacing``): 240 MB of poses
MAX_WAYPOINTS = 10 ** 7
#: [m] the analytic expansion's reach at least (Nav2 Smac's default ``analytic_expansion_max_length``)
ANALYTIC_MIN_LENGTH = 3.0
#: ... and at least this many turning radii: a shortest path to a goal within about one radius is
#: mostly turning, which Smac's 3 m assumes of a robot turning on 0.4 m; a car turning on 4.4 m
#: (PythonRobotics') would otherwise try it only from poses nearer than its own radius
ANALYTIC_RADII = 3.0
#: the keys of what Hybrid A* keeps on a grid (``OccupancyGrid._cache``): its blocked cells, its tables
_BLOCKED_KEY, _TABLES_KEY = "hybrid_astar.blocked", "hybrid_astar.tables"
#: each thread's search arrays, reused query after query (per thread, so threads never share them)
_SCRATCH = Scratch()

# ---------------------------------------------------------------------------
# the planner
# ---------------------------------------------------------------------------
def plan_hybrid(grid: OccupancyGrid, start, goal, turning_radius: float, motion: str = "reeds_shepp",
                footprint=None, robot_radius: Optional[float] = None,
                heading_bins: int = DEFAULTS["heading_bins"], reverse_penalty: float = DEFAULTS["reverse_penalty"],
                change_penalty: float = DEFAULTS["change_penalty"],
                non_straight_penalty: float = DEFAULTS["non_straight_penalty"],
                analytic_expansion: bool = True,
                analytic_expansion_max_length: Optional[float] = DEFAULTS["analytic_expansion_max_length"],
                analytic_expansion_ratio: Optional[float] = None,
                max_expansions: int = DEFAULTS["max_expansions"], smooth: bool = True,
                waypoint_spacing: Optional[float] = None, exact_retry: bool = True,
                distance_table: bool = True, weight: float = DEFAULTS["weight"]) -> Result:
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
        The robot's outline in body coordinates [m]; or ``robot_radius`` for a disc
        (with neither, a point robot).
    heading_bins : int
        Heading resolution (72: 5°, Nav2's default).
    reverse_penalty, change_penalty, non_straight_penalty : float
        Travel-cost factors (≥ 1 for the two multipliers; ≥ 0 for the change penalty).
    analytic_expansion : bool
        Try the exact Dubins/Reeds–Shepp path to the goal from nodes within
        ``analytic_expansion_max_length`` of it [m]. Without it the search ends
        in the goal's cell at a heading less than one arc's turn from the goal's:
        an arc turns k bins (k = ⌈√2·res / (2r·sin(π/bins))⌉), so only every k-th
        heading is reached, and the search ends within k − 1 bins of the goal's
        (the path then ends there, not at the goal).
    analytic_expansion_max_length : float, optional
        [m] None (the default): the larger of 3 m (Nav2 Smac's default) and 3
        turning radii (:data:`ANALYTIC_MIN_LENGTH`, :data:`ANALYTIC_RADII`).
    analytic_expansion_ratio : float, optional
        Try the analytic expansion only on Nav2 Smac's schedule: every
        max(⌊h / ratio⌋, ⌈ratio⌉)-th expansion within ``analytic_expansion_max_length``,
        h the least heuristic seen so far [cells] (Smac's default ratio is 3.5).
        None (the default) tries it at every such expansion. Either way it is
        tried at every node in the goal's cell and heading bin. With a long
        ``analytic_expansion_max_length`` the search can end far from the goal,
        in far fewer expansions; the path may differ (longer or shorter).
    max_expansions : int
        Give up (``FAILED``) after this many expansions.
    smooth : bool
        Shorten the path with collision-free Dubins/Reeds–Shepp shortcuts.
    waypoint_spacing : float, optional
        Spacing of the returned poses [m] along the path; the grid's resolution by default. The poses
        lie on the checked curve (``stats['word']`` and ``stats['segments']`` give it exactly); a
        straight line between two of them cuts an arc by up to spacing² / (8 · turning_radius), so
        a sparse spacing is for display, not for driving chord by chord.
    exact_retry : bool
        When the search exhausts its space on the primitives' swept cells
        (which can wall off a gap the robot clears by more than res/2 on each
        side), open again the nodes that had a primitive rejected and go on,
        within ``max_expansions``, checking those exactly (docs/grid.md).
        False: report the exhausted space at once.
    distance_table : bool
        Reeds–Shepp motion: read the obstacle-free distance to the goal from
        the robot's table (:mod:`navlab.grid.hybrid_table`, Nav2 Smac's
        lookup table: the length from the pose rounded to half a cell and a
        heading bin, solved the first time a query needs it and kept for the
        robot's next queries). False: solved at each pose exactly, every
        time (the search's answers before the table, bit for bit).
    weight : float
        The heuristic's weight (weighted A*: Pohl, "Heuristic search viewed as
        path finding in a graph", Artificial Intelligence 1(3), 1970): nodes
        are ordered by g + weight·h. 1 (the default) is Dolgov et al.'s
        search; more mostly expands fewer nodes, for a path that may be
        longer (not always fewer: a greedier search can follow a detour
        further; PythonRobotics' ``HybridAStar`` weighs its heuristic by 5,
        its ``H_COST``). At most :data:`~navlab.limits.MAX_WEIGHT`.

    Returns
    -------
    Result
        ``path`` (N, 3) poses ``(x, y, θ)``, ``direction`` (N,) +1 forward / −1
        reverse, ``cost`` the length driven [m], ``stats`` with ``expansions``,
        ``nodes``, ``cusps``, ``time_s``, ``heuristics_solved`` (Reeds–Shepp
        lengths the lazy queue solved, not read from the robot's distance table:
        fewer on a robot's later queries), ``goal_offset_m`` and ``goal_heading_offset_rad``
        (how far the path's last pose is from the goal: rounding with the
        analytic expansion, up to a cell and k − 1 bins without), ``g``, the search's penalised cost of the
        primitives driven (before the analytic tail and the smoother), and
        ``exact_retry``: whether the search exhausted its space on the swept
        cells and went on checking the rejected primitives exactly (the
        nodes it opened again count again in ``expansions``).
    """
    t0 = time.perf_counter()
    check_grid(grid)
    if motion not in MOTIONS:
        hint = suggest(motion, list(MOTIONS)) if isinstance(motion, str) else ""
        raise ParameterError(f"motion must be one of {', '.join(MOTIONS)}, got {motion!r}.{hint}".rstrip("."))
    r = check_turning_radius(turning_radius)
    sx, sy, st = check_pose("start", start, degrees_hint=True)
    gx, gy, gt = check_pose("goal", goal, degrees_hint=True)
    checked = check_settings(heading_bins=heading_bins, reverse_penalty=reverse_penalty,
                             change_penalty=change_penalty, non_straight_penalty=non_straight_penalty,
                             analytic_expansion=analytic_expansion,
                             analytic_expansion_max_length=analytic_expansion_max_length,
                             analytic_expansion_ratio=analytic_expansion_ratio, max_expansions=max_expansions,
                             smooth=smooth, waypoint_spacing=waypoint_spacing, exact_retry=exact_retry,
                             distance_table=distance_table, weight=weight)
    distance_table_on = bool(distance_table)
    heading_bins, max_expansions = checked["heading_bins"], checked["max_expansions"]
    analytic_max = max(ANALYTIC_MIN_LENGTH, ANALYTIC_RADII * r) if analytic_expansion_max_length is None else \
        checked["analytic_expansion_max_length"]
    vertices, disc = robot_outline(footprint, robot_radius)
    res = grid.resolution
    spacing = res if waypoint_spacing is None else checked["waypoint_spacing"]
    params: Dict[str, Any] = {"planner": "hybrid_astar", "motion": motion, "turning_radius": r,
                              "heading_bins": int(heading_bins), "reverse_penalty": float(reverse_penalty),
                              "change_penalty": float(change_penalty),
                              "non_straight_penalty": float(non_straight_penalty),
                              "analytic_expansion": bool(analytic_expansion),
                              "analytic_expansion_max_length": analytic_max,
                              "analytic_expansion_ratio": None if analytic_expansion_ratio is None
                              else float(analytic_expansion_ratio), "max_expansions": int(max_expansions),
                              "smooth": bool(smooth), "exact_retry": bool(exact_retry),
                              "distance_table": distance_table_on, "weight": checked["weight"], "resolution": res}
    # the search runs in the grid's own frame: metres from the corner of cell (0, 0), along its axes
    yaw = grid.origin[2]
    c, s = math.cos(yaw), math.sin(yaw)
    ox, oy = grid.origin[0], grid.origin[1]

    def to_local(x, y, th):
        return c * (x - ox) + s * (y - oy), -s * (x - ox) + c * (y - oy), th - yaw

    lsx, lsy, lst = to_local(sx, sy, st)
    lgx, lgy, lgt = to_local(gx, gy, gt)
    outline = tuple(map(tuple, vertices.tolist()))
    misfit = footprint_misfit(outline, float(disc), grid.width * res, grid.height * res, res, int(heading_bins),
                              "robot_radius" if footprint is None else "footprint")
    if misfit is None:  # (a robot that fits nowhere is told so, not that its turning radius is too small)
        check_turning_scale(r, vertices, disc, res, int(heading_bins), math.hypot(grid.width, grid.height) * res)
    blocked = _blocked_of(grid)
    stats: Dict[str, Any] = {"expansions": 0, "nodes": 0, "cusps": 0, "time_s": 0.0, "g": math.inf, "word": "",
                             "segments": [], "exact_retry": False, "goal_offset_m": math.inf,
                             "goal_heading_offset_rad": math.inf}

    def finish(status, reason, path=None, direction=None, cost=math.inf):
        stats["time_s"] = time.perf_counter() - t0
        return Result(status=status, path=np.empty((0, 3)) if path is None else path, cost=cost, stats=stats,
                      reason=reason, params=params,
                      direction=np.empty(0, np.int8) if direction is None else direction)

    if misfit is not None:  # (before the lattice: its tables for such a robot could take gigabytes)
        return finish(Status.INVALID_START, misfit)
    # one lattice of headings k·2π/bins for every query of this robot; the start joins it by a short arc
    lattice = lattice_for(outline, disc, r, res, int(heading_bins), motion == "reeds_shepp", 0.0)
    common = _pose_args(lattice)
    for label, pose, status, given in (("start", (lsx, lsy, lst), Status.INVALID_START, (sx, sy, st)),
                                       ("goal", (lgx, lgy, lgt), Status.INVALID_GOAL, (gx, gy, gt))):
        if pose_free(blocked, *common[:1], *pose, *common[1:]):
            continue  # the lattice's cells for the pose are a superset of what it overlaps: no shapely needed
        hit = first_overlap_exact(blocked, res, vertices, disc, np.array([pose]), 0.0)
        if hit is not None:
            what = "leaves the map at" if hit[0] in (-1, grid.width) or hit[1] in (-1, grid.height) else \
                "overlaps the blocked or unknown"
            where = ", ".join(f"{v:g}" for v in given)
            return finish(status, f"the robot's footprint at the {label} pose ({where}) {what} cell {hit} "
                                  "(column, row)")
    # holonomic heuristic over the cells the inscribed circle fits in (every cell the centre can cross; its
    # 8-connected distances overstate a straight line by up to 8 % off 45°: not strictly admissible, as Smac's)
    inscribed = _inscribed(outline) if len(vertices) else disc
    cells_clear, near2, clear = _tables_of(grid)
    gcx, gcy = int(lgx // res), int(lgy // res)
    scx, scy = int(lsx // res), int(lsy // res)
    # settled lazily: as far as the start here, then as far as the search reads (Smac's way; the same values)
    passable, *field, at_start = field_from_clearance(cells_clear, res, max(0.0, inscribed - math.sqrt(2.0) * res),
                                                      gcx, gcy, scx, scy)
    field = tuple(field)
    if not math.isfinite(at_start) and not math.isfinite(field_at(
            *field_start(passable | _cell_mask(blocked.shape, scx, scy), gcx, gcy, res), grid.width + 2, res, scx,
            scy)[0]):
        # the passable cells hold every cell the robot's centre can cross (its inscribed circle free), so the
        # search could only exhaust max_expansions in vain; the start's own cell is added in case its
        # clearance sits at the margin's edge
        what = f"a disc of the robot's inscribed radius ({inscribed:.3g} m)" if inscribed > 0 else "a point"
        return finish(Status.FAILED, f"no collision-free path: the goal is walled off from the start even for {what}")
    # the travel-cost factors, then 1 / weight: the search keys nodes g / weight + h (the order of g + weight·h)
    penalties = np.array([1.0, float(non_straight_penalty), float(reverse_penalty), float(change_penalty),
                          1.0 / checked["weight"]])
    def through_start():
        """A lattice through the start heading itself, its ``common`` tuple, and the start as its one node."""
        own = lattice_for(outline, disc, r, res, int(heading_bins), motion == "reeds_shepp", lst)
        return own, _pose_args(own), [(lsx, lsy, 0, 0.0, NOP, 0.0)]

    starts = _start_nodes((lsx, lsy, lst), r, motion == "reeds_shepp", penalties, blocked, clear, lattice,
                          exact_grow(lattice))
    if not starts:  # no arc onto the shared lattice is free: search a lattice through the start heading itself
        lattice, common, starts = through_start()

    # the Reeds–Shepp lengths of this robot's earlier queries, kept (Dubins keys stay exact: docs/grid.md says why)
    distances = hybrid_table.distance_table(r, res, int(heading_bins)) \
        if motion == "reeds_shepp" and distance_table_on else hybrid_table.NO_TABLE

    def run(lattice, starts, budget):
        """The search from ``starts`` on ``lattice`` with ``budget`` expansions: its outputs (search's)."""
        nonlocal field
        for x, y, *_ in starts:  # the field settled as far as each start node's cell (the start's already is)
            if (int(x // res), int(y // res)) != (scx, scy):
                cells = field_at(*field, grid.width + 2, res, int(x // res), int(y // res))[1]
                field = (*field[:2], cells, *field[3:])
        start_x, start_y, start_g = (np.array([n[i] for n in starts], dtype=float) for i in (0, 1, 3))
        start_bin = np.array([n[2] for n in starts], dtype=np.int64)
        with lattice.swept_cells() as table:  # the search adds the swept cells it needs to the lattice's table
            *out, table[0], table[1], retried, scratch = search(
                blocked, res, start_x, start_y, start_bin, start_g, lgx, lgy, lgt, lattice.theta0, lattice.step,
                lattice.bins, r, motion == "reeds_shepp", lattice.prim_kind, lattice.prim_len, lattice.dx,
                lattice.dy, lattice.dbin, *table, *lattice.swept_args()[:3], lattice.swept_margin, near2, clear,
                lattice.clear_disc, lattice.pose_cells, lattice.pose_start, lattice.ds, exact_grow(lattice),
                bool(exact_retry), *field, penalties, analytic_max, int(budget), bool(analytic_expansion),
                0.0 if analytic_expansion_ratio is None else float(analytic_expansion_ratio), *distances,
                _SCRATCH.take(lattice.bins))
        _SCRATCH.keep(scratch)  # the node arrays are views into it: read below, before this thread's next search
        return (*out, retried)

    found, nx, ny, nb, ng, parent, prim, last, akinds, alens, expansions, solved, retried = \
        run(lattice, starts, max_expansions)
    if not found and expansions < max_expansions and lattice.theta0 != lst and starts[0][4] != NOP:
        # the shared lattice's space is exhausted from the arcs that join it; a lattice through the start
        # heading itself holds other poses, which may pass where these did not (rare: 2 of 700 random
        # near-wall queries): search it too, in what is left of the budget
        lattice, common, starts = through_start()
        used, used_solved = expansions, solved
        found, nx, ny, nb, ng, parent, prim, last, akinds, alens, expansions, solved, retried = \
            run(lattice, starts, max_expansions - used)
        expansions, solved = expansions + used, solved + used_solved
    stats["exact_retry"] = bool(retried)
    stats["expansions"], stats["nodes"], stats["heuristics_solved"] = int(expansions), int(len(nx)), int(solved)
    if not found:
        forward_only = " (dubins drives forward only: a goal reachable only in reverse needs motion='reeds_shepp')" \
            if motion == "dubins" else ""
        if expansions < max_expansions:  # no path at this resolution; forward-only motion may be why
            why = "the search space is exhausted" + forward_only
            if not analytic_expansion:  # the goal is one cell and a few bins: the lattice may never land in it
                heading = "in the goal's heading bin" if lattice.k == 1 else \
                    f"at a heading within {counted(lattice.k - 1, 'bin')} of the goal's"
                why += (f"; without the analytic expansion it must end in the goal's {lattice.resolution:g} m cell "
                        f"{heading}, which the primitives may never reach (coarser cells or the analytic expansion "
                        "may)")
            if stats["exact_retry"]:  # the exact checks refused what the cell lists did: their margin may be why
                why += (f"; the exact checks keep the footprint {exact_grow(lattice):g} m (half a cell) clear of "
                        "blocked cells and the map's edge, so a gap that leaves less on a side is closed")
        elif stats["exact_retry"]:  # the first finding stands; the rest is what the budget left undecided
            why = (f"the search space is exhausted on the primitives' swept cells{forward_only}, and checking the "
                   f"rejected ones exactly reached max_expansions ({max_expansions}) before the goal "
                   "(raise max_expansions)")
        else:
            why = f"max_expansions ({max_expansions}) reached before the goal (raise max_expansions)"
        # resolution-complete only: a path off the lattice (another start heading, finer cells) may exist
        return finish(Status.FAILED, f"no path on the search's lattice ({int(heading_bins)} headings, "
                                     f"{res:g} m cells): {why}")
    # the chain of primitives, then the analytic tail, as (kind, signed length) segments from the start
    join_kind = np.array([n[4] for n in starts], dtype=np.int64)  # the arcs onto the lattice, per start node
    join_len = np.array([n[5] for n in starts])
    kinds, lengths = _path_segments(parent, prim, last, join_kind, join_len, lattice.prim_kind, lattice.prim_len,
                                    akinds, alens, 1e-12 * r)
    if smooth:
        kinds, lengths = _shortcut(kinds, lengths, (lsx, lsy, lst), r, motion, blocked, clear, lattice, common)
    kinds, lengths = _merged(kinds, lengths)
    overlaps, hx, hy, waypoints, world, direction = _checked_poses(
        lsx, lsy, lst, kinds, lengths, r, lattice.ds, blocked, res, vertices, float(disc), 0.5 * lattice.delta,
        spacing, MAX_WAYPOINTS, ox, oy, yaw)
    if overlaps:
        return finish(Status.FAILED, f"internal check: the path found overlaps cell {(int(hx), int(hy))}; please "
                                     "report it")
    if waypoints > MAX_WAYPOINTS:
        raise ParameterError(f"waypoint_spacing: {spacing:g} m gives {waypoints:.3g} poses along the "
                             f"{float(np.abs(lengths).sum()):.4g} m path, more than the {MAX_WAYPOINTS:.0e} a path holds")
    length = float(np.abs(lengths).sum())
    stats["g"] = float(ng[last])
    stats["word"] = "".join(LETTERS[k] for k in kinds.tolist())
    stats["segments"] = lengths.tolist()  # [m], negative in reverse: the exact path, for re-tracing
    stats["cusps"] = int(_cusps(0, lengths, 0))
    # where the path ends against the goal pose: 0 with the analytic expansion; without it, in the goal's cell
    # at a heading within k - 1 bins (analytic_expansion), which a caller should be able to see
    stats["goal_offset_m"] = float(math.hypot(world[-1, 0] - gx, world[-1, 1] - gy))
    stats["goal_heading_offset_rad"] = float(abs(math.remainder(world[-1, 2] - gt, 2.0 * math.pi)))
    return finish(Status.EXACT, "", world, direction, length)


def check_settings(heading_bins=DEFAULTS["heading_bins"], reverse_penalty=DEFAULTS["reverse_penalty"],
                   change_penalty=DEFAULTS["change_penalty"], non_straight_penalty=DEFAULTS["non_straight_penalty"],
                   analytic_expansion=True, analytic_expansion_max_length=DEFAULTS["analytic_expansion_max_length"],
                   analytic_expansion_ratio=None, max_expansions=DEFAULTS["max_expansions"], smooth=True,
                   waypoint_spacing=None, exact_retry=True, distance_table=True,
                   weight=DEFAULTS["weight"]) -> Dict[str, Any]:
    """:func:`plan_hybrid`'s settings but the robot, map and poses, checked as it searches with them.

    Apart from the search so that a query can be refused before its kernels load: a typo waited for their
    first compile (80 s; newcomer run, session 21).

    Parameters
    ----------
    heading_bins, reverse_penalty, change_penalty, non_straight_penalty, analytic_expansion,
    analytic_expansion_max_length, analytic_expansion_ratio, max_expansions, smooth, waypoint_spacing,
    exact_retry, distance_table, weight
        As :func:`plan_hybrid` takes them.

    Returns
    -------
    dict
        ``heading_bins`` and ``max_expansions`` (capped at :data:`~navlab.limits.MAX_COUNT`) as ints,
        ``analytic_expansion_max_length`` and ``waypoint_spacing`` [m] as floats (None where not given),
        ``weight`` as a float.

    Raises
    ------
    ParameterError
        Naming the first bad setting.
    """
    out: Dict[str, Any] = {"heading_bins": check_count("heading_bins", heading_bins, 4, 1440)}  # 72.0 counts
    for name, value, low in (("reverse_penalty", reverse_penalty, 1.0), ("non_straight_penalty", non_straight_penalty, 1.0),
                             ("change_penalty", change_penalty, 0.0)):
        if finite_number(name, value) < low:
            raise ParameterError(f"{name} must be at least {low:g}, got {value!r}")
    for name, value in (("analytic_expansion", analytic_expansion), ("smooth", smooth), ("exact_retry", exact_retry),
                        ("distance_table", distance_table)):
        check_flag(name, value)
    out["analytic_expansion_max_length"] = None if analytic_expansion_max_length is None else \
        check_length("analytic_expansion_max_length", analytic_expansion_max_length)
    if analytic_expansion_ratio is not None and not finite_number("analytic_expansion_ratio",
                                                                   analytic_expansion_ratio) > 0:
        raise ParameterError(f"analytic_expansion_ratio must be positive, got {analytic_expansion_ratio!r}")
    # beyond any search's reach, so capped rather than refused; int64 for the kernel
    out["max_expansions"] = min(check_count("max_expansions", max_expansions, 1, None), MAX_COUNT)
    out["waypoint_spacing"] = None if waypoint_spacing is None else \
        check_length("waypoint_spacing", waypoint_spacing, allow_zero=False)
    out["weight"] = check_weight(weight)
    return out


def _pose_args(lattice) -> tuple:
    """What :func:`~navlab.sampling.footprint_lattice.pose_free` and the smoother take of a lattice after the
    pose: (resolution, theta0, step, bins, pose cells, their start per bin)."""
    return (lattice.resolution, lattice.theta0, lattice.step, lattice.bins, lattice.pose_cells, lattice.pose_start)


def _start_nodes(start, r, reverse, penalties, blocked, clear, lattice, grow):
    """The search's start nodes: ``[(x, y, bin, cost [m], kind, length [m])]``, each the pose an arc from
    ``start`` reaches on the lattice's headings (``theta0 + bin·step``) with that arc's penalised cost,
    kind and signed length (``NOP``, 0: the start itself, when its heading is within 1e-12 rad of one).

    The arc turns to the nearest heading, at most half a step (2.5° at 72 bins: a 0.19 m arc on a
    4.4 m radius), forward and, for Reeds–Shepp motion, in reverse; an arc is kept if its footprint is
    free (:func:`~navlab.sampling.footprint_lattice.curve_free`). So every query of a robot searches
    one lattice of headings, built once (:func:`~navlab.sampling.footprint_lattice.lattice_for`), from
    its exact start; an empty list means no arc is free (the caller searches a lattice through the
    start heading instead). The nodes are in distinct states (the cheaper of two in one state is kept)."""
    x, y, theta = start
    step = lattice.step
    b = round((theta - lattice.theta0) / step)
    heading = lattice.theta0 + b * step
    turn = heading - theta
    if abs(turn) <= 1e-12:  # on the lattice: the path then drifts at most 1e-12·L m from the searched one in L m
        return [(x, y, b % lattice.bins, 0.0, NOP, 0.0)]
    out = []
    for kind, length in ((LEFT if turn > 0 else RIGHT, r * abs(turn)), (RIGHT if turn > 0 else LEFT, -r * abs(turn))):
        if length < 0 and not reverse:
            continue
        x2, y2, _ = advance(x, y, theta, kind, length, r)
        if not curve_free(blocked, lattice.resolution, x, y, theta, np.array([kind], dtype=np.int64),
                          np.array([length]), r, lattice.ds, lattice.theta0, step, lattice.bins, lattice.pose_cells,
                          lattice.pose_start, clear, lattice.clear_disc, lattice.vertices, lattice.disc, grow):
            continue
        cost = abs(length) * penalties[1] * (penalties[2] if length < 0 else 1.0)
        out.append((x2, y2, b % lattice.bins, cost, kind, length))
    res = lattice.resolution
    if len(out) == 2 and (out[0][0] // res, out[0][1] // res) == (out[1][0] // res, out[1][1] // res):
        out = [min(out, key=lambda node: node[3])]  # both arcs end in one state: the cheaper stands (forward on a tie)
    return out


def exact_grow(lattice) -> float:
    """[m] How far the search's exact re-checks grow the blocked cells' squares: the lattice's δ, the most
    a footprint point moves between two traced poses. A pose the exact test accepts, at least δ from every
    blocked square, leaves every pose within δ/2 of travel at least δ/2 from them, which is the final
    check's margin (``first_overlap_exact(..., 0.5 * lattice.delta)``) wherever the path is traced again
    (poses the cell lists accept keep the lists' own margin)."""
    return lattice.delta


@njit(cache=True)
def _path_segments(parent, prim, last, join_kind, join_len, prim_kind, prim_len, akinds, alens, negligible):
    """The found path as segments (kinds, signed lengths [m]) from the start: the arc from the start onto the
    lattice of the start node the chain leads back to (none when its kind is ``NOP``), the primitives from
    there to node ``last`` (``parent`` and ``prim``: each node's), then the analytic tail's segments longer
    than ``negligible`` [m]."""
    depth = 0
    v = last
    while parent[v] >= 0:
        depth += 1
        v = parent[v]
    first = 1 if join_kind[v] != NOP else 0
    tail = 0
    for i in range(akinds.shape[0]):
        if akinds[i] != NOP and abs(alens[i]) > negligible:
            tail += 1
    kinds = np.empty(first + depth + tail, dtype=np.int64)
    lengths = np.empty(first + depth + tail)
    if first:
        kinds[0], lengths[0] = join_kind[v], join_len[v]
    k = first + depth - 1
    v = last
    while parent[v] >= 0:  # (the chain runs from the end back)
        kinds[k], lengths[k] = prim_kind[prim[v]], prim_len[prim[v]]
        k -= 1
        v = parent[v]
    k = first + depth
    for i in range(akinds.shape[0]):
        if akinds[i] != NOP and abs(alens[i]) > negligible:
            kinds[k], lengths[k] = akinds[i], alens[i]
            k += 1
    return kinds, lengths


@njit(cache=True)
def _merged(kinds, lengths):
    """Consecutive segments of the same kind and direction as one (LLL → L)."""
    out_kinds = np.empty_like(kinds)
    out_lengths = np.empty_like(lengths)
    n = 0
    for i in range(kinds.shape[0]):
        if n > 0 and out_kinds[n - 1] == kinds[i] and (out_lengths[n - 1] < 0) == (lengths[i] < 0):
            out_lengths[n - 1] += lengths[i]
        else:
            out_kinds[n], out_lengths[n] = kinds[i], lengths[i]
            n += 1
    return out_kinds[:n], out_lengths[:n]


def _blocked_of(grid: OccupancyGrid) -> np.ndarray:
    """The cells the search treats as blocked (blocked or unknown), C-ordered; kept on the grid (its
    ``_cache``: the grid is immutable, and the array lives as long as it does). Not written.

    A robot plans on one map many times: found by content, each query hashed the whole map
    (``np.packbits``, 20–30 µs of a 0.6 ms query on PythonRobotics' 61 x 61 map right after a
    PythonRobotics run)."""
    blocked = grid._cache.get(_BLOCKED_KEY)
    if blocked is None:  # (two threads may both build it: the same cells either way)
        blocked = grid._cache.setdefault(_BLOCKED_KEY, np.ascontiguousarray(grid.blocked | grid.unknown))
    return blocked


def _tables_of(grid: OccupancyGrid):
    """:func:`_map_tables` of ``grid``, kept on it as :func:`_blocked_of` is; a new grid with the same cells
    finds the last map's by content."""
    tables = grid._cache.get(_TABLES_KEY)
    if tables is None:
        blocked = _blocked_of(grid)
        tables = grid._cache.setdefault(_TABLES_KEY, _map_tables(blocked.shape, grid.resolution,
                                                                 np.packbits(blocked).tobytes()))
    return tables


@functools.lru_cache(maxsize=1)
def _map_tables(shape, res: float, packed: bytes):
    """What the search reads of a map that is the same for every query on it, cached by the map's content
    (``packed``: ``np.packbits`` of the blocked cells; a robot plans on one map many times, and on
    PythonRobotics' 61 x 61 map these cost about 0.5 ms a query). Here only the last map's are kept, for a
    new grid object with the same cells; each grid also keeps its own on itself while it lives
    (:func:`_tables_of`). They take 24 bytes per cell (2.4 GB at the 10⁸-cell limit), and a replanning
    loop on a changing costmap would only fill a longer cache with maps it never sees again:
    ``distance_transform_edt(~blocked)``
    [cells], :func:`_nearest_blocked2` [cells²] and its roots times ``res``, the values of
    :func:`~navlab.sampling.footprint_lattice.clearance_map` [m] (the same squares' roots), which let
    curve checks pass poses far from everything unread. Read-only arrays."""
    from scipy.ndimage import distance_transform_edt

    blocked = np.unpackbits(np.frombuffer(packed, np.uint8), count=shape[0] * shape[1]).reshape(shape).astype(bool)
    cells_clear = distance_transform_edt(~blocked)  # on a map with nothing blocked, see _nearest_blocked2
    near2 = _nearest_blocked2(blocked, cells_clear)
    tables = (cells_clear, near2, np.sqrt(near2) * res)
    for table in tables:
        table.flags.writeable = False
    return tables


@functools.lru_cache(maxsize=64)
def _inscribed(vertices) -> float:
    """The radius [m] of the largest circle about the origin inside the outline (shapely), cached by vertices."""
    return Polygon(vertices).exterior.distance(Point(0, 0))


def _nearest_blocked2(blocked: np.ndarray, cells_clear: Optional[np.ndarray] = None) -> np.ndarray:
    """Squared distance [cells²] from each cell's centre to the nearest blocked or off-map cell's
    centre (0 on blocked cells): whole numbers, so the search's comparisons with it are exact.

    ``cells_clear`` is ``distance_transform_edt(~blocked)`` if already computed. The nearest
    off-map cell is straight across the nearest edge, so the map's edge needs no second
    transform. (With nothing blocked scipy measures to a cell beyond the corner, an off-map
    cell no nearer than the edge's, so the minimum is right then too; it is left out anyway.)"""
    h, w = blocked.shape
    ys, xs = np.ogrid[:h, :w]
    edge = np.minimum(np.minimum(xs + 1, w - xs), np.minimum(ys + 1, h - ys)).astype(np.int64)
    near = edge * edge
    if blocked.any():
        if cells_clear is None:
            from scipy.ndimage import distance_transform_edt

            cells_clear = distance_transform_edt(~blocked)
        near = np.minimum(near, np.rint(cells_clear * cells_clear).astype(np.int64))
    return np.ascontiguousarray(near)


def _cell_mask(shape, x, y) -> np.ndarray:
    mask = np.zeros(shape, dtype=bool)
    if 0 <= y < shape[0] and 0 <= x < shape[1]:
        mask[y, x] = True
    return mask


def _shortcut(kinds, lengths, start, r, motion, blocked, clear, lattice, common):
    """Greedy smoothing: from each waypoint, jump to the farthest later waypoint
    whose exact Dubins/Reeds–Shepp path is shorter and collision-free. Segments in and out as
    (kinds, signed lengths [m]) arrays."""
    return _shortcut_kernel(kinds, lengths, *start, r, motion == "reeds_shepp", blocked, common[0], lattice.ds,
                            *common[1:], clear, lattice.clear_disc, lattice.vertices, lattice.disc, exact_grow(lattice))


@njit(cache=True)
def _shortcut_kernel(seg_kinds, seg_lengths, x, y, theta, radius, reverse, blocked, res, ds, theta0, step, bins,
                     pose_cells, pose_start, clear, clear_disc, vertices, disc, grow):
    """:func:`_shortcut` in one compiled call: the waypoints (the pose after each segment, as
    :meth:`CurvePath.end` computes it), then from each the farthest shortcut
    (:func:`_farthest_shortcut`). Returns the smoothed segments' kinds and lengths [m]."""
    n = seg_kinds.shape[0]
    waypoints = np.empty((n + 1, 3))
    waypoints[0, 0], waypoints[0, 1], waypoints[0, 2] = x, y, theta
    acc = np.zeros(n + 1)  # cumulative length along the original path
    for i in range(n):
        px, py, pt = advance(waypoints[i, 0], waypoints[i, 1], waypoints[i, 2], seg_kinds[i], seg_lengths[i], radius)
        waypoints[i + 1, 0], waypoints[i + 1, 1], waypoints[i + 1, 2] = px, py, _wrap_compiled(pt)
        acc[i + 1] = acc[i] + abs(seg_lengths[i])
    kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    lengths = np.zeros(MAX_SEGMENTS)
    out_kinds = np.empty(n * MAX_SEGMENTS, dtype=np.int64)  # a shortcut replaces at least two segments
    out_lengths = np.empty(n * MAX_SEGMENTS)
    used_out = 0
    i = 0
    while i < n:
        before = _direction(out_lengths[used_out - 1]) if used_out > 0 else 0
        j, used = _farthest_shortcut(waypoints, acc, seg_lengths, before, i, radius, reverse, blocked, res, ds,
                                     theta0, step, bins, pose_cells, pose_start, clear, clear_disc, vertices, disc,
                                     grow, kinds, lengths)
        if j > 0:
            out_kinds[used_out:used_out + used] = kinds[:used]
            out_lengths[used_out:used_out + used] = lengths[:used]
            used_out += used
            i = j
        else:
            out_kinds[used_out], out_lengths[used_out] = seg_kinds[i], seg_lengths[i]
            used_out += 1
            i += 1
    return out_kinds[:used_out], out_lengths[:used_out]


@njit(cache=True, inline="always")
def _direction(length) -> int:
    """+1 forward, -1 reverse (a segment's signed length), 0 for none."""
    return 1 if length > 0.0 else -1 if length < 0.0 else 0


@njit(cache=True)
def _checked_poses(x, y, theta, kinds, lengths, radius, ds, blocked, res, vertices, disc, grow, spacing, most, ox, oy,
                   yaw):
    """The path's independent re-check and its waypoints, in one compiled call (each call into compiled code
    costs a small query a few tens of microseconds right after another program has run: cold caches).

    The word from (x, y, θ) (grid frame) traced every ``ds`` and checked against the blocked cells grown by
    ``grow`` (:func:`~navlab.grid.hybrid_certify.first_overlap_exact`); then, unless more than ``most``, its
    poses every ``spacing`` [m] in the world frame (the grid's origin ``ox``, ``oy``, ``yaw``).
    Returns (overlaps, cell x, cell y, waypoints, world poses (N, 3), direction (N,)): none traced when it
    overlaps or needs more than ``most``."""
    traced, _ = trace_word(x, y, theta, kinds, lengths, radius, ds)
    overlaps, hx, hy = first_overlap_compiled(blocked, res, vertices, disc, traced, grow)
    count = word_poses(kinds, lengths, spacing)
    if overlaps or count > most:
        return overlaps, hx, hy, count, np.empty((0, 3)), np.empty(0, dtype=np.int8)
    poses, direction = trace_word(x, y, theta, kinds, lengths, radius, spacing)
    c, s = math.cos(yaw), math.sin(yaw)
    for i in range(poses.shape[0]):
        px, py = poses[i, 0], poses[i, 1]
        poses[i, 0], poses[i, 1], poses[i, 2] = ox + c * px - s * py, oy + s * px + c * py, poses[i, 2] + yaw
    return overlaps, hx, hy, count, poses, direction


@njit(cache=True)
def _cusps(before, lengths, after) -> int:
    """The changes of direction along segments ``lengths`` [m] (signed) between a segment going
    ``before`` and one going ``after`` (+1, -1, or 0 for none)."""
    count = 0
    last = before
    for k in range(lengths.shape[0]):
        d = _direction(lengths[k])
        if d != 0:
            if last != 0 and d != last:
                count += 1
            last = d
    if after != 0 and last != 0 and after != last:
        count += 1
    return count


@njit(cache=True)
def _farthest_shortcut(waypoints, acc, seg_lengths, before, i, radius, reverse, blocked, res, ds, theta0, step,
                       bins, pose_cells, pose_start, clear, clear_disc, vertices, disc, grow, kinds, lengths):
    """The farthest waypoint j > i + 1 whose shortest path from waypoint i is
    shorter than the path between them, changes direction no more often (``seg_lengths``: the
    original path's signed segment lengths, ``before``: the direction of the segment the smoothed
    path has just before waypoint i; a Reeds–Shepp shortcut would otherwise put a reversing jog of a
    few centimetres into a forward run to save less), and is collision-free, and how many
    segments that path has (written to ``kinds``, ``lengths`` [m], without
    padding and without segments of no length, as :meth:`CurvePath.of_word`
    drops them); (0, 0) when there is none. The same paths and lengths as
    :func:`dubins.shortest` / :func:`reeds_shepp.shortest`, without a Python
    call per candidate. The curve checks read the clearance map ``clear`` [m] with the lattice's
    ``clear_disc`` (:func:`~navlab.sampling.footprint_lattice.curve_free`: the same answers, sooner)."""
    seg = np.zeros(MAX_SEGMENTS)
    word_kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    word_lens = np.zeros(MAX_SEGMENTS)
    x0, y0, t0 = waypoints[i, 0], waypoints[i, 1], waypoints[i, 2]
    for j in range(waypoints.shape[0] - 1, i + 1, -1):
        x1, y1, t1 = waypoints[j, 0], waypoints[j, 1], waypoints[j, 2]
        if reverse:
            lx, ly, phi = reeds_shepp._local(x0, y0, t0, x1, y1, t1, radius)
            # the full solver's word, bit for bit, by branch and bound; none (inf) when its length is
            # surely no shorter than the stretch it would replace (widened by a relative 1e-9, far above
            # the rounding and the negligible segments dropped below), which the test below skips anyway
            cutoff = (acc[j] - acc[i] - 1e-9) / radius
            if reeds_shepp_length.word_below(lx, ly, phi, cutoff * (1.0 + 1e-9) + 1e-12, seg, word_kinds,
                                             word_lens) == math.inf:
                continue
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
        after = _direction(seg_lengths[j]) if j < seg_lengths.shape[0] else 0
        if reverse and _cusps(before, lengths[:used], after) > _cusps(before, seg_lengths[i:j], after):
            continue
        if curve_free(blocked, res, x0, y0, t0, kinds[:used], lengths[:used], radius, ds, theta0, step, bins,
                      pose_cells, pose_start, clear, clear_disc, vertices, disc, grow):
            return j, used
    return 0, 0
