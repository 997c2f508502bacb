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

- insertion is O(1) (push on the cell's singly linked list), so there are no
  batches of unindexed nodes and no rebalancing, unlike a k-d tree rebuilt in
  batches or OMPL's GNAT;
- both queries are exact by construction: the near query visits every cell
  the disc can touch; the nearest query visits rings of cells around the
  sample until the distance to the unvisited rings provably exceeds the best
  distance found (ties are broken by index, so the visiting order does not
  matter);
- its cost depends on the number of nodes per cell, which stays within a
  constant factor because the grid is rebuilt (O(n), amortised O(1) per node)
  each time the tree doubles, with cells sized for ``NODES_PER_CELL`` nodes
  at the size the tree will reach before the next rebuild.

Cells cover the world's bounds. A node or sample outside them falls into the
nearest border cell: border cells then extend to infinity outwards, which
keeps every distance bound below true (a node in a cell right of the visited
block is still right of the block's right edge). Distance bounds subtract a
margin far above floating-point rounding, so a node whose cell index rounded
the other way is never skipped.

Its weakness is a tree much denser in one part of the bounds than elsewhere
(informed sampling in a thin ellipse): cells there hold more nodes than the
target. The queries stay exact; only their cost grows.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: target nodes per cell when the tree has grown to the next rebuild size
NODES_PER_CELL = 4.0
#: the grid is rebuilt when the tree has grown by this factor since the last build
REBUILD_GROWTH = 2

# Float parameter slots of a grid.
G_X0, G_Y0, G_H, G_INV_H, G_MARGIN = range(5)
N_GPARAMS = 5


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


@njit(cache=True)
def insert(k, xy, head, next_node, gparams, nx, ny):
    """Push node k on its cell's list."""
    i = _cell_index(xy[k, 0], gparams[G_X0], gparams[G_INV_H], nx)
    j = _cell_index(xy[k, 1], gparams[G_Y0], gparams[G_INV_H], ny)
    c = j * nx + i
    next_node[k] = head[c]
    head[c] = k


@njit(cache=True)
def rebuild(n, xy, head, next_node, gparams, nx, ny):
    """Index nodes 0..n-1 afresh on a grid of nx × ny cells."""
    head[:] = -1
    for k in range(n):
        insert(k, xy, head, next_node, gparams, nx, ny)


@njit(cache=True, inline="always")
def _nearest_in_cell(qx, qy, xy, u, next_node, best, best_d2):
    while u >= 0:
        dx = xy[u, 0] - qx
        dy = xy[u, 1] - qy
        d2 = dx * dx + dy * dy
        if d2 < best_d2 or (d2 == best_d2 and u < best):
            best_d2 = d2
            best = u
        u = next_node[u]
    return best, best_d2


@njit(cache=True)
def nearest(qx, qy, xy, head, next_node, gparams, nx, ny):
    """Index and squared distance of the node nearest to (qx, qy); the lowest
    index among equally near nodes, as a forward linear scan returns."""
    x0, y0, h, inv_h, margin = gparams[G_X0], gparams[G_Y0], gparams[G_H], gparams[G_INV_H], gparams[G_MARGIN]
    cx = _cell_index(qx, x0, inv_h, nx)
    cy = _cell_index(qy, y0, inv_h, ny)
    best = -1
    best_d2 = np.inf
    r = 0
    while True:
        ilo, ihi, jlo, jhi = cx - r, cx + r, cy - r, cy + r
        for j in range(max(jlo, 0), min(jhi, ny - 1) + 1):
            if j == jlo or j == jhi:  # the ring's bottom and top rows: all their cells
                for i in range(max(ilo, 0), min(ihi, nx - 1) + 1):
                    best, best_d2 = _nearest_in_cell(qx, qy, xy, head[j * nx + i], next_node, best, best_d2)
            else:  # rows in between: only the ring's two end cells are new
                if ilo >= 0:
                    best, best_d2 = _nearest_in_cell(qx, qy, xy, head[j * nx + ilo], next_node, best, best_d2)
                if ihi <= nx - 1:
                    best, best_d2 = _nearest_in_cell(qx, qy, xy, head[j * nx + ihi], next_node, best, best_d2)
        if ilo <= 0 and jlo <= 0 and ihi >= nx - 1 and jhi >= ny - 1:
            return best, best_d2
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
            return best, best_d2
        r += 1


@njit(cache=True)
def near(qx, qy, r2, xy, head, next_node, gparams, nx, ny, out):
    """Write into ``out`` the indices of all nodes within squared distance r2
    of (qx, qy) (``d2 <= r2``, as the scan tests it), in no particular order;
    return how many."""
    x0, y0, inv_h, margin = gparams[G_X0], gparams[G_Y0], gparams[G_INV_H], gparams[G_MARGIN]
    r = math.sqrt(r2) + margin
    ilo = _cell_index(qx - r, x0, inv_h, nx)
    ihi = _cell_index(qx + r, x0, inv_h, nx)
    jlo = _cell_index(qy - r, y0, inv_h, ny)
    jhi = _cell_index(qy + r, y0, inv_h, ny)
    m = 0
    for j in range(jlo, jhi + 1):
        for i in range(ilo, ihi + 1):
            u = head[j * nx + i]
            while u >= 0:
                dx = xy[u, 0] - qx
                dy = xy[u, 1] - qy
                if dx * dx + dy * dy <= r2:
                    out[m] = u
                    m += 1
                u = next_node[u]
    return m
