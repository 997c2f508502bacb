"""Hybrid A*'s holonomic field, computed lazily: the wave from the goal runs only as far as the search reads.

The field is the shortest 8-connected distance [m] from the goal's cell over the cells the robot's
centre can cross (Dijkstra; diagonal steps only between two free orthogonal cells). Computing it over
the whole map before the search cost 6-10 ms on a 384² map, more than half of many queries, while the
search reads it only at cells no farther from the goal than about the start. Nav2's Smac planner
(``NodeHybrid::getObstacleHeuristic``, nav2_smac_planner/src/node_hybrid.cpp) therefore expands its
obstacle heuristic's Dijkstra only until the cell asked for is settled and resumes it on a later
lookup; navlab does the same (Smac also downsamples the map 2x for it, which changes the values;
navlab keeps the full resolution, so the values and the paths are the same as the whole field's).

Dial's bucket queue instead of a heap: buckets a little narrower than the shortest step (one cell),
so no cell can improve another of its own bucket and each bucket's cells are final in any order. A
step is at most √2 cells, so a relaxed cell lands one or two buckets ahead and three buckets, reused
in turn, hold the whole frontier. Every cell ends at the minimum over its neighbours of (their
distance + step), as with a heap, so the values are the same bit for bit; and pausing between two
settled cells changes neither the order nor the values, so a lazily read value is the whole field's.

The state is plain arrays (:func:`field_start`): the cells numbered row by row in a copy of the map
ringed by impassable cells, one state byte each (bit 1 passable, bit 2 settled), so a neighbour is a
fixed offset away and needs no bounds test; ``dist`` [m] on the same numbering; the three buckets'
cells and sizes; and a cursor (bucket number, position in it).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit

PASSABLE, SETTLED = 1, 2


@njit(cache=True)
def field_start(passable: np.ndarray, gx: int, gy: int, res: float):
    """A lazy field from cell (gx, gy) over ``passable`` cells (the wave leaves the goal's cell even if it is
    not passable, as the whole field did; the planner marks it passable).

    Returns (state, dist, cells, size, cursor): nothing settled yet; read it with :func:`field_at`.
    """
    h, w = passable.shape
    stride = w + 2
    state = np.zeros((h + 2) * stride, dtype=np.uint8)
    for y in range(h):
        row = (y + 1) * stride + 1
        for x in range(w):
            if passable[y, x]:
                state[row + x] = PASSABLE
    dist = np.full((h + 2) * stride, np.inf)
    goal = (gy + 1) * stride + gx + 1
    dist[goal] = 0.0
    cells = np.empty((3, 1024), dtype=np.int64)
    size = np.zeros(3, dtype=np.int64)
    cells[0, 0] = goal
    size[0] = 1
    # bucket number, position in its slot; then the eight neighbours in the order (dy, dx) = (−1, −1),
    # (−1, 0), ... (1, 1): offsets, and a diagonal step's two orthogonal neighbours (0: not diagonal)
    cursor = np.zeros(26, dtype=np.int64)
    n = 0
    for dy in range(-1, 2):
        for dx in range(-1, 2):
            if dx == 0 and dy == 0:
                continue
            cursor[2 + n] = dy * stride + dx
            if dx != 0 and dy != 0:
                cursor[10 + n], cursor[18 + n] = dx, dy * stride
            n += 1
    return state, dist, cells, size, cursor


@njit(cache=True)
def field_settle(state, dist, cells, size, cursor, stride: int, res: float, target: int):
    """Run the wave until cell ``target`` (an index into ``state``) is settled or nothing is pending
    (``target`` −1: until nothing is). Returns ``cells`` (a larger copy when a bucket filled up)."""
    while not field_settle_within(state, dist, cells, size, cursor, stride, res, target):
        cells = field_cells_grown(cells)
    return cells


@njit(cache=True)
def field_cells_grown(cells):
    """``cells`` with twice the room per bucket (what :func:`field_settle_within` asks for when it pauses)."""
    cap = cells.shape[1]
    grown = np.empty((3, 2 * cap), dtype=np.int64)
    grown[:, :cap] = cells
    return grown


@njit(cache=True)
def field_settle_within(state, dist, cells, size, cursor, stride: int, res: float, target: int) -> bool:
    """:func:`field_settle` in the room ``cells`` has: whether it got there (``target`` settled or
    nothing pending); False when it paused, before a cell, because a bucket had no room for the eight
    entries the cell can add (give it :func:`field_cells_grown` and call again: pausing between two
    settled cells changes nothing). It never replaces ``cells``, so a compiled loop that calls it keeps
    one array (numba counts the references of an array variable reassigned in a loop on every pass).

    The buckets ahead of the current one hold only unprocessed entries (a bucket is emptied when done
    and refilled only for two buckets on), so the entries pending are their sizes less the position.
    ``cursor[2:10]`` are the eight neighbours' offsets, ``cursor[10:18]`` and ``cursor[18:26]`` a
    diagonal step's two orthogonal neighbours' (0: not diagonal), set by :func:`field_start`."""
    # buckets (1 - 1e-6) res wide, below one step even after rounding (a product, not a quotient, per
    # relaxed cell: a value a rounding off its bucket's edge lands in the next, which the slack allows)
    per_width = 1.0 / (res * (1.0 - 1e-6))
    diag = math.sqrt(2.0) * res
    room = cells.shape[1] - 8
    offsets, side_x, side_y = cursor[2:10].copy(), cursor[10:18].copy(), cursor[18:26].copy()
    bucket, i = cursor[0], cursor[1]
    pending = size[0] + size[1] + size[2] - i
    while pending > 0:
        slot = bucket % 3
        while i < size[slot]:
            if size[0] > room or size[1] > room or size[2] > room:
                cursor[0], cursor[1] = bucket, i
                return False
            v = cells[slot, i]
            i += 1
            pending -= 1
            if state[v] & SETTLED:  # entered again after an improvement: settled already
                continue
            state[v] |= SETTLED
            d = dist[v]
            for k in range(8):
                u = v + offsets[k]
                if state[u] != PASSABLE:  # impassable (or off the map) or settled
                    continue
                if side_x[k] != 0:
                    if not (state[v + side_x[k]] & PASSABLE and state[v + side_y[k]] & PASSABLE):
                        continue
                    nd = d + diag
                else:
                    nd = d + res
                if nd < dist[u]:
                    dist[u] = nd
                    to = int(nd * per_width) % 3
                    cells[to, size[to]] = u
                    size[to] += 1
                    pending += 1
            if v == target:
                cursor[0], cursor[1] = bucket, i
                return True
        size[slot] = 0
        bucket += 1
        i = 0
    cursor[0], cursor[1] = bucket, i
    return True


@njit(cache=True)
def field_at(state, dist, cells, size, cursor, stride: int, res: float, cx: int, cy: int):
    """The field's value [m] at cell (cx, cy) (inf where the goal cannot be reached), settling as much of
    the wave as it needs, and ``cells`` (see :func:`field_settle`)."""
    v = (cy + 1) * stride + cx + 1
    # an impassable cell keeps its value (inf; 0 at the goal), so the wave need not reach it
    if state[v] & (PASSABLE | SETTLED) == PASSABLE and size[0] + size[1] + size[2] > cursor[1]:
        cells = field_settle(state, dist, cells, size, cursor, stride, res, v)
    return dist[v], cells


@njit(cache=True)
def field_from_clearance(cells_clear: np.ndarray, res: float, limit: float, gx: int, gy: int, sx: int, sy: int):
    """Hybrid A*'s field in one compiled call (each call costs a small query tens of microseconds right after
    another program has run): over the cells whose clearance ``cells_clear`` [cells] times ``res`` exceeds
    ``limit`` [m], and the goal's cell (gx, gy), settled as far as cell (sx, sy).

    Returns (passable, state, dist, cells, size, cursor, the field's value [m] at (sx, sy))."""
    h, w = cells_clear.shape
    passable = cells_clear * res > limit
    if 0 <= gy < h and 0 <= gx < w:
        passable[gy, gx] = True
    state, dist, cells, size, cursor = field_start(passable, gx, gy, res)
    at, cells = field_at(state, dist, cells, size, cursor, w + 2, res, sx, sy)
    return passable, state, dist, cells, size, cursor, at


@njit(cache=True)
def holonomic_field(passable: np.ndarray, gx: int, gy: int, res: float) -> np.ndarray:
    """The whole field [m] from cell (gx, gy) over ``passable`` cells, as an (h, w) array: the lazy
    field settled to the end (for tests and tools; the search reads it lazily)."""
    h, w = passable.shape
    state, dist, cells, size, cursor = field_start(passable, gx, gy, res)
    field_settle(state, dist, cells, size, cursor, w + 2, res, -1)
    return np.ascontiguousarray(dist.reshape(h + 2, w + 2)[1:h + 1, 1:w + 1])
