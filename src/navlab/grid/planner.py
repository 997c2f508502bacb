"""Grid path planning: ``navlab.grid.plan`` and friends.

Algorithms (registered by name): ``dijkstra``, ``astar`` (weighted A* with
``weight > 1``), ``jps`` (Harabor & Grastien 2011; 8-connected, no corner
cutting) and ``theta_star`` (Nash et al. 2007; any-angle).

Heuristics (seed 002 eq. 4 for octile), in cells:

============  ======================  =====================  =====================
heuristic     formula                 4-connected            8-connected
============  ======================  =====================  =====================
manhattan     |dx| + |dy|             admissible, exact      NOT admissible:
                                      on open grids          paths may be longer
euclidean     sqrt(dx² + dy²)         admissible (weak)      admissible (weak)
chebyshev     max(|dx|, |dy|)         admissible (weak)      admissible (weak)
octile        max + (√2 − 1)·min      admissible (weak)      admissible, exact
                                                             on open grids
============  ======================  =====================  =====================

With an admissible, consistent heuristic A* returns an optimal path; with
Manhattan on an 8-connected grid it can return a longer one (it trades
optimality for fewer expansions), as does weighted A* (cost ≤ weight × optimum).
"""

from __future__ import annotations

import contextlib
import functools
import math
import numbers
import threading
import time
from typing import Any, Dict, Iterator, List, Optional, Tuple

import numpy as np

from ..compile_clock import compile_clock, first_call_seconds, hold_interrupts_while_compiling
from ..errors import ParameterError
from ..limits import check_coordinate, check_flag, check_weight, is_finite_real, shown
from ..registry import Registry
from ..result import Result, Status, Tree
from ..wording import counted
from . import kernels as K
from .occupancy import OccupancyGrid, check_grid

HEURISTICS: Registry[int] = Registry("heuristic")
# "none" is A* without a heuristic (uniform-cost search, Dijkstra's order): the name Dijkstra's results report
for _name, _code in (("manhattan", K.H_MANHATTAN), ("euclidean", K.H_EUCLIDEAN),
                     ("chebyshev", K.H_CHEBYSHEV), ("octile", K.H_OCTILE), ("none", K.H_ZERO)):
    HEURISTICS.register(_name)(_code)

GRID_ALGORITHMS: Registry[str] = Registry("grid algorithm")
for _name, _doc in (("dijkstra", "uniform-cost search (no heuristic: heuristic and weight do not apply)"),
                    ("astar", "A*; weighted A* with weight > 1"),
                    ("jps", "Jump Point Search (8-connected, optimal, no corner cutting; always octile, "
                            "weight does not apply)"),
                    ("theta_star", "Theta*: any-angle A* with line of sight (always Euclidean, weight does not "
                                   "apply)")):
    GRID_ALGORITHMS.register(_name)(_doc)

#: the heuristic each algorithm but A* searches with, whatever ``heuristic`` says (its params report this one)
OWN_HEURISTIC = {"dijkstra": "none", "jps": "octile", "theta_star": "euclidean"}


class PaddedGrid:
    """A grid's legal moves (``kernels.legal_moves``) and passable cells, each
    with a blocked border one cell wide, flattened: read-only, shared by every query
    (but for ``needs_wide``, a hint on the state's width that changes no answer).

    Each is built when first asked for, straight from ``blocked`` (and
    ``unknown`` cells, also closed unless None): ``strip_moves`` (the strip
    layout, ``kernels.strip_shape``: ``bits``, ``strip_height``, ``strip_size``)
    by A*, Dijkstra and Theta*, ``moves`` (padded rows of ``stride`` cells) by
    JPS, and ``free`` (one byte per padded cell, in rows) by Theta*, smoothing
    or line of sight: the pages of each were a first query's to map (about
    4100 for ``free`` on a 4096 x 4096 grid; ``kernels.legal_moves``). No
    whole-grid temporaries either, which on a first query cost as much as
    the search's own state (fresh pages). Two threads asking at once may
    both build one: equal arrays, either kept.
    """

    def __init__(self, blocked: np.ndarray, unknown: Optional[np.ndarray] = None) -> None:
        h, w = blocked.shape
        self.stride = w + 2
        self.rows = h + 2
        self.bits, self.strip_height, self.strip_size = K.strip_shape(self.rows, self.stride)
        if self.strip_size > 2**31:  # (kernels.divider's domain; MAX_CELLS grids stay far below)
            raise ParameterError(f"blocked: a {h}x{w} grid is too large to search (over 2**31 cells in strips)")
        self.blocked = blocked
        self.unknown = unknown if unknown is not None and unknown.any() else None
        # what the A* kernels get for ``free`` when they are not Theta*, the only one whose line of sight reads it
        self.no_free = np.zeros(1, dtype=np.uint8)
        self.no_free.flags.writeable = False
        # Set once a search on this grid outgrew the narrow packed state (kernels.WIDEN): every later
        # search on it, by any searcher, starts wide rather than search in vain first (on a 3002² maze
        # corner to corner that was 1.4-2.5x the time). It changes no answer: both widths hold the same
        # whole numbers, so their searches are the same; the one thing here that changes.
        self.needs_wide = False

    def _built(self, name: str, build) -> np.ndarray:
        """The read-only array ``name``, built by ``build()`` when first asked for. Not
        ``functools.cached_property``: on Python 3.11 its lock is one for all grids, so a thread
        building one grid's array would hold up every other thread's first query on any grid."""
        array = self.__dict__.get(name)
        if array is None:
            array = build()
            array.flags.writeable = False
            array = self.__dict__.setdefault(name, array)
        return array

    def _legal_moves(self, bits: int, size: int) -> np.ndarray:
        closed = np.zeros((0, 0), dtype=bool) if self.unknown is None else self.unknown
        # one byte per cell; numpy's allocation (huge pages, kernels.legal_moves)
        return K.legal_moves(self.blocked, closed, np.empty(size, dtype=np.uint8), bits)

    @property
    def strip_moves(self) -> np.ndarray:
        """The legal moves A*, Dijkstra and Theta* read, in the strip layout."""
        return self._built("strip_moves", lambda: self._legal_moves(self.bits, self.strip_size))

    @property
    def moves(self) -> np.ndarray:
        """The legal moves JPS reads, in padded rows."""
        return self._built("moves", lambda: self._legal_moves(-1, self.rows * self.stride))

    @property
    def free(self) -> np.ndarray:
        """Passable cells as 0/1 bytes, padded."""
        return self._built("free", self._free)

    def _free(self) -> np.ndarray:
        h, w = self.blocked.shape
        padded = np.zeros((h + 2, w + 2), dtype=np.uint8)
        inner = padded[1:-1, 1:-1].view(np.bool_)
        np.logical_not(self.blocked, out=inner)
        if self.unknown is not None:
            inner[self.unknown] = False
        return padded.ravel()

    def is_free(self, x: int, y: int) -> bool:
        return not self.blocked[y, x] and not (self.unknown is not None and self.unknown[y, x])

    def index(self, x: int, y: int) -> int:
        """Cell (x, y)'s index in padded rows."""
        return (y + 1) * self.stride + (x + 1)

    def strip_index(self, x: int, y: int) -> int:
        """Cell (x, y)'s index in the strip layout (``kernels.strip_index``)."""
        return int(K.strip_index(x + 1, y + 1, self.strip_height, self.bits))


class GridSearcher:
    """Scratch state for one query at a time on one grid (per-cell state, open lists).

    Queries lease one from the grid's :class:`SearcherPool`, so threads planning
    on the same grid never share it; a searcher is reused by later queries,
    so only the first query on a grid (per concurrent thread) pays for its
    arrays. ``state`` holds A*'s and Dijkstra's per-cell state, packed in 32
    bits (``kernels.state_layout``; ``state_wide``, 64, on a grid where a path
    was too long for that: ``PaddedGrid.needs_wide``), ``g`` Theta*'s (one
    float64 per cell), which also adds ``parent``, all in the strip layout
    (``kernels.strip_shape``); ``row_state`` and ``row_state_wide`` hold JPS's,
    in padded rows, at the start of ``state``'s and ``state_wide``'s memory (never
    used at once: a grid searched by A* and JPS keeps 4 bytes of state per cell,
    not 8). Each is allocated when first used. Only ``written`` holds
    anything but zeros, and the next query clears what the last one wrote
    there: the blocks marked in ``flags`` (``kernels.clear_blocks``), or in
    rows the spans ``lo``, ``hi`` and ``extent`` record
    (``kernels.clear_touched``).
    """

    #: the state arrays in padded rows (JPS's), each the start of a strip-layout array's memory
    ROW_STATES = {"row_state": "state", "row_state_wide": "state_wide"}

    def __init__(self, grid: PaddedGrid) -> None:
        self.stride = grid.stride
        self.grid = grid
        rows = grid.rows
        # zero pages are mapped when first written: a search pays for the cells it reaches
        narrow, wide = K.state_layout(False)[0], K.state_layout(True)[0]
        self.state, self.state_wide = np.zeros(0, dtype=narrow), np.zeros(0, dtype=wide)
        self.row_state, self.row_state_wide = np.zeros(0, dtype=narrow), np.zeros(0, dtype=wide)
        self.g = np.zeros(0)
        self.written = self.g  # the array the records below describe (all the others are zero)
        self.parent = np.empty(0, dtype=np.int32)
        self.flags = np.zeros(-(-grid.strip_size >> K.BLOCK_BITS), dtype=np.uint8)  # blocks written (strips)
        self.lo = np.full(rows, self.stride, dtype=np.int64)  # columns each row's expansions spanned (rows)
        self.hi = np.full(rows, -1, dtype=np.int64)
        self.extent = np.array([rows, -1], dtype=np.int64)  # and the rows they spanned
        # The open list (a bucket queue's node pool) and the same-f stack;
        # grown (and the query rerun) if one fills up.
        room = min(grid.strip_size + 16, 1 << 16)
        self.stack = np.empty(room, dtype=np.int64)
        self._pool(room)

    def _pool(self, room: int) -> None:
        self.key = np.empty(room)
        self.cell = np.empty(room, dtype=np.int64)  # JPS's entries carry a move: cell * 16 + move
        self.next = np.empty(room, dtype=np.int32)
        self.head = np.empty(K.N_BUCKETS, dtype=np.int32)

    def _indices(self, algorithm: str, start, goal) -> Tuple[int, int]:
        """Cells ``start`` and ``goal`` (x, y) as the flat indices ``algorithm``'s kernel reads: in rows
        for JPS, else in the strip layout."""
        index = self.grid.index if algorithm == "jps" else self.grid.strip_index
        return index(*start), index(*goal)

    def search(self, algorithm: str, start, goal, connectivity: int, hcode: int, weight: float) -> Tuple[int, int]:
        """One query from cell ``start`` to cell ``goal`` (x, y; a padded border cell such as (-1, -1) is a
        goal never reached), rerun with larger open lists until they suffice, and in the wide state if its
        path outgrew the narrow one (A* and Dijkstra go on where they stopped, JPS starts over):
        (status, expanded) as the kernels return."""
        grid = self.grid
        a, b = self._indices(algorithm, start, goal)
        if algorithm == "theta_star" and self.parent.size == 0:
            self.parent = np.empty(grid.strip_size, dtype=np.int32)
        resume, before = False, 0  # (expanded by the narrow search a resumed one goes on from)
        while True:
            wide = grid.needs_wide
            if algorithm == "jps":
                state = self._writing("row_state_wide" if wide else "row_state")
                status, expanded = jps_kernel(wide)(grid.moves, self.stride, a, b, state, self.lo, self.hi,
                                                    self.extent, self.key, self.cell, self.next, self.head, self.stack)
            else:
                any_angle = algorithm == "theta_star"
                wide = wide and not any_angle
                kernel = astar_kernel(connectivity, hcode, any_angle, wide)
                free = grid.free if any_angle else grid.no_free
                state = self.written if resume else self._writing("g" if any_angle else "state_wide" if wide
                                                                  else "state")
                status, expanded = kernel(free, self.stride, grid.strip_moves, grid.strip_height, grid.bits, a, b,
                                          weight, state, self.parent, self.flags, self.key, self.cell, self.next,
                                          self.head, self.stack, resume)
            if status == K.WIDEN and not resume and not wide and algorithm != "jps":
                # a path of over 32 766 straight or 65 535 diagonal moves (a big maze's): the stopped search's
                # state moves to the wide array, where it goes on (make_maze(300, 300, seed=1) corner to corner:
                # 146 ms, against 129 for a search wide from the start; starting over took 1.4-2.5x that)
                grid.needs_wide = True
                narrow = self.state
                self._writing("state_wide", keep_records=True)
                K.widen_state(narrow, self.state_wide, self.flags)
                resume, before = True, expanded
            elif status == K.WIDEN:  # JPS, or a resumed search whose open keys did not fit: start over wide
                grid.needs_wide = True
                resume, before = False, 0
            elif status == K.OVERFLOW:
                self.grow()  # (a resumed search that ran out of room may have half-expanded a cell: start over)
                resume, before = False, 0
            else:
                return status, before + expanded

    def _writing(self, name: str, keep_records: bool = False) -> np.ndarray:
        """The state array ``name`` (allocated at first use), once what the last query wrote in another
        is cleared (``keep_records``: left for the caller to move, :func:`kernels.widen_state`, and the
        records then describe ``name``): only ``written`` ever holds anything but zeros."""
        array = getattr(self, name)
        if array.size == 0:
            strips = self.ROW_STATES.get(name, name)
            memory = getattr(self, strips)
            if memory.size == 0:
                memory = np.zeros(self.grid.strip_size, dtype=memory.dtype)
                setattr(self, strips, memory)
            array = memory[:self.grid.rows * self.stride] if name in self.ROW_STATES else memory
            setattr(self, name, array)
        if array is not self.written:
            if not keep_records:
                self.clear()
            self.written = array
        if name in ("state_wide", "row_state_wide"):  # once wide, never narrow again: its bytes go
            for narrow in ("state", "row_state"):
                setattr(self, narrow, np.zeros(0, dtype=getattr(self, narrow).dtype))
        return array

    def _written_in_rows(self) -> bool:
        return any(self.written is getattr(self, name) for name in self.ROW_STATES)

    def clear(self) -> None:
        """Zero what the last query wrote in ``written`` (by its records, which are left empty)."""
        if self._written_in_rows():
            K.clear_touched(self.written, self.stride, self.lo, self.hi, self.extent)
        else:
            K.clear_blocks(self.written, self.flags)

    def written_rows(self) -> np.ndarray:
        """``written`` in padded rows ``(rows, stride)`` (a copy), whichever its layout."""
        if self._written_in_rows():
            return self.written.reshape(self.grid.rows, self.stride).copy()
        return K.to_rows(self.written, self.grid.rows, self.stride)

    def cells(self, algorithm: str, connectivity: int, start, goal) -> np.ndarray:
        """The path the last search (from cell ``start``, which reached cell ``goal``) found, as cells (x, y)."""
        grid = self.grid
        a, b = self._indices(algorithm, start, goal)
        if algorithm == "theta_star":
            return K.trace_path(self.parent, b, grid.strip_height, grid.bits)
        wide = self.written is self.state_wide or self.written is self.row_state_wide
        if algorithm == "jps":
            cells = K.trace_jumps(grid.moves, self.stride, self.written, a, b, *_TRACE_BACK[wide])
        else:
            cells = K.trace_back(grid.strip_moves, grid.strip_height, grid.bits, self.written, a, b, connectivity,
                                 *_TRACE_BACK[wide])
        if len(cells) == 0:  # impossible after a successful search (kernels.trace_back); never report it as found
            raise RuntimeError(f"grid search state broken: no predecessor chain from {goal} back to {start}")
        return cells

    def grow(self) -> None:
        self.stack = np.empty(self.stack.shape[0] * 4, dtype=np.int64)
        self._pool(self.key.size * 4)


@functools.lru_cache(maxsize=None)
def astar_kernel(connectivity: int, hcode: int, any_angle: bool, wide: bool = False):
    """The compiled A* variant for these settings (see ``kernels.make_astar``)."""
    return K.make_astar(connectivity, hcode, any_angle, wide)


@functools.lru_cache(maxsize=None)
def jps_kernel(wide: bool = False):
    """JPS compiled for the narrow or wide state (see ``kernels.make_jps``)."""
    return K.make_jps(wide)


#: kernels.trace_back's last two arguments, for the narrow (False) and wide (True) state
_TRACE_BACK = {wide: K.trace_back_args(wide) for wide in (False, True)}


class SearcherPool:
    """The searchers of one grid: a query leases one for its whole length
    (search, path tracing, smoothing) and gives it back. Thread-safe: two
    threads planning on the same grid at once each get their own."""

    def __init__(self, blocked: np.ndarray, unknown: Optional[np.ndarray] = None) -> None:
        self.grid = PaddedGrid(blocked, unknown)
        self._idle: list = []
        self._lock = threading.Lock()

    @contextlib.contextmanager
    def lease(self) -> Iterator[GridSearcher]:
        with self._lock:
            searcher = self._idle.pop() if self._idle else None
        if searcher is None:
            searcher = GridSearcher(self.grid)
        try:
            yield searcher
        finally:
            with self._lock:
                self._idle.append(searcher)


#: what opens unknown cells to a search, as a reason names it
OPENS_UNKNOWN = ("allow_unknown=true opens them, as --param allow_unknown=true to navlab plan or --allow-unknown to "
                 "navlab grid plan")


def unknown_hint(grid: OccupancyGrid, allow_unknown: bool) -> str:
    """What a failed search on a map with unknown cells adds to its reason: they were closed to it."""
    if allow_unknown or not grid.unknown.any():
        return ""
    return (f"; the map's {int(np.count_nonzero(grid.unknown & ~grid.blocked))} unknown cells were closed to the "
            f"search: {OPENS_UNKNOWN}")


def pool_for(grid: OccupancyGrid, allow_unknown: bool) -> SearcherPool:
    """The grid's searcher pool (kept in the immutable grid's cache)."""
    key = ("searchers", allow_unknown)
    pool = grid._cache.get(key)
    if pool is None:
        # setdefault is atomic: two threads' first queries end up sharing one pool
        # (a grid built without unknown cells passes none: 0.9 ms of a fresh 4096² grid's first query went
        # on reading its 16 MB of zeros)
        closed = None if allow_unknown or grid._no_unknown else grid.unknown
        pool = grid._cache.setdefault(key, SearcherPool(grid.blocked, closed))
    return pool


def _cell(value, what: str) -> Tuple[int, int]:
    try:
        if not isinstance(value, (tuple, list, np.ndarray)):  # a set or a dict would unpack too
            raise TypeError
        x, y = value
        # a number, and a bool is none (True would be cell 1)
        if all(isinstance(c, numbers.Real) and not isinstance(c, (bool, np.bool_)) for c in (x, y)) \
                and int(x) == x and int(y) == y:
            return int(x), int(y)
    except (TypeError, ValueError, OverflowError):  # not a pair, NaN, inf
        pass
    raise ParameterError(f"{what} must be an integer cell (x, y), got {value!r}")


#: The stats every grid Result carries, whatever its status (inf where there is no path).
STATS_KEYS = ("expanded", "time_s", "cost_cells", "length_m", "raw_cost_cells", "warmup_s")


def check_connectivity(value: Any) -> int:
    """A grid search's ``connectivity``, 4 or 8, as a Python int (numpy's ints and whole floats too: an np.int64
    was refused by navlab.plan, and kept as one in navlab.grid.plan's params, which JSON cannot hold)."""
    if not is_finite_real(value) or value not in (4, 8):
        raise ParameterError(f"connectivity must be 4 or 8, got {shown(value)}")
    return int(value)


def check_jps_connectivity(algorithm: str, connectivity: int) -> None:
    """JPS prunes the 8-connected grid's symmetric paths: it searches no other (checked after the value's
    own check, which names a connectivity that is neither 4 nor 8)."""
    if algorithm == "jps" and connectivity != 8:
        raise ParameterError("jps needs connectivity 8")


def settings_ignored(algorithm: str, settings: Optional[Dict[str, Any]] = None) -> Tuple[str, ...]:
    """The grid settings ``algorithm`` searches without, whatever values they are given: Dijkstra, JPS and
    Theta* have their own heuristic (:data:`OWN_HEURISTIC`), only A* takes a weight, and A* with heuristic
    ``none`` in ``settings`` takes none either (a weight times no heuristic is none)."""
    no_weight = algorithm != "astar" or (settings or {}).get("heuristic") == "none"
    return (("heuristic",) if algorithm in OWN_HEURISTIC else ()) + (("weight",) if no_weight else ())


def as_searched(algorithm: str, **settings: Any) -> Dict[str, Any]:
    """``settings`` with the ``heuristic`` and ``weight`` among them as ``algorithm`` searches with them
    (:func:`settings_ignored`). What a result's params report (they said 'manhattan' and 3.0 for a Dijkstra
    search given them, which used neither)."""
    out = dict(settings)
    ignored = settings_ignored(algorithm, settings)
    if "heuristic" in out and "heuristic" in ignored:
        out["heuristic"] = OWN_HEURISTIC[algorithm]
    if "weight" in out and "weight" in ignored:
        out["weight"] = 1.0
    return out


def unused_settings(algorithm: str, settings: Dict[str, Any], spelled) -> List[str]:
    """A note for each of the ``heuristic`` and ``weight`` in ``settings`` (those the user gave; any
    other key is passed over) that ``algorithm`` does not use: Dijkstra, JPS and Theta* have their own
    heuristic, only A* takes a weight, and A* with heuristic ``none`` none (the result's params say what
    the search used). ``spelled(key, value)`` is how the user wrote it (``--heuristic manhattan``,
    ``--param heuristic=manhattan``). Rather than a run that silently searched without them (newcomer
    run, session 19)."""
    given = {key: settings[key] for key in ("heuristic", "weight") if key in settings}
    used = as_searched(algorithm, **given)  # the rule the search and its params follow
    lines = []
    if "heuristic" in given and used["heuristic"] != given["heuristic"]:
        uses = "no heuristic" if used["heuristic"] == "none" else f"its own heuristic ({used['heuristic']})"
        lines.append(f"note: {algorithm} searches with {uses}: {spelled('heuristic', given['heuristic'])} is not used")
    if "weight" in given and used["weight"] != given["weight"]:
        # (worded as the heuristic's note, in the present: the ROS planner says it at start-up, before any plan)
        who, why = ("astar with heuristic none", "a weight scales the heuristic") if algorithm == "astar" else \
            (algorithm, "of the grid planners only astar takes a weight")
        lines.append(f"note: {who} searches unweighted ({why}): {spelled('weight', given['weight'])} is not used")
    return lines


def path_bound_note(params: Dict[str, Any]) -> Optional[str]:
    """What an A* path's length is known to be against the shortest, from the settings it searched with (a
    result's params), where it may be longer: EXACT says the goal was reached, and a weight-3 path of 67.46
    cells beside a 51.01-cell optimum was read as the shortest (newcomer check, session 21).

    Parameters
    ----------
    params : dict
        A grid result's params (``heuristic``, ``connectivity`` and ``weight`` as searched, :func:`as_searched`).

    Returns
    -------
    str or None
        The note, or None when the path is a shortest one.
    """
    weight = params.get("weight")
    weight = weight if isinstance(weight, (int, float)) else 1.0
    if params.get("heuristic") == "manhattan" and params.get("connectivity") == 8:
        return ("manhattan on 8 connections overestimates a diagonal move (not admissible): the path may be "
                "longer than the shortest, by no stated bound (octile is exact there)")
    if weight > 1.0:
        return (f"weighted A* (weight {weight:g}): at most {weight:g} times the shortest path's length, "
                "usually far less (weight 1 finds the shortest)")
    return None


def search_heuristic(algorithm: str, hcode: int) -> int:
    """The heuristic code ``algorithm``'s kernel searches with, given ``hcode`` for A*: its
    :data:`OWN_HEURISTIC`'s, so the code and the name the params report cannot disagree."""
    own = OWN_HEURISTIC.get(algorithm)
    if own is None:
        return hcode
    return K.H_ZERO if own == "none" else HEURISTICS.get(own)


@functools.lru_cache(maxsize=None)
def _warmed(algorithm: str, connectivity: int, hcode: int, smooth: bool) -> float:
    t0 = time.perf_counter()
    blocked = np.zeros((4, 4), dtype=bool)
    blocked[1:3, 2] = True
    pool = pool_for(OccupancyGrid(blocked), False)
    code = search_heuristic(algorithm, hcode)
    with pool.lease() as s:
        s.search(algorithm, (0, 1), (3, 2), connectivity, code, 1.0)
        cells = s.cells(algorithm, connectivity, (0, 1), (3, 2))
    if smooth:
        for bresenham in (True, False):
            K.smooth_path(pool.grid.free, pool.grid.stride, np.ascontiguousarray(cells), bresenham)
    K.step_counts(np.ascontiguousarray(cells, dtype=np.int64))
    return time.perf_counter() - t0


def warm_kernels(algorithm: str, connectivity: int, hcode: int, smooth: bool) -> float:
    """Seconds spent compiling or loading this variant's kernels: on a tiny grid,
    the first time in this process; 0.0 afterwards."""
    hold_interrupts_while_compiling()  # a Ctrl-C during the compile is not lost (navlab.compile_clock)
    return first_call_seconds(_warmed, algorithm, connectivity, hcode, smooth)


def _stats(t0: float, expanded: int = 0, cost_cells: float = math.inf, raw_cost_cells: float = math.inf,
           resolution: float = 1.0, warmup_s: float = 0.0) -> Dict[str, Any]:
    return {"expanded": int(expanded), "time_s": time.perf_counter() - t0, "cost_cells": cost_cells,
            "length_m": cost_cells * resolution, "raw_cost_cells": raw_cost_cells, "warmup_s": warmup_s}


def path_cost(cells: np.ndarray) -> float:
    """Length in cells: exact octile sum for 8-neighbour steps, Euclidean for longer ones."""
    straight, diagonal, rest = K.step_counts(np.ascontiguousarray(cells, dtype=np.int64))
    return straight + diagonal * math.sqrt(2.0) + rest


def line_of_sight(grid: OccupancyGrid, a, b, method: str = "supercover", allow_unknown: bool = False) -> bool:
    """Whether cells ``a`` and ``b`` (x, y) see each other over free cells.

    ``method="supercover"`` checks every cell the segment between the cell
    centres touches; ``"bresenham"`` checks the cells of the Bresenham line
    (and never cuts a blocked corner on a diagonal step).
    """
    check_grid(grid)
    if method not in ("supercover", "bresenham"):
        raise ParameterError(f"method must be 'supercover' or 'bresenham', got {method!r}")
    (ax, ay), (bx, by) = _cell(a, "a"), _cell(b, "b")
    if not (grid.contains([[ax, ay]])[0] and grid.contains([[bx, by]])[0]):
        return False
    s = pool_for(grid, allow_unknown).grid
    if not s.is_free(ax, ay):
        return False
    fn = K.los_bresenham if method == "bresenham" else K.los_supercover
    return bool(fn(s.free, s.stride, ax, ay, bx, by))


def plan(grid: OccupancyGrid, start, goal, algorithm: str = "astar", heuristic: str = "octile",
         connectivity: int = 8, smooth: bool = False, weight: float = 1.0, allow_unknown: bool = False,
         smooth_method: str = "bresenham") -> Result:
    """Plan on an occupancy grid between cells ``start`` and ``goal`` (x, y): the cell-level function.

    Start and goal are cells, and the path joins cell centres; for metres use
    :func:`plan_world`, or ``navlab.plan`` for every source and planner.

    Parameters
    ----------
    grid : OccupancyGrid
    start, goal : (int, int)
        Cells as (x, y) = (column, row).
    algorithm : {"astar", "dijkstra", "jps", "theta_star"}
    heuristic : {"octile", "euclidean", "chebyshev", "manhattan", "none"}
        For ``astar``; ``none`` is no heuristic (uniform-cost search). JPS uses octile, Theta* Euclidean and
        Dijkstra none, whatever this says; the result's ``params`` name the one used (:data:`OWN_HEURISTIC`).
    connectivity : {4, 8}
        8 allows diagonal moves only when both orthogonal neighbours are free.
    smooth : bool
        Shortcut the path along lines of sight (seed 002's Bresenham smoothing).
    weight : float
        Weighted A* (≥ 1); cost ≤ weight × optimum. For ``astar`` only (the others report 1.0).
    allow_unknown : bool
        Let the search enter cells of unknown occupancy.
    smooth_method : {"bresenham", "supercover"}

    Returns
    -------
    Result
        ``cells`` (N, 2) int (x, y), ``path`` (world coordinates of cell
        centres), ``cost`` (path length in **metres**, as for every navlab
        planner), ``stats`` with the same keys whatever the status
        (:data:`STATS_KEYS`): ``expanded``, ``time_s``, ``cost_cells`` (length
        in cells: 1 per straight step, √2 per diagonal, Euclidean between
        smoothed waypoints), ``length_m`` (= ``cost``), ``raw_cost_cells``
        (before smoothing), ``inf`` where there is no path, and ``warmup_s``
        (the kernels' compile or cache load before the query, apart from
        ``time_s``). When smoothed,
        ``tree = {"raw_cells": ...}``, the path before smoothing (for drawing).

    References
    ----------
    P. E. Hart, N. J. Nilsson, B. Raphael, "A formal basis for the heuristic
    determination of minimum cost paths", IEEE TSSC 4(2), 1968.
    D. Harabor, A. Grastien, "Online graph pruning for pathfinding on grid
    maps", AAAI 2011.
    A. Nash, K. Daniel, S. Koenig, A. Felner, "Theta*: any-angle path planning
    on grids", AAAI 2007.
    """
    check_grid(grid)
    GRID_ALGORITHMS.get(algorithm)
    hcode = HEURISTICS.get(heuristic)
    connectivity = check_connectivity(connectivity)
    # (before the warm-up: smooth=np.array([True, False]) was numpy's "truth value ... is ambiguous", and
    # smooth="no" compiled the smoothing kernels before it was refused: attack, session 25)
    smooth = check_flag("smooth", smooth)
    # compiling or loading this variant's kernels is timed apart (stats["warmup_s"]), as navlab.plan does:
    # it was 240–440 ms of a 0.7 ms search on a first call
    warmup_s = warm_kernels(algorithm, connectivity, hcode, smooth)
    # a signature the warm-up did not compile (another map's array types) is compiled in the call: warm-up too
    with compile_clock() as compiled:
        result = _plan_warm(grid, start, goal, algorithm, heuristic, hcode, connectivity, smooth, weight,
                            allow_unknown, smooth_method, warmup_s)
    return compiled.moved_to_warmup(result)


def _plan_warm(grid: OccupancyGrid, start, goal, algorithm: str, heuristic: str, hcode: int, connectivity: int,
               smooth: bool, weight: float, allow_unknown: bool, smooth_method: str, warmup_s: float) -> Result:
    """:func:`plan` once its kernels are warm: the checks, the search and the path, timed (``time_s``)."""
    t0 = time.perf_counter()
    weight = check_weight(weight)
    smooth, allow_unknown = check_flag("smooth", smooth), check_flag("allow_unknown", allow_unknown)
    if smooth_method not in ("bresenham", "supercover"):
        raise ParameterError(f"smooth_method must be 'bresenham' or 'supercover', got {smooth_method!r}")
    check_jps_connectivity(algorithm, connectivity)
    params: Dict[str, Any] = {"algorithm": algorithm, **as_searched(algorithm, heuristic=heuristic, weight=weight),
                              "connectivity": connectivity, "smooth": smooth, "allow_unknown": allow_unknown,
                              "smooth_method": smooth_method}
    s_cell, g_cell = _cell(start, "start"), _cell(goal, "goal")
    pool = pool_for(grid, allow_unknown)
    for label, cell, status in (("start", s_cell, Status.INVALID_START), ("goal", g_cell, Status.INVALID_GOAL)):
        if not (0 <= cell[0] < grid.width and 0 <= cell[1] < grid.height):
            return Result(status=status, params=params, stats=_stats(t0, warmup_s=warmup_s), cells=np.empty((0, 2), dtype=np.int64),
                          reason=f"{label} cell {cell} is outside the {grid.width}x{grid.height} grid")
        if not pool.grid.is_free(*cell):
            kind = f"unknown; {OPENS_UNKNOWN}" \
                if grid.unknown[cell[1], cell[0]] and not grid.blocked[cell[1], cell[0]] else "blocked"
            return Result(status=status, params=params, stats=_stats(t0, warmup_s=warmup_s), cells=np.empty((0, 2), dtype=np.int64),
                          reason=f"{label} cell {cell} is {kind}")
    code = search_heuristic(algorithm, hcode)
    with pool.lease() as s:  # the search state belongs to this call until the path is read out
        status, expanded = s.search(algorithm, s_cell, g_cell, connectivity, code,
                                    float(weight) if algorithm == "astar" else 1.0)
        if status != 1:
            return Result(status=Status.FAILED, params=params, stats=_stats(t0, expanded, warmup_s=warmup_s),
                          cells=np.empty((0, 2), dtype=np.int64),
                          reason=f"no path from {s_cell} to {g_cell} ({counted(expanded, 'cell')} expanded)" + unknown_hint(
                              grid, allow_unknown))
        cells = s.cells(algorithm, connectivity, s_cell, g_cell)
    raw = None
    raw_cost = path_cost(cells)
    if smooth and len(cells) > 2:
        raw = cells
        cells = K.smooth_path(pool.grid.free, pool.grid.stride, np.ascontiguousarray(cells),
                              smooth_method == "bresenham")
    cost = path_cost(cells) if raw is not None else raw_cost
    stats = _stats(t0, expanded, cost, raw_cost, grid.resolution, warmup_s)
    return Result(status=Status.EXACT, path=grid.cell_to_world(cells), cost=stats["length_m"], stats=stats,
                  params=params, cells=cells, tree=None if raw is None else Tree(raw_cells=raw))


def plan_world(grid: OccupancyGrid, start_xy, goal_xy, **kwargs: Any) -> Result:
    """:func:`plan` with start and goal in world coordinates (metres).

    Coordinates must be finite and within ±MAX_COORDINATE (:mod:`navlab.limits`);
    the cells containing them are planned between.
    """
    check_grid(grid)
    points = []
    for label, xy in (("start", start_xy), ("goal", goal_xy)):
        try:
            x, y = xy
        except (TypeError, ValueError):
            raise ParameterError(f"{label} must be a point (x, y) in metres, got {xy!r}") from None
        points.append((check_coordinate(f"{label} x", x), check_coordinate(f"{label} y", y)))
    cells = grid.world_to_cell(np.array(points, dtype=float))
    return plan(grid, tuple(cells[0]), tuple(cells[1]), **kwargs)
