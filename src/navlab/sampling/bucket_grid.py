"""A uniform bucket grid over the tree's nodes: exact nearest and near-set queries.

Why a bucket grid
-----------------
The tree loop asks two questions per iteration: the nearest node to a sample
and every node within the RRT* radius r(n) of a new node. Both have to give
*exactly* the answers of a linear scan (the same nearest node, the lowest
index on a tie; the same near set, whose order the tree loop does not depend
on), so that a seed gives the same tree whichever index is used. In 2-D with nodes that never move (rewiring
changes parents and costs, never positions) a uniform grid is the simplest
structure that does this in expected constant time:

- insertion is O(1) (append to the cell's block), so there are no batches of
  unindexed nodes and no rebalancing, unlike a k-d tree rebuilt in batches or
  OMPL's GNAT;
- both queries are exact by construction: the near query visits every cell
  the disc can touch; the nearest query visits rings of cells around the
  sample until the distance to the unvisited rings provably exceeds the best
  distance found (ties are broken by index, so the visiting order does not
  matter);
- its cost depends on the number of nodes per cell, which stays within a
  constant factor because the grid is rebuilt (O(n), amortised O(1) per node)
  each time the tree doubles, with cells sized for ``NODES_PER_CELL`` nodes
  at the size the tree will reach before the next rebuild.

Each cell keeps its nodes' coordinates, indices and costs in its own block
of shared arrays (sized at each rebuild to the cell's share of the expected
growth plus a little), blocks in cell order, with the cells' bookkeeping
interleaved in one array. A query then reads a few contiguous runs per row
of cells instead of chasing nodes scattered over the tree's arrays: at 10⁶
nodes memory latency, not arithmetic, is the cost of a query. The near query
returns each node's squared distance and cost from the block, so the tree
loop reads the tree's arrays only for the few nodes it rewires (rewiring
updates the block's copy of a cost through ``slot``). A node arriving in a
full block goes on the cell's overflow list (linked through the node index).

Cells cover the world's bounds. A node or sample outside them falls into the
nearest border cell: border cells then extend to infinity outwards, which
keeps every distance bound below true (a node in a cell right of the visited
block is still right of the block's right edge). Distance bounds subtract a
margin far above floating-point rounding, so a node whose cell index rounded
the other way is never skipped.

The coarse counts also answer a cheaper question, :func:`node_within`: is
some node surely within a distance (a coarse cell holding nodes lies wholly
inside it)? The tree loop asks it for samples in collision.

Its weakness is a tree much denser in one part of the bounds than elsewhere
(informed sampling in a thin ellipse): cells there hold more nodes than the
target. The queries stay exact; only their cost grows.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit

#: target nodes per cell when the tree has grown to the next rebuild size (on pythonrobotics
#: at 10⁶ iterations 16 is 25% faster than 4 and as fast as 32 or 64; 1.5 is 2x slower)
NODES_PER_CELL = 16.0
#: the grid is rebuilt when the tree has grown by this factor since the last build
REBUILD_GROWTH = 2
#: free slots every cell's block gets beyond its share of the expected growth
BLOCK_SLACK = 2

#: node indices in the blocks are int32 (a slot is 28 bytes, not 32: at 10⁶
#: nodes a query costs the memory it reads); a tree that large would need
#: some 600 GB
MAX_NODES = 2**31 - 1

# Float parameter slots of a grid.
G_X0, G_Y0, G_H, G_INV_H, G_MARGIN = range(5)
N_GPARAMS = 5
# Integer slots: cells along x and y, coarse cells along x and y.
D_NX, D_NY, D_CX, D_CY = range(4)
#: a coarse cell is COARSE × COARSE cells; its node count lets the nearest
#: query skip empty regions (a sample deep inside an obstacle) in steps
COARSE = 8
# Per-cell bookkeeping columns: first slot of the block, next free slot, overflow list head.
M_START, M_FILL, M_HEAD = range(3)


class BucketGrid:
    """The arrays of a bucket grid over a tree's nodes, rebuilt by
    :meth:`rebuild`; :attr:`arrays` is what the compiled queries take.

    Parameters
    ----------
    bounds : Bounds
        The area the cells cover (nodes outside it go to the border cells).
    """

    def __init__(self, bounds) -> None:
        self.bounds = bounds
        self.built_at = 0
        self.arrays = _empty_arrays(bounds)

    def rebuild(self, xy: np.ndarray, cost: np.ndarray, next_node: np.ndarray, slot: np.ndarray, n: int,
                expected: int) -> None:
        """Index nodes 0..n-1 with cells and blocks sized for ``expected`` nodes."""
        h, nx, ny = grid_shape(self.bounds, expected)
        gparams = grid_params(self.bounds, h)
        dims = np.array([nx, ny, -(-nx // COARSE), -(-ny // COARSE)], dtype=np.int64)
        meta, block, block_id, coarse = _build(xy, cost, next_node, slot, n, expected / max(n, 1), gparams, dims)
        self.arrays = (meta, block, block_id, next_node, slot, gparams, dims, coarse)
        self.built_at = n

    def with_nodes(self, next_node: np.ndarray, slot: np.ndarray) -> tuple:
        """The arrays with the tree's per-node arrays (reallocated when the
        tree grows) for the overflow links and the block slot of each node."""
        self.arrays = self.arrays[:3] + (next_node, slot) + self.arrays[5:]
        return self.arrays


def _empty_arrays(bounds) -> tuple:
    meta = np.zeros((2, 3), dtype=np.int64)
    meta[:, M_HEAD] = -1
    return (meta, np.empty((0, 3)), np.empty(0, dtype=np.int32), np.full(0, -1, dtype=np.int64),
            np.full(0, -1, dtype=np.int64),
            grid_params(bounds, max(bounds.xmax - bounds.xmin, bounds.ymax - bounds.ymin, 1e-300)),
            np.ones(4, dtype=np.int64), np.zeros(1, dtype=np.int64))


def grid_shape(bounds, nodes_expected: int):
    """Cell side and cell counts (nx, ny) for ``nodes_expected`` nodes spread
    over ``bounds`` at ``NODES_PER_CELL`` per cell."""
    width, height = bounds.xmax - bounds.xmin, bounds.ymax - bounds.ymin
    h = math.sqrt(width * height * NODES_PER_CELL / max(nodes_expected, 1))
    h = max(h, 1e-9 * max(width, height, 1e-300))
    nx = max(1, min(int(math.ceil(width / h)), 1 << 15))
    ny = max(1, min(int(math.ceil(height / h)), 1 << 15))
    # Clamping the counts may leave the cells short of the bounds: widen them.
    h = max(h, width / nx, height / ny)
    return h, nx, ny


def grid_params(bounds, h: float) -> np.ndarray:
    g = np.zeros(N_GPARAMS)
    g[G_X0], g[G_Y0] = bounds.xmin, bounds.ymin
    g[G_H], g[G_INV_H] = h, 1.0 / h
    # Far above the rounding of a cell index or a squared distance at these magnitudes.
    scale = abs(bounds.xmin) + abs(bounds.ymin) + (bounds.xmax - bounds.xmin) + (bounds.ymax - bounds.ymin)
    g[G_MARGIN] = 1e-9 * (scale + h)
    return g


@njit(cache=True, inline="always")
def _cell_index(v, v0, inv_h, n):
    # Clamp before converting: a far-away coordinate must not overflow int64.
    c = (v - v0) * inv_h
    if c >= n - 1:
        return n - 1
    if not c >= 0.0:
        return 0
    return int(c)


@njit(cache=True, inline="always")
def _cell(x, y, gparams, dims):
    return (_cell_index(y, gparams[G_Y0], gparams[G_INV_H], dims[D_NY]) * dims[D_NX]
            + _cell_index(x, gparams[G_X0], gparams[G_INV_H], dims[D_NX]))


@njit(cache=True)
def _build(xy, cost, next_node, slot, n, growth, gparams, dims):
    """The bookkeeping, blocks and coarse counts of a grid over nodes 0..n-1, each cell's block sized for
    its nodes times ``growth`` (the expected nodes over n) plus ``BLOCK_SLACK``. One compiled entry point, not
    one per step: a fresh process loads each entry point from numba's cache apart (index, unpickling, linking,
    ~5 ms each at load 1), and a planning command builds a grid before its first query."""
    cells = np.empty(n, dtype=np.int64)
    counts = np.zeros(dims[D_NX] * dims[D_NY], dtype=np.int64)
    for k in range(n):
        cells[k] = _cell(xy[k, 0], xy[k, 1], gparams, dims)
        counts[cells[k]] += 1
    meta = np.empty((len(counts) + 1, 3), dtype=np.int64)  # one spare row: the end of the last block
    meta[0, M_START] = 0
    for c in range(len(counts)):
        meta[c + 1, M_START] = meta[c, M_START] + np.int64(math.ceil(counts[c] * growth)) + BLOCK_SLACK
    meta[:, M_FILL] = meta[:, M_START]
    meta[:, M_HEAD] = -1
    total = meta[-1, M_START]
    # Slots past a block's fill are never read, so never written before use.
    grid = (meta, np.empty((total, 3)), np.empty(total, dtype=np.int32), next_node, slot, gparams, dims,
            np.zeros(dims[D_CX] * dims[D_CY], dtype=np.int64))
    for k in range(n):
        _put(k, xy[k, 0], xy[k, 1], cost[k], cells[k], grid)
    return grid[0], grid[1], grid[2], grid[7]


@njit(cache=True, inline="always")
def _put(k, x, y, c, cell, grid):
    meta, block, block_id, next_node, slot, gparams, dims, coarse = grid
    nx = dims[D_NX]
    coarse[(cell // nx) // COARSE * dims[D_CX] + (cell % nx) // COARSE] += 1
    s = meta[cell, M_FILL]
    if s < meta[cell + 1, M_START]:
        block[s, 0] = x
        block[s, 1] = y
        block[s, 2] = c
        block_id[s] = k
        slot[k] = s
        meta[cell, M_FILL] = s + 1
    else:
        slot[k] = -1
        next_node[k] = meta[cell, M_HEAD]
        meta[cell, M_HEAD] = k


@njit(cache=True)
def insert(k, xy, cost, grid):
    """Add node k to its cell."""
    gparams, dims = grid[5], grid[6]
    _put(k, xy[k, 0], xy[k, 1], cost[k], _cell(xy[k, 0], xy[k, 1], gparams, dims), grid)


@njit(cache=True, inline="always")
def set_cost(k, value, block, slot):
    """Keep the block's copy of node k's cost (the tree's ``cost[k]``)
    current; ``block`` and ``slot`` are the grid's arrays 1 and 4, taken out
    of the grid's tuple once by the caller (taking them out per node costs a
    reference-count update per array, more than the write)."""
    s = slot[k]
    if s >= 0:
        block[s, 2] = value


@njit(cache=True, inline="always")
def _nearest_in_cell(qx, qy, xy, cost, cell, meta, block, block_id, next_node, best, best_d2, bx, by, bc):
    for s in range(meta[cell, M_START], meta[cell, M_FILL]):
        dx = block[s, 0] - qx
        dy = block[s, 1] - qy
        d2 = dx * dx + dy * dy
        if d2 < best_d2 or (d2 == best_d2 and block_id[s] < best):
            best_d2 = d2
            best = block_id[s]
            bx, by, bc = block[s, 0], block[s, 1], block[s, 2]
    u = meta[cell, M_HEAD]
    while u >= 0:
        dx = xy[u, 0] - qx
        dy = xy[u, 1] - qy
        d2 = dx * dx + dy * dy
        if d2 < best_d2 or (d2 == best_d2 and u < best):
            best_d2 = d2
            best = u
            bx, by, bc = xy[u, 0], xy[u, 1], cost[u]
        u = next_node[u]
    return best, best_d2, bx, by, bc


@njit(cache=True, inline="always")
def _gap(v, k, n, v0, h, margin):
    """Distance from coordinate v to cell k's extent along one axis, less the
    margin (never below 0): a lower bound. Border cells reach to infinity."""
    g = 0.0
    if k > 0 and v < v0 + k * h:
        g = v0 + k * h - v
    elif k < n - 1 and v > v0 + (k + 1) * h:
        g = v - (v0 + (k + 1) * h)
    return max(g - margin, 0.0)


@njit(cache=True, inline="always")
def _chord(v, g, rho, lo, hi, v0, inv_h, n, margin):
    """The cells lo..hi along a row (or column) at gap g from the query, cut
    to the chord of the disc of radius rho (inf: no cut) across it."""
    if rho < np.inf:
        half = math.sqrt(max(rho * rho - g * g, 0.0)) + margin
        lo = max(lo, _cell_index(v - half, v0, inv_h, n))
        hi = min(hi, _cell_index(v + half, v0, inv_h, n))
    return lo, hi


@njit(cache=True)
def _first_ring(cx, cy, dims, coarse):
    """A ring of cells around (cx, cy) inside which every cell is empty:
    the coarse cells around the query's are searched ring by ring for a
    node, and cells within COARSE · (R - 1) of (cx, cy) lie in coarse cells
    nearer than the first non-empty coarse ring R."""
    ncx, ncy = dims[D_CX], dims[D_CY]
    kx, ky = cx // COARSE, cy // COARSE
    big = 0
    while True:
        for j in range(max(ky - big, 0), min(ky + big, ncy - 1) + 1):
            step = 1 if (j == ky - big or j == ky + big) else 2 * big
            for i in range(kx - big, kx + big + 1, max(step, 1)):
                if 0 <= i < ncx and coarse[j * ncx + i] > 0:
                    return 0 if big == 0 else COARSE * (big - 1) + 1
        if kx - big <= 0 and ky - big <= 0 and kx + big >= ncx - 1 and ky + big >= ncy - 1:
            return 0  # no node at all: the plain search finds none either
        big += 1


@njit(cache=True)
def node_within(qx, qy, reach, grid):
    """Whether a node provably lies within ``reach`` of (qx, qy): some coarse
    cell holding a node lies wholly within that distance. False proves
    nothing. Rings of coarse cells are searched outwards, as far as a ring
    can still lie within reach. Assumes every node lies inside the bounds
    (the tree's do: an edge check refuses any point outside them); a node
    outside would count as lying in its border cell."""
    dims, coarse, gparams = grid[6], grid[7], grid[5]
    ncx, ncy = dims[D_CX], dims[D_CY]
    x0, y0, h, margin = gparams[G_X0], gparams[G_Y0], gparams[G_H], gparams[G_MARGIN]
    side = COARSE * h
    nx, ny = dims[D_NX], dims[D_NY]
    kx = _cell_index(qx, x0, gparams[G_INV_H], nx) // COARSE
    ky = _cell_index(qy, y0, gparams[G_INV_H], ny) // COARSE
    big = 0
    # A cell of ring `big` reaches at least big · side from the query.
    while big * side <= reach:
        for j in range(max(ky - big, 0), min(ky + big, ncy - 1) + 1):
            step = 1 if (j == ky - big or j == ky + big) else 2 * big
            for i in range(kx - big, kx + big + 1, max(step, 1)):
                if 0 <= i < ncx and coarse[j * ncx + i] > 0:
                    # Nodes of this coarse cell lie within its cells' extent
                    # (the tree's nodes are inside the bounds the cells cover).
                    ax, bx = x0 + i * side, x0 + min((i + 1) * COARSE, nx) * h
                    ay, by = y0 + j * side, y0 + min((j + 1) * COARSE, ny) * h
                    fx = max(abs(qx - ax), abs(qx - bx))
                    fy = max(abs(qy - ay), abs(qy - by))
                    if math.sqrt(fx * fx + fy * fy) + margin <= reach:
                        return True
        if kx - big <= 0 and ky - big <= 0 and kx + big >= ncx - 1 and ky + big >= ncy - 1:
            return False
        big += 1
    return False


@njit(cache=True, inline="always")
def _coarse_empty(i, j, dims, coarse):
    return coarse[(j // COARSE) * dims[D_CX] + i // COARSE] == 0


@njit(cache=True, inline="always")
def _nearest_along(line, a, b, along_x, qx, qy, xy, cost, grid, best, best_d2, bx, by, bc):
    """The nearest-node search over cells a..b of one row (``along_x``, the
    row ``line``) or one column, stepping over runs in empty coarse cells."""
    meta, block, block_id, next_node, slot, gparams, dims, coarse = grid
    nx = dims[D_NX]
    t = a
    while t <= b:
        i, j = (t, line) if along_x else (line, t)
        if _coarse_empty(i, j, dims, coarse):
            t = (t // COARSE + 1) * COARSE
            continue
        best, best_d2, bx, by, bc = _nearest_in_cell(qx, qy, xy, cost, j * nx + i, meta, block, block_id,
                                                     next_node, best, best_d2, bx, by, bc)
        t += 1
    return best, best_d2, bx, by, bc


@njit(cache=True)
def nearest(qx, qy, xy, cost, grid):
    """Index, squared distance, position and cost of the node nearest to
    (qx, qy); the lowest index among equally near nodes, as a forward linear
    scan returns. Position and cost come from the cell's block, sparing the
    loop a read at a random place in the tree's arrays.

    Rings of cells around the query's cell are visited outwards until the
    distance to the unvisited rings provably exceeds the best distance found.
    Inside a ring, only the cells the disc of that best distance can reach
    are read, and runs of cells in empty coarse cells are stepped over; the
    search starts at the first ring that can hold a node.
    """
    meta, block, block_id, next_node, slot, gparams, dims, coarse = grid
    nx, ny = dims[D_NX], dims[D_NY]
    x0, y0, h, inv_h, margin = gparams[G_X0], gparams[G_Y0], gparams[G_H], gparams[G_INV_H], gparams[G_MARGIN]
    cx = _cell_index(qx, x0, inv_h, nx)
    cy = _cell_index(qy, y0, inv_h, ny)
    best = -1
    best_d2 = np.inf
    bx, by, bc = np.nan, np.nan, np.nan
    r = _first_ring(cx, cy, dims, coarse)
    while True:
        ilo, ihi, jlo, jhi = cx - r, cx + r, cy - r, cy + r
        # The ring's bottom and top rows, all their cells the disc reaches.
        for t in range(2 if r > 0 else 1):
            j = jlo if t == 0 else jhi
            if 0 <= j < ny:
                rho = math.sqrt(best_d2) + margin
                g = _gap(qy, j, ny, y0, h, margin)
                if g <= rho:
                    a, b = _chord(qx, g, rho, max(ilo, 0), min(ihi, nx - 1), x0, inv_h, nx, margin)
                    best, best_d2, bx, by, bc = _nearest_along(j, a, b, True, qx, qy, xy, cost, grid,
                                                               best, best_d2, bx, by, bc)
        # Its left and right columns between them.
        if r > 0:
            for i in (ilo, ihi):
                if 0 <= i < nx:
                    rho = math.sqrt(best_d2) + margin
                    g = _gap(qx, i, nx, x0, h, margin)
                    if g <= rho:
                        a, b = _chord(qy, g, rho, max(jlo + 1, 0), min(jhi - 1, ny - 1), y0, inv_h, ny, margin)
                        best, best_d2, bx, by, bc = _nearest_along(i, a, b, False, qx, qy, xy, cost, grid,
                                                                   best, best_d2, bx, by, bc)
        if ilo <= 0 and jlo <= 0 and ihi >= nx - 1 and jhi >= ny - 1:
            return best, best_d2, bx, by, bc
        # Every unvisited cell lies beyond one of the visited block's inner edges.
        lb = np.inf
        if ilo > 0:
            lb = min(lb, qx - (x0 + ilo * h))
        if ihi < nx - 1:
            lb = min(lb, x0 + (ihi + 1) * h - qx)
        if jlo > 0:
            lb = min(lb, qy - (y0 + jlo * h))
        if jhi < ny - 1:
            lb = min(lb, y0 + (jhi + 1) * h - qy)
        lb -= margin
        if best >= 0 and lb > 0.0 and lb * lb > best_d2:
            return best, best_d2, bx, by, bc
        r += 1


@njit(cache=True)
def near(qx, qy, r2, xy, cost, grid, out_idx, out_d2, out_cost, out_x, out_y):
    """Write the index, squared distance, cost and position of every node within
    squared distance r2 of (qx, qy) (``d2 <= r2``, as the scan tests it) into
    the ``out_*`` arrays, in no particular order; return how many.

    Each row of cells is cut to the disc's chord across that row, and each
    cell's block is read only as far as it is filled: at 10⁶ nodes the query
    costs the memory it reads.
    """
    meta, block, block_id, next_node, slot, gparams, dims, coarse = grid
    nx, ny = dims[D_NX], dims[D_NY]
    x0, y0, h, inv_h, margin = gparams[G_X0], gparams[G_Y0], gparams[G_H], gparams[G_INV_H], gparams[G_MARGIN]
    r = math.sqrt(r2) + margin
    jlo = _cell_index(qy - r, y0, inv_h, ny)
    jhi = _cell_index(qy + r, y0, inv_h, ny)
    m = 0
    for j in range(jlo, jhi + 1):
        # The row cut to the disc's chord (never shorter than the true one).
        g = _gap(qy, j, ny, y0, h, margin)
        if g > r:
            continue
        ilo, ihi = _chord(qx, g, r, 0, nx - 1, x0, inv_h, nx, margin)
        for c in range(j * nx + ilo, j * nx + ihi + 1):
            for s in range(meta[c, M_START], meta[c, M_FILL]):
                dx = block[s, 0] - qx
                dy2 = block[s, 1] - qy
                d2 = dx * dx + dy2 * dy2
                # Written whether inside or not, kept by counting it: no branch
                # to mispredict on the half of the slots the disc cuts through.
                out_idx[m] = block_id[s]
                out_d2[m] = d2
                out_cost[m] = block[s, 2]
                out_x[m] = block[s, 0]
                out_y[m] = block[s, 1]
                m += d2 <= r2
            u = meta[c, M_HEAD]
            while u >= 0:
                dx = xy[u, 0] - qx
                dy2 = xy[u, 1] - qy
                d2 = dx * dx + dy2 * dy2
                if d2 <= r2:
                    out_idx[m] = u
                    out_d2[m] = d2
                    out_cost[m] = cost[u]
                    out_x[m] = xy[u, 0]
                    out_y[m] = xy[u, 1]
                    m += 1
                u = next_node[u]
    return m
