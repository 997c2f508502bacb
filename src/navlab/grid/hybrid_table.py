"""Hybrid A*'s obstacle-free distance table: Reeds–Shepp lengths to the goal, kept per robot.

Dolgov et al.'s "non-holonomic-without-obstacles" heuristic ("Path planning for
autonomous vehicles in unknown semi-structured environments", IJRR 29(5), 2010,
§3.2) is the shortest Reeds–Shepp length from a node's pose to the goal's. They
and Nav2's ``SmacPlannerHybrid`` (its ``lookup_table_size``, 20 m across by
default) precompute it in the goal's frame at the grid's cells and the search's
heading bins, once per robot, since it depends on the relative pose alone. A
solve costs about 1 µs, most of a query where the holonomic field stays below
the Reeds–Shepp length all the way (half of PythonRobotics' "middle to right"
query, session 21's profile).

Here the table is a pure function of its index, filled as searches first ask
for an entry (the same values as a table built up front, without building the
entries no query reaches): entry (i, j, k) holds the Reeds–Shepp length from
the pose (i·s, j·s, k·2π/bins) in the goal's frame to the goal, ``s`` half a
cell. A node reads the entry its relative pose rounds to, mirrored to j ≥ 0
(mirroring across the goal's axis swaps left and right turns, which keeps every
length). So a node's heuristic is the length from a pose at most s/√2 and half
a heading bin from its own, rounding that moves it either way, as Smac's does;
the search was never admissible (the holonomic field overstates by up to 8 %,
docs/grid.md), and the paths' costs are measured against known bests. Half a
cell, against a whole one: on PythonRobotics' four queries and the heading
scenes the expansions and costs stay within a few percent of the exact
lengths' (whole cells: 28 % more expansions and 1 % longer on "middle to
right").

The table reaches :data:`REACH_RADII` turning radii (and at least
:data:`MIN_REACH`) from the goal along each axis, unless capped at :data:`MAX_ENTRIES`
entries (8 bytes each; the memory is mapped 4 KB at a time as entries are
first written).
Beyond it the length is solved at the node's own pose, as it is with the table
off (``distance_table=False``: the exact lengths, and the same answers, bit for bit,
as the search before session 22; ``heuristics_solved`` now counts only lengths
actually solved).

Entries are written by whichever search first needs them, each the length of its
own lattice pose, so a query's answers are the same on any thread and in any
order of queries. (The kernels hold the GIL, so two searches never write at
once; if they did, both would write the same 8-byte value.)
"""

from __future__ import annotations

import functools
import math
import mmap

import numpy as np

from ..jit import njit
from ..sampling import reeds_shepp_length
from ..sampling.reeds_shepp import _local

#: [m] the table reaches this far from the goal along each axis (Smac's 20 m across), unless
#: :data:`MAX_ENTRIES` caps it
MIN_REACH = 10.0
#: ... and at least this many turning radii: farther off the length exceeds the straight line by a
#: bounded amount that the holonomic field mostly covers
REACH_RADII = 20.0
#: entries per cell along each axis (half-cell spacing)
PER_CELL = 2
#: the most entries a table holds: 32 MB of float64, mapped as they are first written
MAX_ENTRIES = 1 << 22
#: how many robots' tables are kept (least recently used dropped)
KEPT = 4
#: what :func:`~navlab.grid.hybrid_search.search` takes for no table: every length solved at the pose
NO_TABLE = (np.zeros(1), 1.0, -1)


@functools.lru_cache(maxsize=KEPT)
def distance_table(radius: float, resolution: float, bins: int):
    """The Reeds–Shepp distance table of a robot turning on ``radius`` [m] on cells of
    ``resolution`` [m] with ``bins`` heading bins: ``(table, spacing, half)`` as
    :func:`~navlab.grid.hybrid_search.search` takes them, the entries (0 until
    first solved), their spacing [m] and the table's half-width in entries.

    Kept per robot (the last :data:`KEPT`), keyed on the three values alone: an entry's
    value depends on nothing else."""
    spacing = resolution / PER_CELL
    half = int(math.ceil(max(MIN_REACH, REACH_RADII * radius) / spacing))
    half = max(1, min(half, int(math.sqrt(MAX_ENTRIES / (2 * bins))) - 1))
    return _zeros_in_small_pages((2 * half + 1) * (half + 1) * bins), spacing, half


def _zeros_in_small_pages(count: int) -> np.ndarray:
    """``count`` float64 zeros, mapped 4 KB page by page as they are first written.

    numpy asks the kernel for 2 MB pages for arrays of 4 MB and more, so each entry a query
    writes faulted in and zeroed 2 MB: 200 entries scattered over a 34 MB table took 14 ms
    and 39 MB of memory, against 0.6 ms and 0.8 MB in 4 KB pages (session 22)."""
    if not hasattr(mmap, "MAP_ANONYMOUS"):  # (not POSIX: numpy's own)
        return np.zeros(count)
    pages = mmap.mmap(-1, max(count, 1) * 8, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    if hasattr(mmap, "MADV_NOHUGEPAGE"):  # (Linux)
        pages.madvise(mmap.MADV_NOHUGEPAGE)
    return np.frombuffer(pages, dtype=np.float64, count=count)


@njit(cache=True, inline="always")
def table_pose(x, y, theta, gx, gy, gtheta, gcos, gsin, spacing, step, bins, half):
    """Pose (x, y, θ) as the distance table reads it: ``(index, px, py, pθ, qx, qy, qθ)``.

    Within the table, the pose in the goal's frame (``gcos``, ``gsin``: the goal heading's
    cosine and sine), mirrored to y >= 0 and rounded to the table's lattice (``spacing``
    [m] apart, headings ``step`` [rad] apart), and the goal at the origin. Elsewhere, or
    with no table (``half`` < 0), index −1 and the pose and goal themselves."""
    if half < 0:
        return -1, x, y, theta, gx, gy, gtheta
    dx, dy = x - gx, y - gy
    lx = gcos * dx + gsin * dy
    ly = -gsin * dx + gcos * dy
    rel = theta - gtheta
    if ly < 0.0:
        ly, rel = -ly, -rel
    reach = (half + 1) * spacing  # (only keeps the conversions to int in range)
    if not (abs(lx) < reach and ly < reach):
        return -1, x, y, theta, gx, gy, gtheta
    i = int(math.floor(lx / spacing + 0.5))
    j = int(math.floor(ly / spacing + 0.5))
    # the rounded entry decides, not the float: ly just below (half + 0.5)·spacing can round to half + 1,
    # which indexed the next row's entry, or past the table's end into another robot's (review, session 22)
    if abs(i) > half or j > half:
        return -1, x, y, theta, gx, gy, gtheta
    k = int(math.floor(rel / step + 0.5)) % bins
    return ((i + half) * (half + 1) + j) * bins + k, i * spacing, j * spacing, k * step, 0.0, 0.0, 0.0


@njit(cache=True)
def reeds_shepp_memo(table, index, x, y, theta, gx, gy, gtheta, radius, cutoff) -> float:
    """The Reeds–Shepp length [m] from (x, y, θ) to the goal pose: ``table[index]`` once solved
    there (``index`` >= 0), else solved (and kept there when ``index`` >= 0).

    ``cutoff`` [turning radii] bounds the length from above (a Dubins length: words that
    cannot beat it are dropped sooner; the same length, bit for bit, as the full solve,
    which runs should rounding put the length at the bound)."""
    if index >= 0 and table[index] > 0.0:
        return table[index]
    lx, ly, phi = _local(x, y, theta, gx, gy, gtheta, radius)
    length = reeds_shepp_length.length_below(lx, ly, phi, cutoff)
    if length == math.inf:
        length = reeds_shepp_length.length(lx, ly, phi)
    if index >= 0:
        table[index] = length * radius
    return length * radius
