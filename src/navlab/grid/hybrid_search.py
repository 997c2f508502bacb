"""Hybrid A*'s compiled search: the heuristic and the loop.

The planner (:func:`navlab.grid.hybrid_astar.plan_hybrid`) sets up the map, the
lattice and the holonomic field (:mod:`navlab.grid.hybrid_field`, settled lazily
as the search reads it), then calls :func:`search`; this module holds only the
compiled kernels. The loop is Dolgov et al.'s ("Path planning for autonomous
vehicles in unknown semi-structured environments", IJRR 29(5), 2010): one
continuous pose per discrete state (cell, heading bin), three primitives per
driving direction, closed states never re-opened. Nodes are keyed g / w + h,
the order of weighted A*'s g + w·h (``plan_hybrid``'s ``weight``; 1 by
default); "g" below is that share of a key.

Two choices make it fast without changing which nodes it expands:

- **lazy heuristic** for Reeds–Shepp motion (Lazy A*: Tolpin, Beja, Shimony,
  Felner and Karpas, "Toward rational deployment of multiple heuristics in
  A*", IJCAI 2013): a child enters the queue keyed by ``g + field`` — the
  holonomic field alone, a lower bound of the heuristic ``max(field, exact
  distance)`` — and the exact distance is solved only when that entry reaches
  the top. If it raises the key the entry goes back in with the true key, else
  it is expanded at once. An entry reaching the top under a lower bound is no
  later than under its true key, and every other entry's true key is at least
  its queue key, so the entry expanded next is the one an eager queue would
  pop: the same least ``(key, node)`` pair, ties broken by node number as the
  eager ``heapq`` of ``(key, node)`` tuples did. Most entries need no solve:
  an upper bound on the distance that is no more than the field, or below
  the next key, settles the order (first the same-side words,
  :func:`~navlab.sampling.reeds_shepp_length.same_side_above`, then the
  Dubins length). Entries popped for a state
  already closed are dropped unsolved, and so are entries still queued when
  the search ends (on the 384² bench map 17 000 solves for 130 000 children).
  A Dubins solve costs little more than putting it off, so Dubins keys are
  computed when the child is queued;
- **dense state index**: a state's node is found through a per-cell block of
  slots, allocated the first time the cell is reached (no hash map): a slot
  for each heading bin the search can reach (an arc turns k bins, so a
  quarter of them at 72 bins and k = 4), a quarter of the memory to miss.

And a few choices keep numba from slowing it down: the loop (:func:`_expand`)
indexes its arrays through ``np.uint64`` where the index cannot be negative
(numba wraps a signed index around the array's length first: a few
instructions an access, and registers for the lengths); :func:`_open`, called
for each child, is inlined by numba (called, it counted the references of the
heap's three arrays, with locked atomic adds, every time); and the loop never
replaces an array. Numba reference-counts an array variable that a loop
may reassign on every pass, with locked atomic adds (12 % of the
PythonRobotics demo query when the arrays grew inside the loop), so the loop
returns when one needs room and :func:`search` grows it between two calls.
"""

from __future__ import annotations

import math
import threading

import numpy as np

from ..jit import njit
from ..sampling import dubins, reeds_shepp, reeds_shepp_length
from ..sampling.curves import MAX_SEGMENTS, NOP
from ..sampling.reeds_shepp import _local
from ..sampling.footprint_lattice import curve_free, free_cells_near, swept_group
from .floor_cells import floor_div
from .hybrid_field import PASSABLE, SETTLED, field_cells_grown, field_settle_within
from .hybrid_table import reeds_shepp_memo, table_pose

#: relative slack under which a Dubins length no longer settles that the Reeds–Shepp one is below the field
GATE_MARGIN = 1e-9


@njit(cache=True)
def _forward(x, y, theta, gx, gy, gtheta, radius) -> float:
    """The Dubins length [m] from pose (x, y, θ) to the goal."""
    d, a, b = dubins._normalised(x, y, theta, gx, gy, gtheta, radius)
    return dubins.length(d, a, b) * radius  # solve's t + p + q bit for bit, 0.8x its time


@njit(cache=True, inline="always")
def _above(forward, radius) -> float:
    """``forward`` (a Dubins length [m]) raised by the gate's margin: no less than the
    Reeds–Shepp length as computed, whose closed forms round differently."""
    return forward * (1.0 + GATE_MARGIN) + GATE_MARGIN * radius


@njit(cache=True)
def _below_reeds_shepp(x, y, theta, gx, gy, gtheta, radius) -> float:
    """A lower bound [m] on the Reeds–Shepp length from pose (x, y, θ) to the goal: no shorter than the
    straight line, and only arcs turn the heading, by at most 1/r per metre, so no shorter than
    r·|Δθ| (Δθ wrapped to [−π, π]). Lowered by the gate's margin, so it stays below the closed
    forms' rounding."""
    turn = abs(reeds_shepp._mod_pi(gtheta - theta))
    bound = max(math.hypot(gx - x, gy - y), radius * turn)
    return bound * (1.0 - GATE_MARGIN) - GATE_MARGIN * radius


@njit(cache=True)
def _same_side_settles(x, y, theta, gx, gy, gtheta, radius, field, room) -> bool:
    """Whether an upper bound on the Reeds–Shepp length [m] from pose (x, y, θ) to the goal is no more than
    ``field`` or less than ``room`` (:func:`~navlab.sampling.reeds_shepp_length.same_side_above`, lifted by
    the gate's margin): then ``max(field, length)`` is ``field``, or less than ``room``, unsolved."""
    bound = _above(reeds_shepp_length.same_side_above(*_local(x, y, theta, gx, gy, gtheta, radius), True) * radius,
                   radius)
    return bound <= field or bound < room


@njit(cache=True)
def _heuristic_from(field, forward, x, y, theta, gx, gy, gtheta, radius, reverse, table, index) -> float:
    """:func:`_heuristic` given the Dubins length ``forward`` [m] already solved, the Reeds–Shepp length
    read from or kept in ``table[index]`` (:func:`~navlab.grid.hybrid_table.reeds_shepp_memo`; ``index``
    −1: solved)."""
    if not reverse:
        return max(field, forward)
    if _above(forward, radius) <= field:
        return field
    # the Dubins length bounds the shortest word from above: words that cannot beat it are dropped sooner
    return max(field, reeds_shepp_memo(table, index, x, y, theta, gx, gy, gtheta, radius,
                                       _above(forward, radius) / radius))


@njit(cache=True)
def _heuristic(field, x, y, theta, gx, gy, gtheta, radius, reverse) -> float:
    """The larger of ``field`` (the holonomic distance at the node's cell) and the
    exact obstacle-free Dubins / Reeds–Shepp distance from pose (x, y, θ) to the goal.

    A Reeds–Shepp solve (44 closed forms) costs about ten Dubins solves, and
    far from the goal the field is usually the larger. Every Dubins path is a
    Reeds–Shepp path, so the Dubins length bounds the Reeds–Shepp length from
    above: when it is no more than the field, the maximum is the field and the
    Reeds–Shepp solve is skipped. The value is the same as always solving; the
    relative margin keeps rounding in the two closed forms from deciding. (The
    search reads the pose rounded to the robot's distance table instead, where
    it has one: :mod:`~navlab.grid.hybrid_table`.)
    """
    forward = _forward(x, y, theta, gx, gy, gtheta, radius)
    return _heuristic_from(field, forward, x, y, theta, gx, gy, gtheta, radius, reverse, np.zeros(1), -1)


# ---------------------------------------------------------------------------
# the priority queue: a binary heap of (key, node, entry) ordered by (key, node)
# ---------------------------------------------------------------------------
_ONE = np.uint64(1)


@njit(cache=True, inline="always")
def _U(i):
    """``i`` (>= 0) as an index numba does not wrap around the array's length (it does a signed one:
    a few instructions an access, and registers for the lengths)."""
    return np.uint64(i)


@njit(cache=True)
def _push(hkey, hnode, hentry, size, key, node, entry) -> None:
    """Add (key, node, entry) to the heap of ``size`` entries held in the three arrays.

    Indexed through ``np.uint64`` (as the grid kernels): numba wraps a signed index around the array's
    length first, which costs each access a few instructions and the loop registers for the lengths."""
    i = np.uint64(size)
    while i != 0:
        up = (i - _ONE) >> _ONE
        if hkey[up] < key or (hkey[up] == key and hnode[up] <= node):
            break
        hkey[i], hnode[i], hentry[i] = hkey[up], hnode[up], hentry[up]
        i = up
    hkey[i], hnode[i], hentry[i] = key, node, entry


@njit(cache=True)
def _pop(hkey, hnode, hentry, size):
    """Remove the first (smallest key, then smallest node) of ``size`` (> 0) entries: (key, node, entry),
    the order of heapq's (key, node) tuples.

    Bottom-up, as heapq's ``_siftup``: the hole at the root goes down to a leaf along the lesser children,
    one comparison a level, and the last entry goes in it and up past the entries no less than it. The
    path is ordered, so that puts every entry where the usual sift-down (two comparisons a level) does.
    Indexed through ``np.uint64``, as :func:`_push`."""
    key, node, entry = hkey[0], hnode[0], hentry[0]
    last = np.uint64(size - 1)
    lk, ln, le = hkey[last], hnode[last], hentry[last]
    i = np.uint64(0)
    child = _ONE
    while child < last:
        right = child + _ONE
        if right < last:
            kr, kc = hkey[right], hkey[child]
            if kr < kc or (kr == kc and hnode[right] < hnode[child]):
                child = right
        hkey[i], hnode[i], hentry[i] = hkey[child], hnode[child], hentry[child]
        i = child
        child = i + i + _ONE
    while i != 0:
        up = (i - _ONE) >> _ONE
        if hkey[up] < lk or (hkey[up] == lk and hnode[up] < ln):
            break
        hkey[i], hnode[i], hentry[i] = hkey[up], hnode[up], hentry[up]
        i = up
    hkey[i], hnode[i], hentry[i] = lk, ln, le
    return key, node, entry


@njit(cache=True, inline="always")
def _open(hkey, hnode, hentry, size, eg, ex, ey, elazy, entry, node, g, x, y, theta, field, reverse, gx, gy, gtheta,
          radius) -> None:
    """Queue ``node`` (pose x, y, θ; ``g`` its cost's share of the key, the cost over the heuristic's weight;
    ``field`` the holonomic heuristic at its cell) as ``entry``: keyed on the field alone when Reeds–Shepp (the
    distance is found when it comes up), on the larger of it and the Dubins distance otherwise (a Dubins solve
    costs little more than the queue's bookkeeping for putting it off; where an upper bound on it is no more
    than the field, that is the field)."""
    eg[entry], ex[entry], ey[entry], elazy[entry] = g, x, y, reverse
    if reverse or _forward_within(x, y, theta, gx, gy, gtheta, radius, field):
        key = g + field
    else:
        key = g + max(field, _forward(x, y, theta, gx, gy, gtheta, radius))
    _push(hkey, hnode, hentry, size, key, node, entry)


#: [turning radii] the Dubins gate's absolute margin: within a thousandth of a radius of the goal the
#: Dubins closed forms lose digits (up to 3e-5 radii above the forward same-side words' length)
DUBINS_MARGIN = 1e-4


@njit(cache=True)
def _forward_within(x, y, theta, gx, gy, gtheta, radius, field) -> bool:
    """Whether the Dubins length [m] from pose (x, y, θ) to the goal is surely no more than ``field``: the
    forward same-side words' length (:func:`~navlab.sampling.reeds_shepp_length.same_side_above`), an upper
    bound on it at a tenth of a solve's cost, lifted by :data:`DUBINS_MARGIN` radii, is."""
    bound = reeds_shepp_length.same_side_above(*_local(x, y, theta, gx, gy, gtheta, radius), False)
    return (bound * (1.0 + GATE_MARGIN) + DUBINS_MARGIN) * radius <= field


@njit(cache=True)
def _entries_grown(eg, ex, ey, elazy, hkey, hnode, hentry, cap):
    """The queue's entry arrays (what each key was computed from, and the heap) with room for ``cap``."""
    return (_grow(eg, cap), _grow(ex, cap), _grow(ey, cap), _grow(elazy, cap), _grow(hkey, cap), _grow(hnode, cap),
            _grow(hentry, cap))


@njit(cache=True, inline="always")
def _field_index(x, y, res, stride):
    """The holonomic field's index of the cell holding (x, y) [m] (the field has a one-cell border)."""
    return (int(floor_div(y, res)) + 1) * stride + int(floor_div(x, res)) + 1


@njit(cache=True)
def _grow(a, cap):
    out = np.empty((cap,) + a.shape[1:], dtype=a.dtype)
    out[:a.shape[0]] = a
    return out


@njit(cache=True)
def _swept_free(blocked, near2, cx, cy, offsets, lo, hi) -> bool:
    """Whether none of the cells ``offsets[lo:hi]`` from cell (cx, cy) is blocked or off the map:
    :func:`~navlab.sampling.footprint_lattice.free_cells`' answer, reading fewer cells.

    ``near2`` is the squared distance [cells²] from each cell to the nearest blocked or off-map
    cell (centre to centre), and the offsets come outermost first: from the first offset nearer
    than that, every remaining one is nearer too, so none of them can be blocked
    (:func:`~navlab.sampling.footprint_lattice.free_cells_near`)."""
    return free_cells_near(blocked, cx, cy, offsets, lo, hi, near2[cy, cx])


@njit(cache=True)
def _analytic(blocked, res, x, y, theta, gx, gy, gtheta, radius, reverse, ds, theta0, step, bins, pose_cells,
              pose_start, clear, clear_disc, vertices, disc, exact_grow, seg, best_kinds, best_lens, akinds,
              alens) -> bool:
    """The exact obstacle-free path from (x, y, θ) to the goal into ``akinds``/``alens`` [m]; whether it is free
    (:func:`~navlab.sampling.footprint_lattice.curve_free` with the clearance map ``clear`` and the lattice's
    ``clear_disc``: poses far from every blocked cell pass unread, the same answer; poses its cell lists
    reject are checked exactly, the outline ``vertices`` or ``disc`` against squares grown by ``exact_grow``)."""
    for i in range(MAX_SEGMENTS):
        akinds[i] = NOP
        alens[i] = 0.0
    if reverse:
        # the full solver's word, bit for bit, by branch and bound: a third of its cost
        reeds_shepp_length.word(*_local(x, y, theta, gx, gy, gtheta, radius), math.inf, seg, best_kinds, best_lens)
        for i in range(MAX_SEGMENTS):
            akinds[i] = best_kinds[i]
            alens[i] = best_lens[i] * radius
    else:
        d, a, bb = dubins._normalised(x, y, theta, gx, gy, gtheta, radius)
        word, t, p, q = dubins.solve(d, a, bb)
        for i in range(3):
            akinds[i] = dubins.WORDS[word, i]
        alens[0], alens[1], alens[2] = t * radius, p * radius, q * radius
    return curve_free(blocked, res, x, y, theta, akinds, alens, radius, ds, theta0, step, bins, pose_cells,
                      pose_start, clear, clear_disc, vertices, disc, exact_grow)


def new_scratch(bins: int):
    """Empty scratch arrays for :func:`search`: nodes (x, y, bin, g, parent, primitive, closed, rejected),
    the state index (cell -> block, blocks of node numbers, each block's cell) and the queue's entries
    (g, x, y, lazy) and heap (key, node, entry); the state index is sized for the map, and the blocks' width
    set to the headings the search reaches, at the first search."""
    cap = 1024
    return (np.empty(cap), np.empty(cap), np.empty(cap, dtype=np.int64), np.empty(cap),
            np.empty(cap, dtype=np.int64), np.empty(cap, dtype=np.int64), np.zeros(cap, dtype=np.bool_),
            np.zeros(cap, dtype=np.bool_), np.full(0, -1, dtype=np.int32), np.full((64, bins), -1, dtype=np.int32),
            np.empty(64, dtype=np.int64), np.empty(cap), np.empty(cap), np.empty(cap), np.zeros(cap, dtype=np.bool_),
            np.empty(cap), np.empty(cap, dtype=np.int64), np.empty(cap, dtype=np.int64))


class Scratch(threading.local):
    """One thread's :func:`search` scratch arrays, kept between its queries.

    Each thread has its own, so searches on several threads never share them; a search takes
    them (:meth:`take`) and hands back what it returned (:meth:`keep`), so an error in between
    leaves none to reuse (the next search starts from :func:`new_scratch`). Arrays of more than
    ``keep_bytes`` in all are not kept: one huge query does not hold its memory for the thread's life.
    """

    def __init__(self, keep_bytes: int = 64 << 20) -> None:
        self.keep_bytes = keep_bytes
        self.arrays = None

    def take(self, bins: int):
        """The kept arrays (none kept any more), or new ones."""
        arrays, self.arrays = self.arrays, None
        return arrays if arrays is not None else new_scratch(bins)

    def keep(self, arrays) -> None:
        """Keep ``arrays`` (a search's last result) for this thread's next search, if small enough."""
        if sum(a.nbytes for a in arrays) <= self.keep_bytes:
            self.arrays = arrays


# what the expansion loop (:func:`_expand`) hands back to :func:`search`
_EXHAUSTED, _FOUND, _GROW, _SWEPT, _FIELD = 0, 1, 2, 3, 4
#: ``penalties[_KEY_SCALE]``: 1 / the heuristic's weight (after the four travel-cost penalties)
_KEY_SCALE = 4
# the loop's counters, kept in one int64 array between its calls
(_COUNT, _NBLOCKS, _NENTRIES, _HSIZE, _EXPANSIONS, _SOLVED, _COUNTDOWN, _PENDING, _PENDING_CHILD,
 _GOAL_NODE, _EXACT, _COUNTERS) = range(12)


@njit(cache=True)
def search(blocked, res, sx, sy, sbin, sg, gx, gy, gtheta, theta0, step, bins, radius, reverse,
           prim_kind, prim_len, pdx, pdy, pdbin, swept, swept_used, swept_lo, swept_hi, vertices, disc, reach,
           swept_margin, near2, clear, clear_disc, pose_cells, pose_start, ds, exact_grow, exact_retry, fstate,
           fdist, fcells, fsize, fcursor, penalties, analytic_max, max_expansions, use_analytic, analytic_ratio,
           table, spacing, half, scratch):
    """The Hybrid A* loop. Returns (found, node x, y, bin, penalised cost g, parent, primitive, goal node,
    analytic word (kinds, lengths [m]), expansions, heuristics solved, swept cells, rows used).

    ``analytic_ratio`` > 0 tries the analytic expansion on Nav2 Smac's schedule (its
    ``analytic_expansion_ratio``): every max(⌊h / ratio⌋, ⌈ratio⌉)-th expansion, h the least heuristic
    seen so far [cells]; 0 tries it at every expansion within ``analytic_max`` of the goal.

    ``sx``, ``sy``, ``sbin``, ``sg`` are the start nodes (poses on the lattice, their heading bins and
    costs [m], in distinct states; :func:`navlab.grid.hybrid_astar._start_nodes`): nodes 0, 1, ...

    The primitives' swept cells (``swept``, ``swept_used``, ``swept_lo``, ``swept_hi``: the lattice's
    table, :func:`~navlab.sampling.footprint_lattice.swept_group`) are built the first time a child
    needs them, from the outline (``vertices``, ``disc``, ``reach``) and ``swept_margin``. ``clear`` [m] is
    ``sqrt(near2)·res`` (:func:`~navlab.sampling.footprint_lattice.clearance_map`'s values) for the analytic
    expansion's curve checks, with the lattice's ``clear_disc``. ``fstate`` ... ``fcursor`` are the lazy
    holonomic field (:func:`~navlab.grid.hybrid_field.field_start`), settled as far as the lookups need.

    A curve (analytic expansion) pose the cell lists reject is checked again exactly: the outline at the
    pose against the blocked squares grown by ``exact_grow`` [m] (negative: never). A primitive is
    checked that way only once the search has exhausted its space on the swept cells, and only with
    ``exact_retry``: then the nodes that had a primitive rejected are opened again, and the search goes
    on (the same queue, field and budget) checking every rejected primitive exactly. Returns, last,
    whether it did.

    The loop itself is :func:`_expand`, which never replaces an array: numba counts the references of
    an array variable that a loop may reassign on every pass, with atomic instructions (12 % of the
    PythonRobotics demo query's time, ``perf``). When the node arrays, a primitive's swept cells or the
    field's buckets need to grow, it returns; they grow here and it resumes where it stopped.

    ``scratch`` is the node, state-index and queue arrays (:func:`new_scratch`, or what the last
    search returned, last, grown as it needed): a query reusing them writes memory already mapped
    (fresh arrays cost the PythonRobotics demo query about 10 % of its time in page faults). Every
    value is written before it is read, but for the state index, which is all −1 between queries
    (this function sets it back). The node arrays returned are views into the scratch arrays.
    """
    h, w = blocked.shape
    nx, ny, nb, ng, nparent, nprim_of, closed, rejected, block_of, blocks, block_cell, eg, ex, ey, elazy, hkey, \
        hnode, hentry = scratch
    cap, ecap = nx.shape[0], eg.shape[0]
    # discrete state -> node: a block of node numbers per cell reached (all -1 between queries)
    if block_of.shape[0] < h * w:
        block_of = np.full(h * w, -1, dtype=np.int32)  # int32: half what the field takes a cell
    nprim = prim_kind.shape[0]
    child_bin = np.empty((bins, nprim), dtype=np.int64)  # a child's heading bin [parent's bin, primitive]:
    for bb in range(bins):  # no division in the loop
        for j in range(nprim):
            child_bin[bb, j] = (bb + pdbin[j]) % bins
    # the heading bins the search can reach: the start nodes' and those the primitives turn them to, again
    # and again (an arc turns k bins: at 72 bins and k = 4, a quarter of them). A cell's block has a slot
    # for each of these alone, in the order of the bins: a quarter of the memory, so more of it is cached
    slot_of = np.full(bins, -1, dtype=np.int64)
    todo = np.empty(bins, dtype=np.int64)
    top = 0
    for i in range(sbin.shape[0]):
        if slot_of[sbin[i]] < 0:
            slot_of[sbin[i]] = 0
            todo[top] = sbin[i]
            top += 1
    while top > 0:
        top -= 1
        b = todo[top]
        for j in range(nprim):
            b2 = child_bin[b, j]
            if slot_of[b2] < 0:
                slot_of[b2] = 0
                todo[top] = b2
                top += 1
    width = 0
    for b in range(bins):
        if slot_of[b] == 0:
            slot_of[b] = width
            width += 1
    child_slot = np.empty((bins, nprim), dtype=np.int64)  # and its slot in a block
    for bb in range(bins):
        for j in range(nprim):
            child_slot[bb, j] = slot_of[child_bin[bb, j]]
    if blocks.shape[1] != width:
        blocks = np.full((64, width), -1, dtype=np.int32)
        block_cell = np.empty(64, dtype=np.int64)
    akinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    alens = np.zeros(MAX_SEGMENTS)
    counters = np.zeros(_COUNTERS, dtype=np.int64)
    closest = np.full(1, math.inf)  # the schedule's least heuristic so far [cells]
    one_kind = np.empty(1, dtype=np.int64)  # one primitive as a word, for its exact check
    one_len = np.empty(1)

    # the start nodes (in distinct states), queued under their cost alone: the order among themselves is all
    # it decides, and a single start's key is 0, as the analytic expansion's schedule expects
    count = nblocks = 0
    for i in range(sx.shape[0]):
        cell = int(floor_div(sy[i], res)) * w + int(floor_div(sx[i], res))
        if block_of[cell] < 0:
            block_of[cell] = nblocks
            block_cell[nblocks] = cell
            nblocks += 1
        blocks[block_of[cell], slot_of[sbin[i]]] = count
        nx[count], ny[count], nb[count], ng[count], nparent[count], nprim_of[count] = sx[i], sy[i], sbin[i], sg[i], \
            -1, -1
        closed[count] = rejected[count] = False  # (scratch arrays hold the last query's values)
        elazy[count] = False
        _push(hkey, hnode, hentry, count, sg[i] * penalties[_KEY_SCALE], count, count)
        count += 1
    counters[_COUNT] = counters[_NENTRIES] = counters[_HSIZE] = count
    counters[_NBLOCKS] = nblocks
    counters[_PENDING] = counters[_GOAL_NODE] = -1
    while True:
        event = _expand(blocked, res, gx, gy, gtheta, theta0, step, bins, radius, reverse, prim_kind, prim_len,
                        pdx, pdy, pdbin, swept, swept_lo, swept_hi, near2, clear, clear_disc, pose_cells,
                        pose_start, ds, vertices, disc, exact_grow, fstate, fdist, fcells, fsize, fcursor,
                        penalties, analytic_max, max_expansions, use_analytic, analytic_ratio, table, spacing, half,
                        nx, ny, nb, ng, nparent, nprim_of, closed, rejected, block_of, blocks, block_cell, child_bin,
                        child_slot, eg, ex, ey, elazy, hkey, hnode, hentry, akinds, alens, one_kind, one_len, counters,
                        closest)
        if event == _GROW:  # room for every child of the pending node
            count, nentries = counters[_COUNT], counters[_NENTRIES]
            if count + nprim > cap:
                cap = max(2 * cap, count + nprim)
                nx, ny, nb, ng = _grow(nx, cap), _grow(ny, cap), _grow(nb, cap), _grow(ng, cap)
                nparent, nprim_of, closed = _grow(nparent, cap), _grow(nprim_of, cap), _grow(closed, cap)
                rejected = _grow(rejected, cap)
            if counters[_NBLOCKS] + nprim > blocks.shape[0]:
                blocks = _grow(blocks, 2 * blocks.shape[0])
                blocks[counters[_NBLOCKS]:] = -1
                block_cell = _grow(block_cell, blocks.shape[0])
            if nentries + nprim > ecap:
                ecap = max(2 * ecap, nentries + nprim)
                eg, ex, ey, elazy, hkey, hnode, hentry = _entries_grown(eg, ex, ey, elazy, hkey, hnode, hentry, ecap)
        elif event == _SWEPT:  # the pending child's primitive, from the pending node's bin
            swept, swept_used = swept_group(swept, swept_used, swept_lo, swept_hi, nb[counters[_PENDING]],
                                            counters[_PENDING_CHILD], vertices, disc, reach, theta0, step, bins,
                                            prim_kind, prim_len, radius, ds, swept_margin, res)
        elif event == _FIELD:  # the wave paused for room
            fcells = field_cells_grown(fcells)
        elif event == _EXHAUSTED and exact_retry and counters[_EXACT] == 0 and \
                counters[_EXPANSIONS] < max_expansions and rejected[:counters[_COUNT]].any():
            # the space is exhausted on the swept cells, which can wall off a gap the robot fits through:
            # open again the nodes that had a primitive rejected, and go on checking those exactly
            count, nentries = counters[_COUNT], counters[_NENTRIES]
            again = np.nonzero(rejected[:count])[0]
            if nentries + again.shape[0] > ecap:
                ecap = max(2 * ecap, nentries + again.shape[0])
                eg, ex, ey, elazy, hkey, hnode, hentry = _entries_grown(eg, ex, ey, elazy, hkey, hnode, hentry, ecap)
            for u in again:
                closed[u] = False
                field = fdist[_field_index(nx[u], ny[u], res, w + 2)]  # settled when the node was pushed
                _open(hkey, hnode, hentry, counters[_HSIZE], eg, ex, ey, elazy, counters[_NENTRIES], u,
                      ng[u] * penalties[_KEY_SCALE],
                      nx[u], ny[u], theta0 + nb[u] * step, field, reverse, gx, gy, gtheta, radius)
                counters[_HSIZE] += 1
                counters[_NENTRIES] += 1
            counters[_EXACT] = 1
        else:
            count = counters[_COUNT]
            for i in range(counters[_NBLOCKS]):  # the state index back to all -1, for the next query
                block_of[block_cell[i]] = -1
                blocks[i, :] = -1
            return event == _FOUND, nx[:count], ny[:count], nb[:count], ng[:count], nparent[:count], \
                nprim_of[:count], counters[_GOAL_NODE], akinds, alens, counters[_EXPANSIONS], counters[_SOLVED], \
                swept, swept_used, counters[_EXACT] == 1, (nx, ny, nb, ng, nparent, nprim_of, closed, rejected,
                                                          block_of, blocks, block_cell, eg, ex, ey, elazy, hkey,
                                                          hnode, hentry)


@njit(cache=True)
def _expand(blocked, res, gx, gy, gtheta, theta0, step, bins, radius, reverse, prim_kind, prim_len, pdx, pdy,
            pdbin, swept, swept_lo, swept_hi, near2, clear, clear_disc, pose_cells, pose_start, ds, vertices, disc,
            exact_grow, fstate, fdist, fcells, fsize, fcursor, penalties, analytic_max, max_expansions, use_analytic,
            analytic_ratio, table, spacing, half, nx, ny, nb, ng, nparent, nprim_of, closed, rejected, block_of,
            blocks, block_cell, child_bin, child_slot, eg, ex, ey, elazy, hkey, hnode, hentry, akinds, alens, one_kind,
            one_len, counters, closest) -> int:
    """:func:`search`'s loop over its arrays, which it fills but never replaces: pop, expand, push, until
    the goal is reached (``_FOUND``, the node in ``counters[_GOAL_NODE]``) or nothing is left to expand
    (``_EXHAUSTED``), or an array must grow first: ``_GROW`` (room for a node's children), ``_SWEPT`` (a
    primitive's swept cells are not listed yet), ``_FIELD`` (the field's buckets are full). Then
    ``counters[_PENDING]`` is the node being expanded and ``counters[_PENDING_CHILD]`` the child to
    resume at: the children before it are done, and nothing of that child was written yet. A state's node
    is ``blocks[block_of[cell], slot]``, a child's bin and slot ``child_bin`` and ``child_slot`` [parent's
    bin, primitive] (:func:`search`)."""
    h, w = blocked.shape
    fstride = w + 2
    nprim = prim_kind.shape[0]
    seg = np.zeros(MAX_SEGMENTS)
    best_kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    best_lens = np.zeros(MAX_SEGMENTS)
    straight_pen, turn_pen, reverse_pen, change_pen = penalties[0], penalties[1], penalties[2], penalties[3]
    key_scale = penalties[_KEY_SCALE]  # 1 / the heuristic's weight: keys are g / weight + h
    gcos, gsin = math.cos(gtheta), math.sin(gtheta)  # the goal's frame, for the distance table
    count, nblocks, nentries, hsize = counters[_COUNT], counters[_NBLOCKS], counters[_NENTRIES], counters[_HSIZE]
    expansions, solved, countdown = counters[_EXPANSIONS], counters[_SOLVED], counters[_COUNTDOWN]
    v, first = counters[_PENDING], counters[_PENDING_CHILD]
    exact = counters[_EXACT] == 1  # primitives the swept cells reject are checked exactly
    goal_cx, goal_cy, goal_bin = floor_div(gx, res), floor_div(gy, res), int(round((gtheta - theta0) / step))
    # An arc turns k bins (footprint_lattice.Lattice), so the headings a search reaches are those of its
    # start nodes plus multiples of k: the goal's state is its cell with a heading less than one arc's turn
    # from the goal's, within k - 1 bins (the goal's bin alone left 3 in 4 goal headings unreachable without
    # the analytic expansion at 72 bins and k = 4; within k // 2, the nearest, a Dubins car still missed 2
    # of 72 on an empty map: the state it needed was taken by a cheaper arrival at another heading)
    slack = 0
    for j in range(nprim):
        slack = max(slack, abs(pdbin[j]))
    slack -= 1
    event = _EXHAUSTED
    while v >= 0 or hsize > 0:
        if v < 0:
            key, v, e = _pop(hkey, hnode, hentry, hsize)
            hsize -= 1
            if closed[_U(v)]:
                v = -1
                continue
            e = _U(e)
            if elazy[e]:
                elazy[e] = False
                theta = theta0 + nb[_U(v)] * step
                # settled at the push
                field = fdist[_U(_field_index(ex[e], ey[e], res, fstride))]
                # the distance is the table's at the pose rounded to its lattice (hybrid_table), within its reach
                index, px, py, pth, qx, qy, qth = table_pose(ex[e], ey[e], theta, gx, gy, gtheta, gcos, gsin,
                                                             spacing, step, bins, half)
                if index >= 0 and table[index] > 0.0 and analytic_ratio == 0.0:
                    # read, not solved: the true key at once (the order is the same as settling it below; Smac's
                    # schedule reads the key an entry is expanded under, so it takes the path below alone)
                    f = eg[e] + max(field, table[index])
                    if f != key:
                        _push(hkey, hnode, hentry, hsize, f, v, e)
                        hsize += 1
                        v = -1
                        continue
                # the order needs the key only against the next entry's. An upper bound on the Reeds–Shepp
                # length no more than the field, or below the next key less g, settles that this entry is
                # first: its true key is its key, or below the next one. The same-side words bound it at a
                # tenth of a Dubins solve's cost, and settle most entries; the Dubins length, a tighter
                # bound, settles more of the rest
                elif hsize > 0 and not _same_side_settles(px, py, pth, qx, qy, qth, radius, field, hkey[0] - eg[e]):
                    forward = _forward(px, py, pth, qx, qy, qth, radius)
                    if not eg[e] + max(field, _above(forward, radius)) < hkey[0]:
                        below = eg[e] + max(field, _below_reeds_shepp(px, py, pth, qx, qy, qth, radius))
                        if below > hkey[0]:
                            # a better lower bound already puts it after the next entry: back in the queue,
                            # still unsolved (entries that never come back to the top are never solved)
                            elazy[e] = True
                            _push(hkey, hnode, hentry, hsize, below, v, e)
                            hsize += 1
                            v = -1
                            continue
                        if _above(forward, radius) > field and (index < 0 or table[index] == 0.0):
                            solved += 1  # (else the field, or read)
                        f = eg[e] + _heuristic_from(field, forward, px, py, pth, qx, qy, qth, radius, reverse, table,
                                                    index)
                        if f != key:
                            # the true key is larger: back in the queue (ties still go by node)
                            _push(hkey, hnode, hentry, hsize, f, v, e)
                            hsize += 1
                            v = -1
                            continue
            closed[_U(v)] = True
            expansions += 1
            x, y, b = nx[_U(v)], ny[_U(v)], nb[_U(v)]
            theta = theta0 + b * step
            # the goal's state (its cell, a heading within ``slack`` bins): where the search ends without the
            # analytic expansion, and where it always tries one with it (a schedule that seldom comes round, a
            # large analytic_expansion_ratio, or a short analytic_max would otherwise pass the goal by)
            off = (b - goal_bin) % bins
            at_goal = floor_div(x, res) == goal_cx and floor_div(y, res) == goal_cy and min(off, bins - off) <= slack
            # analytic expansion near the goal: the exact obstacle-free path, if it is free
            if use_analytic and (at_goal or math.hypot(gx - x, gy - y) <= analytic_max):
                attempt = True
                if analytic_ratio > 0.0 and not at_goal:  # Smac's AnalyticExpansion::tryAnalyticExpansion
                    closest[0] = min(closest[0], (key - ng[v] * key_scale) / res)
                    # (capped: a ratio of 1e-300 or 1e300 must not overflow the conversion to int64)
                    desired = max(int(min(closest[0] / analytic_ratio, 1e18)),
                                  int(min(math.ceil(analytic_ratio), 1e18)))
                    countdown = min(countdown, desired)
                    attempt = countdown <= 0
                    if attempt:
                        countdown = desired
                    countdown -= 1
                if attempt and _analytic(blocked, res, x, y, theta, gx, gy, gtheta, radius, reverse, ds, theta0,
                                         step, bins, pose_cells, pose_start, clear, clear_disc, vertices, disc,
                                         exact_grow, seg, best_kinds, best_lens, akinds, alens):
                    counters[_GOAL_NODE] = v
                    event = _FOUND
                    break
            elif not use_analytic and at_goal:
                counters[_GOAL_NODE] = v
                event = _FOUND
                break
            if expansions >= max_expansions:
                break
            first = 0
        uv = _U(v)
        x, y, b = nx[uv], ny[uv], nb[uv]
        ub = _U(b)
        theta = theta0 + b * step
        g = ng[uv]
        # the primitive the node was reached by drove in reverse (a change of direction costs change_pen)
        was_backwards = nprim_of[uv] >= 0 and prim_len[_U(nprim_of[uv])] < 0
        children = nprim - first  # room for each child still to come, first
        if count + children > nx.shape[0] or nblocks + children > blocks.shape[0] or \
                nentries + children > eg.shape[0]:
            event = _GROW
            break
        cx, cy = int(floor_div(x, res)), int(floor_div(y, res))
        for j in range(first, nprim):
            uj = _U(j)
            x2, y2 = x + pdx[ub, uj], y + pdy[ub, uj]
            b2 = child_bin[ub, uj]
            cx2, cy2 = int(floor_div(x2, res)), int(floor_div(y2, res))
            if cx2 < 0 or cy2 < 0 or cx2 >= w or cy2 >= h:
                continue
            plen = prim_len[uj]
            length = abs(plen)
            cost = length * (straight_pen if prim_kind[uj] == 2 else turn_pen)
            backwards = plen < 0
            if backwards:
                cost *= reverse_pen
            if was_backwards != backwards and nprim_of[uv] >= 0:
                cost += change_pen
            g2 = g + cost
            cell = cy2 * w + cx2
            blk = block_of[_U(cell)]
            slot = child_slot[ub, uj]  # (>= 0: a child's bin is in the reachable set, by construction)
            u = blocks[_U(blk), _U(slot)] if blk >= 0 else -1
            if u >= 0 and (closed[_U(u)] or ng[_U(u)] <= g2):
                continue
            # the collision check last: it is the dearest test, and it decides nothing a cheaper one rejected
            k = _U(b * nprim + j)
            if swept_lo[k] < 0:
                first = j
                event = _SWEPT
                break
            if not _swept_free(blocked, near2, cx, cy, swept, swept_lo[k], swept_hi[k]):
                # the swept cells hold every cell near the primitive from anywhere in the node's cell, so
                # they reject primitives well clear of a wall; checking the poses they reject exactly costs
                # several times an expansion near walls, so that waits for an exhausted search (search)
                if not exact:
                    rejected[v] = True
                    continue
                one_kind[0], one_len[0] = prim_kind[j], prim_len[j]
                if not curve_free(blocked, res, x, y, theta, one_kind, one_len, radius, ds, theta0, step, bins,
                                  pose_cells, pose_start, clear, clear_disc, vertices, disc, exact_grow):
                    continue
            fv = (cy2 + 1) * fstride + cx2 + 1
            if fstate[_U(fv)] & (PASSABLE | SETTLED) == PASSABLE and fsize[0] + fsize[1] + fsize[2] > fcursor[1] and \
                    not field_settle_within(fstate, fdist, fcells, fsize, fcursor, fstride, res, fv):
                first = j  # the wave goes on (seldom once past the start), once its buckets have room
                event = _FIELD
                break
            field = fdist[_U(fv)]
            if u < 0:
                if blk < 0:
                    blk = nblocks
                    nblocks += 1
                    block_of[cell] = blk
                    block_cell[blk] = cell
                u = count
                count += 1
                blocks[_U(blk), _U(slot)] = u
                closed[_U(u)] = False
                rejected[_U(u)] = False  # (the node arrays grow uninitialised)
            uu = _U(u)
            nx[uu], ny[uu], nb[uu], ng[uu], nparent[uu], nprim_of[uu] = x2, y2, b2, g2, v, j
            _open(hkey, hnode, hentry, hsize, eg, ex, ey, elazy, nentries, u, g2 * key_scale, x2, y2,
                  theta0 + b2 * step, field, reverse, gx, gy, gtheta, radius)
            hsize += 1
            nentries += 1
        if event != _EXHAUSTED:
            break
        v = -1
    counters[_COUNT], counters[_NBLOCKS], counters[_NENTRIES], counters[_HSIZE] = count, nblocks, nentries, hsize
    counters[_EXPANSIONS], counters[_SOLVED], counters[_COUNTDOWN] = expansions, solved, countdown
    counters[_PENDING] = v if event == _GROW or event == _SWEPT or event == _FIELD else -1
    counters[_PENDING_CHILD] = first
    return event
