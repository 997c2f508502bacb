"""The compiled tree-growth loop shared by RRT, RRT* and growth-ratio RRT.

Python draws a batch of samples (any sampler), this loop consumes it: nearest
node, steer, exact edge check, and for RRT* choose-parent and rewire with cost
propagation. All state lives in preallocated arrays owned by :class:`Tree`, so
a query never reallocates and a batch boundary changes nothing: the same seed
gives the same tree bit for bit whatever the batch size.

Nearest-neighbour and near-set queries are brute force over the node array.
For the trees this loop grows (≤ 10⁵ nodes) a compiled linear scan is cheaper
than maintaining a spatial index under rewiring.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..world.geometry import segment_free

MODE_RRT, MODE_RRT_STAR, MODE_GROWTH = 0, 1, 2

# Integer state slots.
S_NODES, S_EDGE_CHECKS, S_GOALS, S_FIRST_ITER, S_DONE, S_IN, S_OUT, S_REWIRES, S_BEST = range(9)
N_ISTATE = 9
# Float parameter slots.
P_STEP, P_GAMMA, P_GX, P_GY, P_GTOL, P_CONNECT, P_CAP, P_SX, P_SY = range(9)
N_FPARAMS = 9


class Tree:
    """Preallocated arrays of a search tree with ``capacity`` nodes."""

    def __init__(self, capacity: int, start, max_iter: int) -> None:
        self.xy = np.zeros((capacity, 2))
        self.parent = np.full(capacity, -1, dtype=np.int64)
        self.cost = np.zeros(capacity)
        self.child = np.full(capacity, -1, dtype=np.int64)
        self.sibling = np.full(capacity, -1, dtype=np.int64)
        self.goal_node = np.full(capacity, -1, dtype=np.int64)
        self.goal_extra = np.zeros(capacity)
        self.trace = np.full(max_iter, np.inf)
        self.istate = np.zeros(N_ISTATE, dtype=np.int64)
        self.istate[S_FIRST_ITER] = -1
        self.istate[S_BEST] = -1
        self.best_cost = np.full(1, np.inf)
        self.scratch_idx = np.zeros(capacity, dtype=np.int64)
        self.scratch_val = np.zeros(capacity)
        self.scratch_dist = np.zeros(capacity)
        self.scratch_state = np.zeros(capacity, dtype=np.int8)
        self.scratch_stack = np.zeros(capacity, dtype=np.int64)
        self.xy[0] = start
        self.istate[S_NODES] = 1

    @property
    def size(self) -> int:
        return int(self.istate[S_NODES])

    def nodes(self) -> np.ndarray:
        return self.xy[: self.size].copy()

    def parents(self) -> np.ndarray:
        return self.parent[: self.size].copy()

    def branch(self, node: int) -> np.ndarray:
        """Node positions from the root to ``node``."""
        out = []
        while node >= 0:
            out.append(self.xy[node])
            node = int(self.parent[node])
        return np.array(out[::-1])


@njit(cache=True)
def _remove_child(child, sibling, p, k):
    if child[p] == k:
        child[p] = sibling[k]
        return
    prev = child[p]
    while sibling[prev] != k:
        prev = sibling[prev]
    sibling[prev] = sibling[k]


@njit(cache=True)
def _shift_subtree(child, sibling, cost, root, delta, stack):
    top = 0
    stack[top] = root
    top += 1
    while top > 0:
        top -= 1
        u = stack[top]
        cost[u] += delta
        c = child[u]
        while c >= 0:
            stack[top] = c
            top += 1
            c = sibling[c]


@njit(cache=True)
def _refresh_best(cost, goal_node, goal_extra, istate, best_cost):
    best = np.inf
    arg = -1
    for g in range(istate[S_GOALS]):
        c = cost[goal_node[g]] + goal_extra[g]
        if c < best:
            best = c
            arg = g
    best_cost[0] = best
    istate[S_BEST] = arg


@njit(cache=True)
def growth_step(inside, n_in, n_out, d, cap):
    """Seed 003's step: the share of samples in the sample's own area (target
    rectangle or outside) times the parent–sample distance, optionally capped."""
    share = (n_in if inside else n_out) / (n_in + n_out)
    step = share * d
    if cap > 0.0:
        step = min(step, cap)
    return step


@njit(cache=True)
def add_goal_candidate(k, geom, xy, goal_node, goal_extra, istate, fparams, mode):
    """Record node k as reaching the goal if it does (returns True then)."""
    gx, gy = fparams[P_GX], fparams[P_GY]
    dg = math.hypot(gx - xy[k, 0], gy - xy[k, 1])
    extra = -1.0
    if mode == MODE_GROWTH:
        if dg < fparams[P_GTOL] or dg == 0.0:
            istate[S_EDGE_CHECKS] += 1
            extra = dg if segment_free(xy[k, 0], xy[k, 1], gx, gy, geom) else 0.0
    elif dg <= fparams[P_GTOL]:
        extra = 0.0
    elif dg <= fparams[P_CONNECT]:
        istate[S_EDGE_CHECKS] += 1
        if segment_free(xy[k, 0], xy[k, 1], gx, gy, geom):
            extra = dg
    if extra < 0.0:
        return False
    g = istate[S_GOALS]
    goal_node[g] = k
    goal_extra[g] = extra
    istate[S_GOALS] = g + 1
    return True


@njit(cache=True)
def grow(samples, it0, geom, xy, parent, cost, child, sibling, goal_node, goal_extra,
         trace, istate, best_cost, fparams, mode, near_idx, near_val, near_dist, near_state, stack):
    """Consume ``samples`` as iterations ``it0, it0 + 1, ...``.

    Returns the number of samples consumed (fewer than given when the tree
    stops: RRT and growth-ratio RRT at their first solution).
    """
    step_max = fparams[P_STEP]
    gamma = fparams[P_GAMMA]
    for i in range(samples.shape[0]):
        it = it0 + i
        qx = samples[i, 0]
        qy = samples[i, 1]
        n = istate[S_NODES]
        nearest = 0
        best_d2 = np.inf
        for j in range(n):
            dx = xy[j, 0] - qx
            dy = xy[j, 1] - qy
            d2 = dx * dx + dy * dy
            if d2 < best_d2:
                best_d2 = d2
                nearest = j
        d = math.sqrt(best_d2)
        trace[it] = best_cost[0]
        if d <= 1e-12:
            continue
        if mode == MODE_GROWTH:
            # Seed 003: step = (share of samples in this sample's area) · d_PR.
            inside = (min(fparams[P_SX], fparams[P_GX]) <= qx <= max(fparams[P_SX], fparams[P_GX])
                      and min(fparams[P_SY], fparams[P_GY]) <= qy <= max(fparams[P_SY], fparams[P_GY]))
            if inside:
                istate[S_IN] += 1
            else:
                istate[S_OUT] += 1
            step = growth_step(inside, istate[S_IN], istate[S_OUT], d, fparams[P_CAP])
        else:
            step = min(d, step_max)
        if step <= 1e-12:
            continue
        px = xy[nearest, 0]
        py = xy[nearest, 1]
        nx = px + (qx - px) / d * step
        ny = py + (qy - py) / d * step
        istate[S_EDGE_CHECKS] += 1
        if not segment_free(px, py, nx, ny, geom):
            continue
        k = n
        xy[k, 0] = nx
        xy[k, 1] = ny
        best_parent = nearest
        best_c = cost[nearest] + step
        n_near = 0
        rewired = False
        if mode == MODE_RRT_STAR:
            radius = min(gamma * math.sqrt(math.log(n + 1) / (n + 1)), step_max)
            r2 = radius * radius
            for j in range(n):
                dx = xy[j, 0] - nx
                dy = xy[j, 1] - ny
                d2 = dx * dx + dy * dy
                if d2 <= r2:
                    near_idx[n_near] = j
                    near_dist[n_near] = math.sqrt(d2)
                    near_val[n_near] = cost[j] + near_dist[n_near]
                    near_state[n_near] = 0  # edge not checked yet
                    n_near += 1
            # Choose parent: check candidates cheapest first, stop at the first free.
            order = np.argsort(near_val[:n_near])
            for o in order:
                j = near_idx[o]
                if near_val[o] >= best_c:
                    break
                if j == nearest:
                    continue
                istate[S_EDGE_CHECKS] += 1
                if segment_free(xy[j, 0], xy[j, 1], nx, ny, geom):
                    near_state[o] = 1
                    best_parent = j
                    best_c = near_val[o]
                    break
                near_state[o] = 2
        parent[k] = best_parent
        cost[k] = best_c
        sibling[k] = child[best_parent]
        child[best_parent] = k
        child[k] = -1
        istate[S_NODES] = n + 1
        if mode == MODE_RRT_STAR:
            for o in range(n_near):
                j = near_idx[o]
                if j == best_parent:
                    continue
                new_c = best_c + near_dist[o]
                if new_c >= cost[j] - 1e-12:
                    continue
                if near_state[o] == 2:
                    continue
                if near_state[o] == 0 and j != nearest:
                    istate[S_EDGE_CHECKS] += 1
                    if not segment_free(nx, ny, xy[j, 0], xy[j, 1], geom):
                        continue
                _remove_child(child, sibling, parent[j], j)
                parent[j] = k
                sibling[j] = child[k]
                child[k] = j
                _shift_subtree(child, sibling, cost, j, new_c - cost[j], stack)
                istate[S_REWIRES] += 1
                rewired = True
        found = add_goal_candidate(k, geom, xy, goal_node, goal_extra, istate, fparams, mode)
        if found or (rewired and istate[S_GOALS] > 0):
            _refresh_best(cost, goal_node, goal_extra, istate, best_cost)
            if istate[S_FIRST_ITER] < 0 and best_cost[0] < np.inf:
                istate[S_FIRST_ITER] = it
        trace[it] = best_cost[0]
        if mode != MODE_RRT_STAR and istate[S_GOALS] > 0:
            istate[S_DONE] = 1
            return i + 1
    return samples.shape[0]
