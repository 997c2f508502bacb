"""Compiled grid search: A* (and Dijkstra, weighted A*), JPS and Theta*.

The grid is padded with a blocked border one cell wide, so neighbour lookups
need no bounds checks, and flattened in one of two layouts. JPS, line of sight
and smoothing read it row by row: padded cell (x, y) at ``y * S + x`` with
stride ``S = W + 2``. A*, Dijkstra and Theta* read it in vertical strips
(:func:`strip_index`), where the cells near one another share memory pages.

Per-cell search state is one packed integer per cell for A*, Dijkstra and
JPS (a uint32: :func:`state_layout`), one float64 and a parent index for
Theta*, allocated once per grid; a query clears only what the previous one
wrote (:func:`clear_blocks` in the strip layout, :func:`clear_touched` in
rows). The open list is described below.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

from ..jit import njit

SQRT2 = math.sqrt(2.0)
H_ZERO, H_MANHATTAN, H_EUCLIDEAN, H_CHEBYSHEV, H_OCTILE = 0, 1, 2, 3, 4


@njit(cache=True, inline="always")
def heuristic(code, ax, ay, bx, by):
    dx = abs(ax - bx)
    dy = abs(ay - by)
    if code == H_MANHATTAN:
        return float(dx + dy)
    if code == H_EUCLIDEAN:
        return math.sqrt(dx * dx + dy * dy)
    if code == H_CHEBYSHEV:
        return float(max(dx, dy))
    if code == H_OCTILE:
        return max(dx, dy) + (SQRT2 - 1.0) * min(dx, dy)
    return 0.0


@njit(cache=True, inline="always")
def cell_xy(u, S):
    """(x, y) of the padded flat index ``u`` (never negative) in rows of stride ``S`` (at least 1),
    by one unsigned division (JPS's; the strip layout's kernels use :func:`strip_xy`): numba divides
    signed integers with Python's floor rounding, a sign fix-up after the quotient and the remainder
    that cost A* 3-5 % of its time when it searched padded rows (paired in-process A/B, session 27)."""
    return np.int64(np.uint64(u) % np.uint64(S)), np.int64(np.uint64(u) // np.uint64(S))


# -- the strip layout ------------------------------------------------------------
# A*, Dijkstra and Theta* keep the legal moves and their search state in vertical strips of
# 2**bits padded columns, each strip stored row after row: padded cell (x, y) at
# ``(x >> bits) * SH + y * 2**bits + (x & (2**bits - 1))`` with SH = rows * 2**bits. A row-major
# 4096-wide grid puts each row of uint32 state on four 4 KB pages of its own, so the cells around
# one another lie on three pages and the cells a search front holds on thousands; on this VM the
# address translations of 4 KB pages are what it misses, the guest's huge pages notwithstanding
# (the host apparently maps them in 4 KB pieces: dependent reads of 4096 cache lines took 20 ns
# each spread over 4096 pages of a 16 MB array, 5 ns packed into 64 pages). In strips of 128 columns a 4 KB page of state is 8 rows of one strip: with the written
# blocks marked (:func:`clear_blocks`) and the reciprocal of :func:`divider`, random4096 A* 0.90x
# the time, maze1001 1.00x (the same expansions and state, cell for cell; paired in-process A/B,
# session 28). Only a move east or west across a strip's edge is not a constant offset
# (:func:`strip_sides`).
#: the widest strip (columns): 64 to 256 measured alike on random4096, 16 and 32 slower
STRIP_BITS = 7
#: a block of the strip layout: 2**10 cells (4 KB of uint32 state), the unit a search marks as
#: written (``flags``) and the next query clears (:func:`clear_blocks`)
BLOCK_BITS = 10


def strip_bits(stride: int) -> int:
    """The strip width's bits for padded rows ``stride`` cells long: the widest strip up to
    ``2**STRIP_BITS`` columns that is at most an eighth of the row, so the last strip's unused
    columns add at most an eighth to the arrays (a grid under 14 cells wide is stored a column at
    a time)."""
    bits = 0
    while bits < STRIP_BITS and (2 << bits) <= max(1, stride // 8):
        bits += 1
    return bits


def strip_shape(rows: int, stride: int):
    """The strip layout of ``rows`` padded rows of ``stride`` cells.

    Returns
    -------
    bits : int
        The strip width's bits (:func:`strip_bits`).
    SH : int
        The cells of one strip (``rows << bits``).
    size : int
        The cells of all the strips (a multiple of SH)."""
    bits = strip_bits(stride)
    strips = -(-stride // (1 << bits))
    return bits, rows << bits, strips * (rows << bits)


@njit(cache=True, inline="always")
def strip_index(x, y, SH, bits):
    """The strip-layout index of padded cell (x, y) (see above)."""
    return (x >> bits) * SH + (y << bits) + (x & ((1 << bits) - 1))


@njit(cache=True, inline="always")
def divider(d, n):
    """A multiply and a shift that divide by ``d``: ``(u * magic) >> shift == u // d``.

    The round-up reciprocal, exact because ``magic * d - 2**shift < d <= 2**(shift - N)`` for
    ``u < 2**N``, and ``u * magic < 2**(2N + 1)`` fits in 64 bits. One per expansion instead of a
    division (:func:`strip_xy`; random4096 A* 0.985x the time, in-process A/B).

    Parameters
    ----------
    d, n : int
        The divisor and a bound on the dividends: ``1 <= d <= n <= 2**31``.

    Returns
    -------
    magic, shift : np.uint64

    References
    ----------
    T. Granlund and P. L. Montgomery, "Division by invariant integers using multiplication",
    PLDI 1994.
    """
    N = 1
    while (1 << N) < n:
        N += 1
    L = 0
    while (1 << L) < d:
        L += 1
    return np.uint64(((1 << (N + L)) + d - 1) // d), np.uint64(N + L)


@njit(cache=True, inline="always")
def strip_xy(u, SH, bits, magic, shift):
    """Padded (x, y) of strip-layout index ``u`` (``magic, shift``: :func:`divider` of SH)."""
    s = (np.uint64(u) * magic) >> shift
    r = np.uint64(u) - s * np.uint64(SH)
    b = np.uint64(bits)
    return np.int64((s << b) | (r & ((np.uint64(1) << b) - np.uint64(1)))), np.int64(r >> b)


@njit(cache=True, inline="always")
def strip_sides(u, SH, bits):
    """``(east, west)``: what a move east adds to strip-layout index ``u`` and a move west takes
    away: 1 within a strip, and from a strip's last (first) column to the next (previous) strip's
    first (last) column of the same row, ``SH - width + 1``."""
    width = 1 << bits
    column = u & (width - 1)
    cross = SH - width + 1
    return (cross if column == width - 1 else 1), (cross if column == 0 else 1)


@njit(cache=True, inline="always")
def strip_step(u, k, bits, east, west):
    """The strip-layout index of the cell move k (:data:`MOVES_X`) leads to from ``u``
    (``east, west``: :func:`strip_sides` of u)."""
    return u + (_DY[np.uint64(k)] << bits) + _EAST[np.uint64(k)] * east - _WEST[np.uint64(k)] * west


@njit(cache=True, inline="always")
def strip_step_back(v, k, bits, east, west):
    """The strip-layout index of the cell move k leads to ``v`` from: :func:`strip_step` undone
    (``east, west``: :func:`strip_sides` of v)."""
    return v - (_DY[np.uint64(k)] << bits) - _EAST[np.uint64(k)] * west + _WEST[np.uint64(k)] * east


def to_rows(flat: np.ndarray, rows: int, stride: int) -> np.ndarray:
    """A strip-layout array (:func:`strip_shape`) as padded rows ``(rows, stride)`` (a copy)."""
    bits, SH, size = strip_shape(rows, stride)
    strips = size // SH
    return flat.reshape(strips, rows, 1 << bits).transpose(1, 0, 2).reshape(rows, strips << bits)[:, :stride].copy()


@njit(cache=True, inline="always")
def block_span(b, size):
    """The indices ``range(first, last)`` of block ``b`` of a strip-layout array of ``size`` cells."""
    return b << BLOCK_BITS, min((b + 1) << BLOCK_BITS, size)


@njit(cache=True, nogil=True)
def clear_blocks(gs, flags):
    """Zero the blocks of ``gs`` (strip layout) a query marked in ``flags``, and the marks."""
    for b in range(flags.shape[0]):
        if flags[b]:
            first, last = block_span(b, gs.shape[0])
            gs[first:last] = 0
            flags[b] = 0


TIE = 1e-9  # f values closer than this are equal (distinct a + b√2 lengths differ by far more)
OVERFLOW = -1
#: an A*, Dijkstra or JPS search whose path outgrew the 32-bit state (:func:`state_layout`): rerun it wide
WIDEN = -2
ALL_BITS = np.uint64(0xFFFFFFFFFFFFFFFF)
# The kernels spell out their open-list pops and pushes inline rather than
# through shared helpers: helpers returning (size, top, ...) tuples made A*
# ~30% slower on maze512, and helpers keeping that state in an array 2x slower
# (measured with benchmarks/bench_grid.py).


@intrinsic
def _prefetch(typingctx, arr, idx):
    """Ask the CPU to start loading ``arr[idx]``'s cache line (LLVM's
    ``llvm.prefetch``: a read, kept in every cache level); no effect on results."""
    sig = types.void(arr, idx)

    def codegen(context, builder, signature, args):
        aryty = signature.args[0]
        ary = context.make_array(aryty)(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, aryty, ary, [args[1]], wraparound=False)
        i8p = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
                                            "llvm.prefetch.p0")
        builder.call(fn, [builder.bitcast(ptr, i8p), i32(0), i32(3), i32(1)])
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _cttz(typingctx, x):
    """The index of the lowest set bit of ``x`` (LLVM's ``llvm.cttz``; x must not be 0)."""
    sig = x(x)

    def codegen(context, builder, signature, args):
        ty = context.get_value_type(signature.args[0])
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ty, [ty, ir.IntType(1)]),
                                            f"llvm.cttz.i{ty.width}")
        return builder.call(fn, [args[0], ir.IntType(1)(1)])

    return sig, codegen


# -- line of sight -------------------------------------------------------------
@njit(cache=True, nogil=True)
def los_supercover(free, S, x0, y0, x1, y1):
    """Whether the segment between cell centres crosses only free cells
    (every cell it touches; through a cell corner both side cells must be free)."""
    dx = x1 - x0
    dy = y1 - y0
    nx = abs(dx)
    ny = abs(dy)
    sx = 1 if dx > 0 else -1
    sy = 1 if dy > 0 else -1
    x = x0
    y = y0
    ix = 0
    iy = 0
    while ix < nx or iy < ny:
        decision = (1 + 2 * ix) * ny - (1 + 2 * iy) * nx
        if decision == 0:
            if free[(y + 1) * S + x + sx + 1] == 0 or free[(y + sy + 1) * S + x + 1] == 0:
                return False
            x += sx
            y += sy
            ix += 1
            iy += 1
        elif decision < 0:
            x += sx
            ix += 1
        else:
            y += sy
            iy += 1
        if free[(y + 1) * S + x + 1] == 0:
            return False
    return True


@njit(cache=True, nogil=True)
def los_bresenham(free, S, x0, y0, x1, y1):
    """Bresenham line of sight: every cell of the Bresenham line is free, and a
    diagonal step never cuts a blocked corner (both orthogonal cells free)."""
    dx = abs(x1 - x0)
    dy = -abs(y1 - y0)
    sx = 1 if x0 < x1 else -1
    sy = 1 if y0 < y1 else -1
    err = dx + dy
    x = x0
    y = y0
    while True:
        if free[(y + 1) * S + x + 1] == 0:
            return False
        if x == x1 and y == y1:
            return True
        e2 = 2 * err
        step_x = e2 >= dy
        step_y = e2 <= dx
        if step_x and step_y:
            if free[(y + 1) * S + x + sx + 1] == 0 or free[(y + sy + 1) * S + x + 1] == 0:
                return False
        if step_x:
            err += dy
            x += sx
        if step_y:
            err += dx
            y += sy


# -- per-cell search state -------------------------------------------------------
# A*, Dijkstra and JPS keep one packed integer per cell (:func:`state_layout`): 0 unseen, else
# the straight moves + 1 and the diagonal moves of the best path found so far, with a closed bit.
# Their g is a + b·√2 for whole a and b, so the pair is exact where a float sum rounds: equal
# lengths are equal bit for bit, and the path is read back by integer equality
# (:func:`trace_back`, :func:`trace_jumps`). In 32 bits that is 4 bytes per cell, with the
# legal-move byte (:func:`legal_moves`) 5; Theta*, whose g is a sum of square roots, keeps one
# float64 (0.0 unseen, g + 1 while open, -(g + 1) once closed; g + 1 > 0 keeps the start's g = 0
# apart from "unseen"). The state starts
# as np.zeros (untouched pages stay unallocated), and a query records what it wrote so that the
# next query can zero just that instead of the whole grid: A*, Dijkstra and Theta* mark the blocks
# of the strip layout they write (:func:`clear_blocks`), JPS the rows and columns it expanded
# (:func:`clear_touched`).


#: the packed state's (shift, a_mask, b_mask, closed) for each width (:func:`state_layout`)
NARROW_LAYOUT = (np.uint32(16), np.uint32(0x7FFF), np.uint32(0xFFFF), np.uint32(1 << 31))
WIDE_LAYOUT = (np.uint64(32), np.uint64(0x7FFFFFFF), np.uint64(0xFFFFFFFF), np.uint64(1 << 63))


def state_layout(wide: bool):
    """How A*, Dijkstra and JPS pack a cell's state: ``(dtype, shift, a_mask, b_mask, closed)``, numpy
    scalars of the state's dtype. A reached cell holds ``(a << shift) | b`` with ``a`` the path's
    straight moves + 1 (so no reached cell is 0) and ``b`` its diagonal moves, its g + 1 being
    ``a + b·√2``, and ``closed`` or-ed in once it is expanded.

    Narrow (uint32: a < 2¹⁵, b < 2¹⁶: up to 32 766 straight and 65 535 diagonal moves) is the
    default: half the bytes of a float64, so a search's state takes half the cache lines and a first
    query maps half the pages (random4096 A* 0.91x the time of the float64 state on a fresh grid,
    0.93x repeated; in-process A/B). A path with more moves than that (a big maze's) stops the search
    (:data:`WIDEN`, :func:`would_carry`) and it runs again wide (uint64: a < 2³¹, b < 2³², more than
    the 10⁸ cells of the largest grid)."""
    return (np.uint64, *WIDE_LAYOUT) if wide else (np.uint32, *NARROW_LAYOUT)


def state_steps(wide: bool) -> np.ndarray:
    """What each of the eight moves (:data:`MOVES_X`, orthogonal first) adds to a packed state:
    one straight move (``1 << shift``) or one diagonal (1)."""
    state_type, shift = state_layout(wide)[:2]
    return np.array([state_type(1) << shift] * 4 + [state_type(1)] * 4, dtype=state_type)


@njit(cache=True, inline="always")
def would_carry(field, moves, mask) -> bool:
    """Whether adding ``moves`` to a packed field now holding ``field`` passes its ``mask`` (would carry
    into the next field: :func:`state_layout`). In uint64 whatever the state's width (numba makes a
    float of a uint64 mixed with an int64)."""
    return np.uint64(field) + np.uint64(moves) > np.uint64(mask)


@njit(cache=True, inline="always")
def state_g(p, shift, a_mask, b_mask):
    """g + 1 of a packed state ``p`` (:func:`state_layout`): ``a + b·√2``, one rounding."""
    return np.float64(np.int64((p >> shift) & a_mask)) + np.float64(np.int64(p & b_mask)) * SQRT2


def state_costs(state: np.ndarray):
    """(closed mask, g [cells]) of every cell of a search's state array, packed (uint32 or uint64,
    :func:`state_layout`) or float64 (Theta*); g is inf where the search never reached."""
    if state.dtype == np.float64:
        return state < 0, np.where(state == 0, np.inf, np.abs(state) - 1.0)
    _, shift, a_mask, b_mask, closed = state_layout(state.dtype == np.uint64)
    a = ((state >> shift) & a_mask).astype(np.float64)
    b = (state & b_mask).astype(np.float64)
    return (state & closed) != 0, np.where(state == 0, np.inf, (a - 1.0) + b * SQRT2)


@njit(cache=True)
def touched_span(r, lo, hi, extent, S):
    """The flat indices ``range(first, last)`` of padded row ``r`` a query may have written: every
    cell within one of a recorded cell (each row's recorded columns in ``lo``/``hi``, its rows in
    ``extent``), which covers everything a search writes (expanded cells and their neighbours; JPS
    records its jump points). Rows ``extent[0] - 1`` to ``extent[1] + 1`` hold them all."""
    a = S
    b = -1
    for q in range(max(r - 1, extent[0]), min(r + 1, extent[1]) + 1):
        a = min(a, lo[q])
        b = max(b, hi[q])
    return r * S + a - 1, r * S + b + 2


@njit(cache=True, nogil=True)
def clear_touched(gs, S, lo, hi, extent):
    """Zero the state a query wrote (:func:`touched_span`). Leaves the records empty."""
    r0 = extent[0]
    r1 = extent[1]
    for r in range(r0 - 1, r1 + 2):
        first, last = touched_span(r, lo, hi, extent, S)
        for v in range(first, last):
            gs[v] = 0
    for q in range(r0, r1 + 1):
        lo[q] = S
        hi[q] = -1
    extent[0] = lo.shape[0]
    extent[1] = -1


@njit(cache=True, nogil=True)
def widen_state(narrow, wide, flags):
    """Move what a query wrote in the narrow packed state into the wide one (:func:`state_layout`;
    strip layout), zeroing the narrow cells: the blocks :func:`clear_blocks` would clear. The marks
    stay: they now describe ``wide``, in which the stopped search can go on (``make_astar``'s
    ``resume``)."""
    shift32, a_mask, b_mask, closed32 = NARROW_LAYOUT
    shift64, closed64 = WIDE_LAYOUT[0], WIDE_LAYOUT[3]
    for b in range(flags.shape[0]):
        if not flags[b]:
            continue
        first, last = block_span(b, narrow.shape[0])
        for v in range(first, last):
            p = narrow[v]
            if p != 0:
                moved = (np.uint64((p >> shift32) & a_mask) << shift64) | np.uint64(p & b_mask)
                wide[v] = moved | closed64 if p & closed32 else moved
                narrow[v] = 0


# -- legal moves ---------------------------------------------------------------
#: the eight moves, orthogonal first (tuples: constants in the compiled code);
#: bit k of a cell's legal-move mask (:func:`legal_moves`) is move k
MOVES_X = (1, -1, 0, 0, 1, -1, 1, -1)
MOVES_Y = (0, 0, 1, -1, 1, 1, -1, -1)
# The same as arrays, for a move index known only at run time (numba freezes
# global arrays into the compiled code as constants).
_DX = np.array(MOVES_X, dtype=np.int64)
_DY = np.array(MOVES_Y, dtype=np.int64)
_STEP = np.array([1.0] * 4 + [SQRT2] * 4)
#: 1 for the moves with an eastward (westward) part: their strip-layout step (:func:`strip_step`)
_EAST = np.array([int(dx > 0) for dx in MOVES_X], dtype=np.int64)
_WEST = np.array([int(dx < 0) for dx in MOVES_X], dtype=np.int64)


def _canonical_table():
    """``CANONICAL[k * 256 + mu]``: the moves a cell entered by move k from a
    cell whose legal-move mask is ``mu`` expands (see :func:`make_astar`).

    After a straight move d, the side move p is needed only when the cell
    beside the previous one (its move p) is blocked: otherwise the diagonal
    d + p from the previous cell reaches the same cell for sqrt(2) < 2, and
    the diagonal d + p from here is as long as that diagonal followed by d.
    After a diagonal, without corner cutting, both cells beside the move are
    free, so every other neighbour is as close through them."""
    out = np.zeros(8 * 256, dtype=np.uint8)
    for k in range(8):
        dx, dy = MOVES_X[k], MOVES_Y[k]
        for mu in range(256):
            if dx and dy:  # a diagonal: itself and its two straight parts, never more without corner cutting
                bits = (1 << k) | (1 << (0 if dx > 0 else 1)) | (1 << (2 if dy > 0 else 3))
            else:
                bits = 1 << k
                for p in ((2, 3) if dx else (0, 1)):  # the two sides
                    if not (mu >> p) & 1:  # blocked beside the cell we came from: forced
                        bits |= (1 << p) | (1 << _diagonal(dx + MOVES_X[p], dy + MOVES_Y[p]))
            out[k * 256 + mu] = bits
    return out


def _diagonal(dx, dy):
    return 4 + (dx < 0) + 2 * (dy < 0)


CANONICAL = _canonical_table()
#: the highest move of each move mask: the move whose line A* prefetches ahead (see make_astar)
LEAD = np.array([max(0, int(b).bit_length() - 1) for b in range(256)], dtype=np.uint8)
#: how many cells ahead it prefetches (3 to 8 within 1% on random4096; 2 no gain)
LOOK = 5


@njit(cache=True, inline="always")
def _move_mask(so, me, no, c):
    """The legal-move mask (see :func:`legal_moves`) of the cell in ring column ``c`` of row ``me``,
    between rows ``so`` (south) and ``no`` (north)."""
    one = np.uint64(1)
    east = np.int32(me[c + one])
    west = np.int32(me[c - one])
    north = np.int32(no[c])
    south = np.int32(so[c])
    m = (east | (west << 1) | (north << 2) | (south << 3)
         | ((east & north & np.int32(no[c + one])) << 4) | ((west & north & np.int32(no[c - one])) << 5)
         | ((east & south & np.int32(so[c + one])) << 6) | ((west & south & np.int32(so[c - one])) << 7))
    return np.uint8(m * np.int32(me[c]))


@njit(cache=True, nogil=True)
def legal_moves(blocked, unknown, out, bits=-1):
    """Each padded cell's legal 8-connected moves as a bit mask (bit k: move
    ``(MOVES_X[k], MOVES_Y[k])`` stays on free cells and, diagonally, cuts no
    blocked corner; 0 for blocked and border cells; the 4-connected moves are
    bits 0-3), from the unpadded ``blocked`` cells (and ``unknown`` ones,
    also closed unless the array has no rows).

    Built once per grid (the grid is immutable; ``planner.PaddedGrid`` keeps
    it), so an expansion reads one byte and visits only its legal moves
    instead of testing up to eight grid bytes with a branch each (the
    branches follow the random map and mispredict): A* and Dijkstra 10-15%
    faster per expansion on random4096 and maze1001 (in-process A/B, CPU
    medians of 5-9 interleaved runs at load 6). Branch-free and indexed
    through ``np.uint64``. It reads three padded rows of free cells kept in
    a ring, not a padded copy of the whole grid: A*, Dijkstra and JPS need
    no such copy (``PaddedGrid.free`` is built for Theta*, smoothing and
    line of sight only), and its 4 KB pages were a first query's to map
    (4100 on 4096 x 4096, at 2-14 us each in this VM): ``PaddedGrid`` on a
    4096 x 4096 grid 18-23 -> 4.5-5.0 ms CPU (medians of 5, three
    interleaved pairs of processes, load 14).

    Written into ``out`` in padded rows (``(h + 2) * (w + 2)`` bytes), or
    with ``bits`` >= 0 in the strip layout of that width (:func:`strip_shape`'s
    size; the columns past the padded grid 0), which the caller allocates with
    numpy: numpy asks for transparent huge pages on arrays
    of 4 MB or more (``madvise(MADV_HUGEPAGE)``), numba's allocator does
    not, so a fresh 4096 x 4096 grid maps 7 huge pages (and its unaligned
    ends in small ones: ~520 faults) instead of about 4100 small pages, and
    the searches, which read these bytes all over the grid, miss the TLB
    less: random4096 A* 0.85-0.91x, JPS 0.92-0.98x the time with numba's
    allocation (in-process A/B, CPU medians of 9-11 interleaved runs, load 2-5).
    """
    h, w = blocked.shape
    S = w + 2
    rows = h + 2
    # the row length in ``out``: S, or whole strips
    width = S if bits < 0 else -(-S // (1 << bits)) << bits
    if out.ndim != 1 or out.shape[0] != rows * width:  # the writes below index it unchecked
        raise ValueError("legal_moves: out must be a 1-D array of (h + 2) * (w + 2) bytes (in strips: whole strips)")
    SH = rows << max(bits, 0)
    strips = width >> max(bits, 0)
    if bits < 0:
        out[:S] = 0
        out[(h + 1) * S:] = 0
    else:
        for s in range(strips):  # the first and last padded rows of every strip
            out[s * SH:s * SH + (1 << bits)] = 0
            out[(s + 1) * SH - (1 << bits):(s + 1) * SH] = 0
    # padded row p in slot p % 3, padded column x in ring column x + 1: the columns around the grid stay 0
    ring = np.zeros((3, width + 2), dtype=np.uint8)
    closed_unknown = unknown.shape[0] > 0
    for r in range(0, h + 1):
        nxt = (r + 1) % 3
        if r < h:  # padded row r + 1 is grid row r
            row = ring[nxt]
            if closed_unknown:
                for x in range(w):
                    row[x + 2] = np.uint8(1) ^ (np.uint8(blocked[r, x]) | np.uint8(unknown[r, x]))
            else:
                for x in range(w):
                    row[x + 2] = np.uint8(1) ^ np.uint8(blocked[r, x])
        else:
            ring[nxt, :] = 0
        if r == 0:
            continue
        so = ring[(r - 1) % 3]
        me = ring[r % 3]
        no = ring[nxt]
        one = np.uint64(1)
        if bits < 0:
            base = np.uint64(r * S)
            out[base] = 0
            out[base + np.uint64(w + 1)] = 0
            for x in range(one, np.uint64(w + 1)):
                out[base + x] = _move_mask(so, me, no, x + one)
        else:
            for s in range(strips):
                base = np.uint64(s * SH + (r << bits))
                first = np.uint64(s << bits)
                for j in range(np.uint64(1 << bits)):
                    out[base + j] = _move_mask(so, me, no, first + j + one)
    return out


# -- A* family -----------------------------------------------------------------
# A*'s open list is a circular bucket queue (Dial 1969) whose buckets hold
# keys within one bucket width of each other, with the exact minimum of the
# lowest non-empty bucket kept beside it (``low``, updated by each push: the
# scan for it was a second walk of the bucket's list, 2.4% of A*'s time on
# random4096, paired in-process A/B). It works because the keys in the open
# list always lie in a window just above the current minimum f: a successor's
# f exceeds its parent's by c + weight * (h(v) - h(u)) <= sqrt(2) + 2 weight
# (a step costs at most sqrt(2), and no heuristic here changes by more than 2
# over one step), and successors with f equal to the minimum go on a LIFO
# stack instead (f never decreases with a consistent heuristic; the stack
# also breaks ties toward larger g). So ``N_BUCKETS`` buckets spanning that
# window, reused circularly, keep every key in a bucket of its own band: a
# push is one multiply and a list insert, a pop moves the lowest bucket's
# minimal keys to the stack. On random4096 this halved A*'s time against the
# radix heap (Ahuja et al. 1990) it replaced, whose nodes moved about five
# times each between buckets; 2048 buckets beat 1024 and 4096 on random4096
# and maze1001 (benchmarks/bench_grid.py --large). A better path to an open
# cell just pushes another node; the older one is skipped when popped.
# One bit per bucket (``occupied``, 32 words) marks the non-empty ones, so the
# next is found by a bit scan instead of a walk over empty buckets: on
# maze1001, where few cells share a band of f, the walk passed about 20
# empty buckets per expansion and took 18% of A*'s samples (perf); with the
# bits A* and Dijkstra there take 0.65-0.80x the time, random4096 unchanged
# (same expansions and paths; in-process A/B, CPU medians of 15 runs, 3-5
# interleaved pairs of processes, load 0.7-3).
N_BUCKETS = 2048
#: the span of f JPS's ring covers (a jump may raise f by more: overflow list);
#: not tuned (jumps on random4096 average 2.3 cells, so few keys overflow)
JPS_SPAN = 32.0
#: how many cells ahead JPS prefetches along a jump point's arrival move
JPS_LOOK = 8



def make_astar(conn: int, hcode: int, any_angle: bool, wide: bool = False):
    """A* over the strip layout's indices, compiled for one connectivity, heuristic
    and any-angle setting (Dijkstra with ``hcode`` 0; Theta* with
    ``any_angle``) and state width: as compile-time constants they cost nothing in the inner
    loop (about 8% of A*'s time when they were arguments). Numba caches each
    variant on disk like any other kernel.

    ``gs`` is the packed state of :func:`state_layout` (uint32, or uint64 with
    ``wide``), or for Theta* a float64 per cell (its g is a sum of square roots).
    With ``resume`` (A* and Dijkstra, wide) the kernel goes on with a search the
    narrow state stopped (WIDEN), its state moved into ``gs`` by
    :func:`widen_state`: the marks are kept, and every cell reached and not
    closed is opened again with all its moves; it returns WIDEN when their
    keys do not fit the bucket window (the caller starts over).

    The returned kernel ``astar(free, S, moves, SH, wbits, start, goal, weight, gs, parent, flags,
    key, cell, nxt, head, stack)`` searches the strip layout (:func:`strip_shape`: ``SH`` and
    ``wbits``, its width's bits; ``moves``, the grid's :func:`legal_moves` in it; ``start`` and ``goal`` its
    indices) and keeps all per-cell state in ``gs``, first clearing what the previous query wrote
    (:func:`clear_blocks`; it marks in ``flags`` every block it writes); ``free`` (padded rows of
    stride ``S``) is read and ``parent`` written only with ``any_angle`` (A*'s paths are read back
    from ``gs`` by :func:`trace_back`).
    Every array is indexed through ``np.uint64``: numba wraps a signed index
    that could be negative (a shift, an and and an add per access), which
    an unsigned one cannot be; the indices here never are (13% of A*'s time
    on random4096 and 9% on maze1001, in-process A/B).
    ``key``, ``cell`` and ``nxt`` are the open list's node pool and ``head``
    (``N_BUCKETS`` int32) its buckets; an open entry (in ``cell`` or on
    ``stack``) is ``cell * 256`` plus the moves that cell may expand.
    Returns (status, expanded) with status 1 found, 0 no path, OVERFLOW when
    the pool or the stack ran out of room, WIDEN when a path outgrew the narrow
    state (the caller runs the wide variant).

    8-connected A* and Dijkstra (not Theta*) generate canonical successors
    (Sturtevant & Rabin 2016; the pruning rules of Jump Point Search,
    Harabor & Grastien 2011/2014, one step at a time, without jumping): a
    cell entered diagonally relaxes only that diagonal and its two straight
    parts, one entered straight only the same move, plus, where the cell
    beside the one it came from is blocked, the side move and the diagonal
    ahead on that side (forced neighbours; :data:`CANONICAL`, from the
    arrival move and the previous cell's legal-move mask, carried in the
    open entry: no per-cell byte). Every other neighbour has a path at most
    as short that avoids this cell, so each reachable cell is still closed
    with its exact distance (tests/grid/test_canonical.py checks every cell
    against scipy); the expansions are the same, with 1.37 relaxations each
    instead of 5.26 on random4096 (1.0 instead of 7.3 on maze1001). In-process
    A/B, CPU medians of 7 interleaved runs at load 6.5-10: random4096 0.52-0.57
    -> 0.30-0.36 s (0.58-0.64x), maze1001 60-65 -> 43-45 ms (0.69-0.72x).

    References
    ----------
    N. R. Sturtevant and S. Rabin, "Canonical Orderings on Grids", IJCAI 2016.
    D. Harabor and A. Grastien, "Improving Jump Point Search", ICAPS 2014.
    """
    legal = 255 if conn == 8 else 15  # the mask bits of the allowed moves
    slots = 8 if conn == 8 else 4
    canonical = conn == 8 and not any_angle
    state_type, shift, a_mask, b_mask, closed_bit = state_layout(wide)
    zero = state_type(0)
    a_one = state_type(1) << shift  # the start: no moves yet (a = 0 + 1)
    step_bits = state_steps(wide)
    # Fused multiply-adds for A*'s and Dijkstra's g = a + b·√2, octile h = max + (√2 − 1)·min and
    # f = g + weight·h: one rounding instead of two, and fewer instructions in the relaxation loop
    # (0.975 / 0.959 of the time on random4096 / maze1001, paired in-process A/B of 21 pairs, with the
    # same expansions and the same state bit for bit; JPS measured 1.000 and keeps plain arithmetic).
    # Only "contract": no reassociation, and nothing assumed about NaN or infinity. g is the packed
    # integers (a, b) and the path is traced back from them (trace_back), so costs do not depend on the
    # rounding. What it can change is which keys count as equal (within TIE) when two differ by about
    # TIE: with a weight such as 1 + 1e-9/3, or keys past about 5e6, where one rounding step is TIE's
    # size. Then equally good nodes expand in another order (review, session 31: 1 837 expansions
    # instead of 1 835 on a 160² grid, the same path and cost); A* stays exact at weight 1 and within
    # its weight otherwise, and on a CPU without FMA such near-ties break as they did before.
    # Theta*'s g sums square roots and keeps plain arithmetic.
    contract = False if any_angle else {"contract"}

    @njit(cache=True, nogil=True, fastmath=contract)
    def astar(free, S, moves, SH, wbits, start, goal, weight, gs, parent, flags, key, cell, nxt, head, stack,
              resume=False):
        if not resume:
            clear_blocks(gs, flags)  # what the previous query wrote
        magic, dshift = divider(SH, gs.shape[0])
        gx, gy = strip_xy(goal, SH, wbits, magic, dshift)
        mask = N_BUCKETS - 1
        inv_width = (N_BUCKETS - 3) / (SQRT2 + 2.0 * weight)  # buckets per unit of f: the window fits, with room
        for b in range(N_BUCKETS):
            head[np.uint64(b)] = -1
        occupied = np.zeros(N_BUCKETS // 64, dtype=np.uint64)  # bit b: bucket b holds a node
        low = np.empty(N_BUCKETS)  # a non-empty bucket's smallest key
        word_mask = N_BUCKETS // 64 - 1
        free_node = -1
        bump = 0
        cap_pool = key.shape[0]
        cap_stack = stack.shape[0]
        expanded = 0
        status = 0
        # Each move's step in the strip layout, 8 for a cell inside a strip, 8 on its last column (east crosses
        # to the next strip), 8 on its first (west crosses back) and 8 on both (a strip one column wide): one
        # load per relaxation where strip_sides and strip_step took two compares, three table loads and two
        # multiplies (random4096 A* 0.976 of the time, maze1001 0.959; Dijkstra 0.934 and 0.861; paired
        # in-process A/B, the same expansions and state bit for bit).
        edge = (1 << wbits) - 1
        offsets = np.empty(32, dtype=np.int64)
        for e in range(4):
            for k in range(8):
                offsets[e * 8 + k] = strip_step(0, k, wbits, SH - edge if e & 1 else 1, SH - edge if e & 2 else 1)
        if not any_angle and resume:
            # Go on with a search the narrow state stopped (WIDEN), its state moved here (widen_state): every
            # cell reached and not closed is open again, each expanding all its moves (the push below is
            # the loop's, spelled out as the loop's is). Their keys must fit the window above the least (as a
            # running search's do, with a consistent heuristic); else (WIDEN) the caller starts over.
            fcur = math.inf
            fmax = -math.inf
            for blk in range(flags.shape[0]):
                if not flags[blk]:
                    continue
                first, last = block_span(blk, gs.shape[0])
                for v in range(first, last):
                    pv = gs[np.uint64(v)]
                    if pv == zero or pv >= closed_bit:
                        continue
                    vx, vy = strip_xy(v, SH, wbits, magic, dshift)
                    f = state_g(pv, shift, a_mask, b_mask) + weight * heuristic(hcode, vx, vy, gx, gy)
                    fcur = min(fcur, f)
                    fmax = max(fmax, f)
                    if bump == cap_pool:
                        return OVERFLOW, 0
                    n = bump
                    bump += 1
                    key[np.uint64(n)] = f
                    cell[np.uint64(n)] = v * 256 + 255
                    b = np.int64(f * inv_width) & mask
                    hb = head[np.uint64(b)]
                    if hb < 0:  # (a bucket's bit is set while it holds a node: only its first push sets it)
                        low[np.uint64(b)] = f
                        occupied[np.uint64(b >> 6)] |= np.uint64(1) << np.uint64(b & 63)
                    elif f < low[np.uint64(b)]:
                        low[np.uint64(b)] = f
                    nxt[np.uint64(n)] = hb
                    head[np.uint64(b)] = n
            if fcur == math.inf or (fmax - fcur) * inv_width > N_BUCKETS - 3:
                return WIDEN, 0
            cb = np.int64(fcur * inv_width) & mask
            fcur = -math.inf  # (the first pop takes the lowest bucket's least key)
            top = 0
        else:
            if any_angle:
                gs[np.uint64(start)] = 1.0
                parent[start] = start
            else:
                gs[np.uint64(start)] = a_one
            flags[np.uint64(start >> BLOCK_BITS)] = 1
            sx, sy = strip_xy(start, SH, wbits, magic, dshift)
            fcur = 1.0 + weight * heuristic(hcode, sx, sy, gx, gy)  # keys are (g + 1) + weight * h
            cb = np.int64(fcur * inv_width) & mask
            stack[np.uint64(0)] = start * 256 + 255  # open entries: cell * 256 + the moves it may expand
            top = 1
        while True:
            if top == 0:  # the next non-empty bucket (circularly from cb): its smallest keys go on the stack
                word = cb >> 6
                bits = occupied[np.uint64(word)] & (ALL_BITS << np.uint64(cb & 63))
                # (no count of queued nodes: an empty open list is found here, every word read once and
                # this one whole; random4096 0.981 of the time, 1.009 swapped, maze1001 0.979 and 0.995;
                # paired in-process A/B)
                for _ in range(word_mask + 1):  # the other words, then this one whole
                    if bits != 0:
                        break
                    word = (word + 1) & word_mask
                    bits = occupied[np.uint64(word)]
                if bits == 0:
                    break  # the open list is empty: no path
                cb = word * 64 + np.int64(_cttz(bits))
                fcur = low[np.uint64(cb)]
                n = head[np.uint64(cb)]
                head[np.uint64(cb)] = -1
                while n >= 0:
                    after = nxt[np.uint64(n)]
                    kn = key[np.uint64(n)]
                    if kn <= fcur + TIE:
                        if top == cap_stack:
                            status = OVERFLOW
                            break
                        stack[np.uint64(top)] = cell[np.uint64(n)]
                        top += 1
                        nxt[np.uint64(n)] = free_node
                        free_node = n
                    else:
                        if head[np.uint64(cb)] < 0 or kn < low[np.uint64(cb)]:
                            low[np.uint64(cb)] = kn
                        nxt[np.uint64(n)] = head[np.uint64(cb)]
                        head[np.uint64(cb)] = n
                    n = after
                if head[np.uint64(cb)] < 0:
                    occupied[np.uint64(word)] &= ~(np.uint64(1) << np.uint64(cb & 63))
                if status == OVERFLOW:
                    break
            top -= 1
            u = stack[np.uint64(top)] >> 8
            allowed = stack[np.uint64(top)] & 255
            if canonical:
                # Further along the move that reached u lie the cells the search reaches next (a
                # canonical entry's highest move: the arrival move or a diagonal beside it): start
                # loading their state and moves, which a first visit finds in memory, not in cache
                # (4% of A*'s time on random4096, 5% on maze1001, paired in-process A/B). The address
                # may lie outside the arrays near the border: a prefetch never faults.
                # (Across a strip's edge the line bends: that prefetch is wasted, never wrong.) The lead
                # move's step is read from ``offsets`` (a cell inside a strip), not from _DX and _DY: 0.964
                # to 0.976 of random4096 A*'s time, and 1.031 with the versions swapped (paired in-process A/B).
                lead = LEAD[np.uint64(allowed)]
                ahead = u + LOOK * offsets[np.uint64(lead)]
                _prefetch(gs, ahead)
                _prefetch(moves, ahead)
            if top > 0:
                # The cell below on the stack is usually expanded next, and far from this one: start
                # loading its state and grid now (A* waits on memory, not arithmetic: 11-16% faster on
                # random4096, 9% on maze1001). In padded rows the rows above and below it, and the cell
                # below it on the stack, were prefetched as well; in strips each of those measured as
                # noise or a loss (the cell below: 0.991 of the time without it on random4096, 0.965
                # on maze1001; the rows: 1.023; the neighbour its highest move leads to: 1.010).
                w = stack[np.uint64(top - 1)] >> 8
                _prefetch(gs, w)
                _prefetch(moves, w)
            if any_angle:
                gu = gs[np.uint64(u)]
                if gu < 0.0:  # closed already: a node superseded by a better push, or a tie pushed twice
                    continue
                gs[np.uint64(u)] = -gu
                pu = zero
            else:
                pu = gs[np.uint64(u)]
                if pu >= closed_bit:  # closed already (as above)
                    continue
                if not wide and u != goal and (would_carry(pu >> shift, 1, a_mask) or would_carry(pu & b_mask, 1,
                                                                                                  b_mask)):
                    status = WIDEN  # a move from here would carry into the next field; u stays open (resume)
                    break
                gs[np.uint64(u)] = pu | closed_bit
                gu = state_g(pu, shift, a_mask, b_mask)
            expanded += 1
            ux, uy = strip_xy(u, SH, wbits, magic, dshift)
            if u == goal:
                status = 1
                break
            grandparent = parent[u] if any_angle else u  # Theta*: the parent a child may inherit
            column = u & edge
            side = (np.int64(column == edge) | (np.int64(column == 0) << 1)) << 3  # which 8 of ``offsets``
            mu = np.int64(moves[np.uint64(u)])
            m = mu & legal & allowed
            for j in range(slots):  # the legal moves, lowest bit first (orthogonal before diagonal)
                if conn == 8:
                    if m == 0:
                        break
                    k = _cttz(m)
                    m &= m - 1
                else:
                    # Four bits: tested one by one in a loop LLVM unrolls (constant moves); the bit scan
                    # made 4-connected A* 10-25% slower than the old unrolled tests (in-process A/B).
                    k = j
                    if (m >> k) & 1 == 0:
                        continue
                dx = _DX[np.uint64(k)]
                dy = _DY[np.uint64(k)]
                v = u + offsets[np.uint64(side + k)]
                if any_angle:
                    gv = gs[np.uint64(v)]
                    if gv < 0.0:
                        continue  # closed: never improved (and Theta* spares its line of sight)
                    ng = gu + _STEP[np.uint64(k)]
                    par = u
                    if grandparent != u:
                        qx, qy = strip_xy(grandparent, SH, wbits, magic, dshift)
                        if los_supercover(free, S, qx - 1, qy - 1, ux + dx - 1, uy + dy - 1):
                            ng = -gs[np.uint64(grandparent)] + math.sqrt((ux + dx - qx) ** 2 + (uy + dy - qy) ** 2)
                            par = grandparent
                    better = gv == 0.0 or ng < gv
                else:
                    pv = gs[np.uint64(v)]
                    pn = pu + step_bits[np.uint64(k)]
                    ng = state_g(pn, shift, a_mask, b_mask)
                    # a closed cell is never improved: closed cells are not reopened (as Theta*'s above)
                    better = pv == zero or (pv < closed_bit and ng < state_g(pv, shift, a_mask, b_mask))
                if better:
                    if any_angle:
                        gs[np.uint64(v)] = ng
                        parent[v] = par
                    else:
                        gs[np.uint64(v)] = pn
                    # its block, for the next query to clear: a byte stored per write, where bounds on
                    # each row's columns took two loads, two compares and their branches per expansion
                    # (random4096 A* 0.955x the time in strips, paired in-process A/B)
                    flags[np.uint64(v >> BLOCK_BITS)] = 1
                    if canonical:
                        entry = v * 256 + np.int64(CANONICAL[np.uint64(k * 256 + mu)])
                    else:
                        entry = v * 256 + 255
                    f = ng + weight * heuristic(hcode, ux + dx, uy + dy, gx, gy)
                    if f <= fcur + TIE:
                        if top == cap_stack:
                            status = OVERFLOW
                            break
                        stack[np.uint64(top)] = entry
                        top += 1
                        continue
                    if free_node >= 0:
                        n = free_node
                        free_node = nxt[np.uint64(n)]
                    elif bump < cap_pool:
                        n = bump
                        bump += 1
                    else:
                        status = OVERFLOW
                        break
                    key[np.uint64(n)] = f
                    cell[np.uint64(n)] = entry
                    b = np.int64(f * inv_width) & mask
                    hb = head[np.uint64(b)]
                    # A bucket's bit is set while it holds a node, so only its first push sets it (random4096
                    # 0.980 of the time, 1.028 swapped; maze1001 0.958 and 1.033; paired in-process A/B)
                    if hb < 0:
                        low[np.uint64(b)] = f
                        occupied[np.uint64(b >> 6)] |= np.uint64(1) << np.uint64(b & 63)
                    elif f < low[np.uint64(b)]:
                        low[np.uint64(b)] = f
                    nxt[np.uint64(n)] = hb
                    head[np.uint64(b)] = n
            if status == OVERFLOW:
                break
        return status, expanded

    return astar


@njit(cache=True)
def _predecessor(moves, SH, bits, gs, v, n_moves, steps, value_mask):
    """A reached neighbour u of v with ``state(u) + steps[k] == state(v)``
    (packed states without their closed bit, :func:`state_layout`; ``steps``:
    what each move k adds, :func:`state_steps`), over a legal move
    (``moves``: the legal-move masks; all in the strip layout); -1 if there is none."""
    pv = gs[v] & value_mask
    east, west = strip_sides(v, SH, bits)
    for k in range(n_moves):
        u = strip_step_back(v, k, bits, east, west)
        pu = gs[u] & value_mask
        if (moves[u] >> k) & 1 == 0 or pu == 0:  # u cannot step to v, or was never reached
            continue
        if pu + steps[k] == pv:
            return u
    return -1


@njit(cache=True, nogil=True)
def trace_back(moves, SH, bits, gs, start, goal, conn, steps, value_mask):
    """Cells (x, y) from start to goal of the path A* found, read from its
    packed state ``gs`` alone (A* keeps no parents; :func:`state_layout`;
    ``steps`` and ``value_mask`` of the state's dtype: :func:`trace_back_args`;
    ``moves`` and ``gs`` in the strip layout of ``SH`` and ``bits``).

    Why this works: every reached cell v other than the start got its state
    as ``state[u] + step(u, v)`` (one more straight or diagonal move) from a
    cell u that was closed then, and closed cells never change again, so at
    the end v has at least one reached neighbour u with ``state[u] + step ==
    state[v]``, in whole numbers: a predecessor always exists. Any such u (not
    only the one that set v) lies on a path of cost g[v], since every stored
    state counts the moves of a path the search built; so the walk from the goal returns a
    path of exactly the cost the search found, optimal when the goal's g is
    (A* with a consistent heuristic). It ends: each step removes a move, and
    the start is the only cell with none. Returns an empty array if the walk
    breaks (which would be a bug in the search).
    """
    n_moves = 8 if conn == 8 else 4
    magic, shift = divider(SH, gs.shape[0])
    count = 1
    v = goal
    while v != start:
        v = _predecessor(moves, SH, bits, gs, v, n_moves, steps, value_mask)
        if v < 0:
            return np.empty((0, 2), dtype=np.int64)
        count += 1
    out = np.empty((count, 2), dtype=np.int64)
    v = goal
    for m in range(count - 1, -1, -1):
        x, y = strip_xy(v, SH, bits, magic, shift)
        out[m, 0] = x - 1
        out[m, 1] = y - 1
        if m > 0:
            v = _predecessor(moves, SH, bits, gs, v, n_moves, steps, value_mask)
    return out


def trace_back_args(wide: bool):
    """:func:`trace_back`'s ``steps`` and ``value_mask`` (the state without its closed bit) for the
    narrow or wide state."""
    return state_steps(wide), ~state_layout(wide)[4]


# -- Jump Point Search (8-connected, no corner cutting) -------------------------
# The jumps read the legal-move masks (:func:`legal_moves`): a straight jump
# steps while its forward bit is set and stops where a side bit appears that
# the previous cell lacked (a side cell opens where it was blocked behind:
# a forced neighbour); a diagonal step's bit already says that both cells
# beside it and the cell it enters are free.
_SIDES_X = 0b1100  # moving along x, the cells beside are north (bit 2) and south (bit 3)
_SIDES_Y = 0b0011  # moving along y: east (bit 0) and west (bit 1)
# A jump point's successors are those canonical A* relaxes (:data:`CANONICAL`;
# Harabor & Grastien 2014 without corner cutting): after a straight jump the
# move itself and, on a side blocked beside the cell before, the side move and
# the diagonal ahead; after a diagonal, it and its straight parts. (Until
# session 14 every straight arrival also tried both perpendicular moves and
# both diagonals ahead: the same costs (the paths may be others of that cost),
# 2.81 instead of 2.31 million jump points on random4096, 0.76x the time
# without them.)
# Helpers that take arrays are plain njit functions (LLVM inlines them), not numba's
# inline="always", and JPS records rows itself instead of calling a helper: numba leaves an
# atomic NRT_incref/NRT_decref of each array argument around such calls (inlined at its own
# level, or a helper whose body branches), which its reference-count pruning misses, and a
# locked add drains the store buffer. In the loop that was an increment and a decrement of
# ``moves`` per jump and of ``lo`` and ``hi`` per push: random4096 JPS 0.81x the time without
# them (in-process A/B, CPU medians, 9 runs; tests/grid/test_kernel_refcounts.py).


@njit(cache=True)
def _jump_straight(moves, v, d, k, sides, goal):
    """From free cell v, entered by straight move k (offset d): the jump point
    (or -1 at a dead end) and the steps from v to it."""
    prev = moves[np.uint64(v - d)]
    n = 0
    while True:
        cur = moves[np.uint64(v)]
        if v == goal or (cur & ~prev & sides) != 0:
            return v, n
        if (cur >> k) & 1 == 0:
            return -1, n
        prev = cur
        v += d
        n += 1


@njit(cache=True)
def _jump_diagonal(moves, S, v, dx, dy, k, goal):
    """From free cell v, entered by diagonal move k = (dx, dy): the jump point
    (a cell whose straight parts reach one) or -1, and the steps to it."""
    kx = 0 if dx > 0 else 1
    ky = 2 if dy > 0 else 3
    n = 0
    while True:
        m = moves[np.uint64(v)]
        if v == goal:
            return v, n
        if (m >> kx) & 1 and _jump_straight(moves, v + dx, dx, kx, _SIDES_X, goal)[0] >= 0:
            return v, n
        if (m >> ky) & 1 and _jump_straight(moves, v + dy * S, dy * S, ky, _SIDES_Y, goal)[0] >= 0:
            return v, n
        if (m >> k) & 1 == 0:
            return -1, n
        v += dx + dy * S
        n += 1


def make_jps(wide: bool = False):
    """:func:`jps` compiled for the narrow (uint32) or ``wide`` (uint64) packed state of
    :func:`state_layout`, as :func:`make_astar` is."""
    state_type, shift, a_mask, b_mask, closed_bit = state_layout(wide)
    zero = state_type(0)
    a_one = state_type(1) << shift
    step_bits = state_steps(wide)

    @njit(cache=True, nogil=True)
    def jps(moves, S, start, goal, gs, lo, hi, extent, key, cell, nxt, head, stack):
        """Jump Point Search for 8-connected grids without corner cutting.

        The same packed per-cell state (``gs``, as :func:`state_layout` says, but in padded rows, with
        the rows and columns expanded recorded in ``lo``, ``hi`` and ``extent``) and return
        values as the A* kernel (:func:`make_astar`; a jump adds its n moves to one field at once, and
        a field it would carry over stops the search with WIDEN), and like A* no parents: an open entry
        carries the move that reached its cell (which successors to try: the
        first entry of a cell popped is its last and best push, so its move is
        that of its g), and :func:`trace_jumps` reads the path back from ``gs``.
        Without the parent and arrival arrays (5 bytes per cell) random4096 ran
        in 0.71 s instead of 1.0 s (CPU medians, 9 interleaved runs, load 7,
        path tracing included). The open list
        is A*'s circular bucket queue and same-f stack over ``key``, ``cell``,
        ``nxt`` and ``head``, except that a jump can raise f by more than the
        ring spans: such keys wait in an overflow list, moved into the ring when
        the ring's minimum reaches theirs (:data:`JPS_SPAN`). Indexed through
        ``np.uint64`` like A*.
        """
        clear_touched(gs, S, lo, hi, extent)  # what the previous query wrote
        gx = goal % S
        gy = goal // S
        wrap = N_BUCKETS - 1
        inv_width = N_BUCKETS / JPS_SPAN
        for b in range(N_BUCKETS):
            head[np.uint64(b)] = -1
        low = np.empty(N_BUCKETS)  # a non-empty bucket's smallest key (as A*'s)
        free_node = -1
        bump = 0
        ring = 0  # nodes in the ring
        over = -1  # the overflow list and its smallest bucket number
        over_min = np.int64(1) << 62
        cap_pool = key.shape[0]
        cap_stack = stack.shape[0]
        gs[np.uint64(start)] = a_one
        rmin = rmax = start // S
        lo[np.uint64(rmin)] = min(lo[np.uint64(rmin)], start % S)  # the start's row and column, recorded
        hi[np.uint64(rmin)] = max(hi[np.uint64(rmin)], start % S)
        fcur = 1.0 + heuristic(H_OCTILE, start % S, start // S, gx, gy)  # keys are (g + 1) + h, as A*'s
        cur = np.int64(fcur * inv_width)  # the ring's lowest bucket number (not wrapped)
        stack[np.uint64(0)] = start * 16 + 8  # open entries are cell * 16 + the move that reached it (8: none)
        top = 1
        expanded = 0
        status = 0
        while ring > 0 or over >= 0 or top > 0:
            if top == 0:
                if ring == 0:
                    cur = over_min
                while True:
                    if cur >= over_min:  # overflow keys now within the ring's span move in
                        n = over
                        over = -1
                        over_min = np.int64(1) << 62
                        while n >= 0:
                            after = nxt[np.uint64(n)]
                            a = np.int64(key[np.uint64(n)] * inv_width)
                            if a < cur + N_BUCKETS:
                                kn = key[np.uint64(n)]
                                if head[np.uint64(a & wrap)] < 0 or kn < low[np.uint64(a & wrap)]:
                                    low[np.uint64(a & wrap)] = kn
                                nxt[np.uint64(n)] = head[np.uint64(a & wrap)]
                                head[np.uint64(a & wrap)] = n
                                ring += 1
                            else:
                                nxt[np.uint64(n)] = over
                                over = n
                                over_min = min(over_min, a)
                            n = after
                    if head[np.uint64(cur & wrap)] >= 0:
                        break
                    cur += 1
                cb = cur & wrap
                fcur = low[np.uint64(cb)]
                n = head[np.uint64(cb)]
                head[np.uint64(cb)] = -1
                while n >= 0:
                    after = nxt[np.uint64(n)]
                    kn = key[np.uint64(n)]
                    if kn <= fcur + TIE:
                        if top == cap_stack:
                            status = OVERFLOW
                            break
                        stack[np.uint64(top)] = cell[np.uint64(n)]
                        top += 1
                        nxt[np.uint64(n)] = free_node
                        free_node = n
                        ring -= 1
                    else:
                        if head[np.uint64(cb)] < 0 or kn < low[np.uint64(cb)]:
                            low[np.uint64(cb)] = kn
                        nxt[np.uint64(n)] = head[np.uint64(cb)]
                        head[np.uint64(cb)] = n
                    n = after
                if status == OVERFLOW:
                    break
            top -= 1
            u = stack[np.uint64(top)] >> 4
            came = stack[np.uint64(top)] & 15
            # As A* does (make_astar), the state and moves further along the arrival move (the start's
            # 8 reads as move 0): 6% of JPS's time on random4096 (paired in-process A/B; 5 to 12 cells
            # ahead within 1.5%), and the stack's second cell below (2%).
            lead = came & 7
            ahead = u + JPS_LOOK * (_DX[np.uint64(lead)] + _DY[np.uint64(lead)] * S)
            _prefetch(gs, ahead)
            _prefetch(moves, ahead)
            if top > 0:
                # As A* does: start loading what the next cell's jumps read first (its moves and those of
                # the rows beside, the state around it, its arrival move); JPS waits on memory even more.
                w = stack[np.uint64(top - 1)] >> 4
                for row in (w - S, w, w + S):
                    _prefetch(gs, row)
                    _prefetch(moves, row)
                if top > 1:
                    w = stack[np.uint64(top - 2)] >> 4
                    for row in (w - S, w, w + S):
                        _prefetch(gs, row)
                        _prefetch(moves, row)
            pu = gs[np.uint64(u)]
            if pu >= closed_bit:  # closed already: a node superseded by a better push, or a tie pushed twice
                continue
            gs[np.uint64(u)] = pu | closed_bit
            gu = state_g(pu, shift, a_mask, b_mask)
            expanded += 1
            if u == goal:
                status = 1
                break
            ux, uy = cell_xy(u, S)
            # The successors canonical A* would relax (CANONICAL): after a straight jump, the move
            # itself and, on a side blocked beside the cell before, the side move and the diagonal
            # ahead; after a diagonal, it and its straight parts; from the start, every move.
            m = np.int64(moves[np.uint64(u)])
            if came < 4:
                back = u - _DX[np.uint64(came)] - _DY[np.uint64(came)] * S
                m &= np.int64(CANONICAL[np.uint64(came * 256 + np.int64(moves[np.uint64(back)]))])
            elif came < 8:
                m &= np.int64(CANONICAL[np.uint64(came * 256)])
            while m != 0:
                k = _cttz(m)
                m &= m - 1
                dx = _DX[np.uint64(k)]
                dy = _DY[np.uint64(k)]
                if k >= 4:
                    jp, n = _jump_diagonal(moves, S, u + dx + dy * S, dx, dy, k, goal)
                elif k < 2:
                    jp, n = _jump_straight(moves, u + dx, dx, k, _SIDES_X, goal)
                else:
                    jp, n = _jump_straight(moves, u + dy * S, dy * S, k, _SIDES_Y, goal)
                if jp < 0:
                    continue
                # a jump is n + 1 equal moves, added to one field of the state: none may carry over
                if not wide and (would_carry(pu >> shift, n + 1, a_mask) if k < 4 else
                                 would_carry(pu & b_mask, n + 1, b_mask)):
                    status = WIDEN
                    break
                pn = pu + step_bits[np.uint64(k)] * state_type(n + 1)
                ng = state_g(pn, shift, a_mask, b_mask)
                pj = gs[np.uint64(jp)]
                if pj == zero or (pj < closed_bit and ng < state_g(pj, shift, a_mask, b_mask)):
                    gs[np.uint64(jp)] = pn
                    jx = ux + (n + 1) * dx
                    jy = uy + (n + 1) * dy
                    if jx < lo[np.uint64(jy)]:
                        lo[np.uint64(jy)] = jx
                    if jx > hi[np.uint64(jy)]:
                        hi[np.uint64(jy)] = jx
                    rmin = min(rmin, jy)
                    rmax = max(rmax, jy)
                    f = ng + heuristic(H_OCTILE, jx, jy, gx, gy)
                    if f <= fcur + TIE:
                        if top == cap_stack:
                            status = OVERFLOW
                            break
                        stack[np.uint64(top)] = jp * 16 + k
                        top += 1
                        continue
                    if free_node >= 0:
                        nd = free_node
                        free_node = nxt[np.uint64(nd)]
                    elif bump < cap_pool:
                        nd = bump
                        bump += 1
                    else:
                        status = OVERFLOW
                        break
                    key[np.uint64(nd)] = f
                    cell[np.uint64(nd)] = jp * 16 + k
                    a = np.int64(f * inv_width)
                    if a < cur + N_BUCKETS:
                        if head[np.uint64(a & wrap)] < 0 or f < low[np.uint64(a & wrap)]:
                            low[np.uint64(a & wrap)] = f
                        nxt[np.uint64(nd)] = head[np.uint64(a & wrap)]
                        head[np.uint64(a & wrap)] = nd
                        ring += 1
                    else:
                        nxt[np.uint64(nd)] = over
                        over = nd
                        over_min = min(over_min, a)
            if status == OVERFLOW or status == WIDEN:
                break
        extent[0] = min(extent[0], rmin)
        extent[1] = max(extent[1], rmax)
        return status, expanded

    return jps


@njit(cache=True)
def _jump_predecessor(moves, S, gs, v, steps, value_mask):
    """A reached cell c on a straight or diagonal run of legal moves into v
    with ``state(c) + L * steps[k] == state(v)`` after L moves k (packed states
    without their closed bit, :func:`state_layout`: what JPS added), or -1 if
    there is none."""
    pv = gs[np.uint64(v)] & value_mask
    for k in range(8):
        d = _DX[np.uint64(k)] + _DY[np.uint64(k)] * S
        step = steps[k]
        added = step - step  # L moves k, in the state's own integer type (L * step would be a float in 64 bits)
        c = v
        while True:
            c -= d
            added += step
            if (moves[np.uint64(c)] >> k) & 1 == 0:  # c cannot step toward v (blocked cells have no moves)
                break
            pc = gs[np.uint64(c)] & value_mask
            if pc != 0 and pc + added == pv:
                return c
    return -1


@njit(cache=True, nogil=True)
def trace_jumps(moves, S, gs, start, goal, steps, value_mask):
    """Cells (x, y) from start to goal of the path JPS found, every cell of
    each jump filled in, read from its packed state ``gs`` alone (JPS keeps no
    parents; ``steps`` and ``value_mask``: :func:`trace_back_args`).

    As :func:`trace_back` for A*: a jump point's state was set as its jump
    origin's plus L moves along a run of legal moves, and that origin
    is closed (unchanged) at the end, so walking back along each of the
    eight runs into v finds a reached cell with exactly that sum, in whole
    numbers; any cell that matches lies on a path of cost g[v], so the walk
    returns a path of the cost JPS found. It ends since each jump removes
    moves. Empty if the walk breaks (a bug in the search).
    """
    count = 1
    v = goal
    while v != start:
        p = _jump_predecessor(moves, S, gs, v, steps, value_mask)
        if p < 0:
            return np.empty((0, 2), dtype=np.int64)
        count += max(abs(v % S - p % S), abs(v // S - p // S))
        v = p
    out = np.empty((count, 2), dtype=np.int64)
    m = count - 1
    v = goal
    out[m, 0] = v % S - 1
    out[m, 1] = v // S - 1
    while v != start:
        p = _jump_predecessor(moves, S, gs, v, steps, value_mask)
        vx, vy, px, py = v % S, v // S, p % S, p // S
        steps_between = max(abs(vx - px), abs(vy - py))
        for k in range(steps_between - 1, -1, -1):  # the cells from just after p back to p
            m -= 1
            out[m, 0] = px + (vx - px) * k // steps_between - 1
            out[m, 1] = py + (vy - py) * k // steps_between - 1
        v = p
    return out


@njit(cache=True, nogil=True)
def trace_path(parent, goal, SH, bits):
    """Cells (x, y) from start to goal along Theta*'s parent chain (its
    waypoints: consecutive cells see each other; strip-layout indices)."""
    magic, shift = divider(SH, parent.shape[0])
    count = 1
    v = goal
    while parent[v] != v:
        count += 1
        v = parent[v]
    out = np.empty((count, 2), dtype=np.int64)
    v = goal
    for m in range(count - 1, -1, -1):
        x, y = strip_xy(v, SH, bits, magic, shift)
        out[m, 0] = x - 1
        out[m, 1] = y - 1
        v = parent[v]
    return out


@njit(cache=True, nogil=True)
def smooth_path(free, S, cells, bresenham):
    """Greedy line-of-sight shortcut: from each kept cell, advance to the last
    cell of the following run that stays visible; drop the cells between."""
    n = cells.shape[0]
    keep = np.zeros(n, dtype=np.bool_)
    keep[0] = True
    keep[n - 1] = True
    i = 0
    while i < n - 1:
        j = i + 1
        while j + 1 < n:
            if bresenham:
                ok = los_bresenham(free, S, cells[i, 0], cells[i, 1], cells[j + 1, 0], cells[j + 1, 1])
            else:
                ok = los_supercover(free, S, cells[i, 0], cells[i, 1], cells[j + 1, 0], cells[j + 1, 1])
            if not ok:
                break
            j += 1
        keep[j] = True
        i = j
    return cells[keep]


@njit(cache=True, nogil=True)
def step_counts(cells):
    """(straight steps, diagonal steps, Euclidean length of longer steps)."""
    straight = 0
    diagonal = 0
    rest = 0.0
    for k in range(1, cells.shape[0]):
        dx = abs(cells[k, 0] - cells[k - 1, 0])
        dy = abs(cells[k, 1] - cells[k - 1, 1])
        if dx <= 1 and dy <= 1:
            if dx + dy == 1:
                straight += 1
            elif dx + dy == 2:
                diagonal += 1
        else:
            rest += math.sqrt(dx * dx + dy * dy)
    return straight, diagonal, rest
