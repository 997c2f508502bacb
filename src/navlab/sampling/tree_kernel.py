"""The compiled tree-growth loop shared by RRT, RRT* and growth-ratio RRT.

Python draws a batch of samples (any sampler), this loop consumes it: nearest
node, steer, exact edge check, and for RRT* choose-parent and rewire with cost
propagation. Two shortcuts give the same tree with less memory traffic:

- a sample in collision is rejected before any search when a node provably
  lies within the step (the new node would be the sample itself, since a
  step to a sample within reach lands on it exactly);
- RRT* asks the grid for the sample's near set first: when not empty it
  holds the nearest node, and it is the new node's near set as well.

The point check of each sample (not made by growth-ratio RRT) is counted with
the collision checks.

State lives in arrays owned by :class:`Tree`, which Python grows between
batches so that a batch always fits: with a time budget by doubling (memory
follows the tree actually grown, not ``max_iter``), without one allocated
once for ``max_iter + 1`` nodes and written as the tree grows. A batch boundary changes nothing: the
same seed gives the same tree bit for bit whatever the batch size.

Nearest-neighbour and near-set queries go through a uniform bucket grid
(:mod:`.bucket_grid`, which says why that structure) or, with
``use_grid=False``, through the brute-force scan over the node array. Both
return the same nodes (in different orders, which nothing depends on), so both grow the same tree; the scan
stays as the reference the tests compare the grid against.

The best-cost trace is stored as change points (iteration, new best cost),
one per improvement, and expanded to one value per iteration only for the
result (:meth:`Tree.cost_trace`).
"""

from __future__ import annotations

import math

import numpy as np

from ..arrays import grown
from ..jit import njit
from ..world.geometry import segment_free
from . import bucket_grid as G

MODE_RRT, MODE_RRT_STAR, MODE_GROWTH = 0, 1, 2

# Integer state slots.
S_NODES, S_EDGE_CHECKS, S_GOALS, S_FIRST_ITER, S_DONE, S_IN, S_OUT, S_REWIRES, S_BEST, S_TRACE, S_POINT_CHECKS = \
    range(11)
N_ISTATE = 11
# Float parameter slots.
P_STEP, P_GAMMA, P_GX, P_GY, P_GTOL, P_CONNECT, P_CAP, P_SX, P_SY = range(9)
N_FPARAMS = 9

#: nodes the arrays hold at first (they double when needed)
INITIAL_CAPACITY = 1024


class Tree:
    """Arrays of a search tree, grown by doubling as the tree grows (or, with
    ``reserve_all``, allocated once and written as the tree grows).

    Parameters
    ----------
    start : (2,) array_like
        The root.
    bounds : Bounds
        The world's bounds (the bucket grid covers them).
    max_nodes : int
        Nodes the tree can ever hold (``max_iter + 1``); the arrays never grow
        beyond it, and start at ``min(max_nodes, INITIAL_CAPACITY)`` (all of
        them with ``reserve_all``).
    use_grid : bool
        Answer nearest / near-set queries with the bucket grid (else by scan).
    reserve_all : bool
        Allocate ``max_nodes`` rows at once, for a caller that has checked
        they fit. They are address space until the tree reaches them, so the
        kernel zeroes each page once, where doubling zeroes and copies every
        row about twice (at 10⁶ nodes, about 3% of the time).
    """

    #: The fields the loop touches together for one node share one 64-byte
    #: record, aligned to a cache line (a row of one int64 array; the float
    #: fields are columns of its float64 view): rewiring walks subtrees in
    #: random index order, and at 10⁶ nodes every separate array, or a record
    #: straddling two lines, costs its own cache miss per node visited.
    _FLOAT_FIELDS = (("xy", slice(0, 2)), ("cost", 2))
    _INT_FIELDS = (("parent", 3), ("child", 4), ("sibling", 5), ("goal_slot", 6), ("grid_slot", 7))
    _RECORD_WIDTH = 8
    #: other per-node arrays whose contents are kept, and their fill value
    _NODE_ARRAYS = (("goal_node", -1), ("goal_extra", 0.0), ("next_in_cell", -1))
    #: per-node work space of one iteration: never read before written, so
    #: neither filled nor copied when the tree grows (its pages stay untouched
    #: until a large near set or subtree needs them)
    _SCRATCH = (("scratch_idx", np.int64), ("scratch_val", np.float64), ("scratch_dist", np.float64),
                ("scratch_cost", np.float64), ("scratch_x", np.float64), ("scratch_y", np.float64),
                ("scratch_state", np.int8), ("scratch_cand", np.int64),
                ("scratch_queue", np.int64))
    _DTYPES = {"goal_node": np.int64, "next_in_cell": np.int64}

    def __init__(self, start, bounds, max_nodes: int, use_grid: bool = True, reserve_all: bool = False) -> None:
        self.bounds = bounds
        self.max_nodes = int(max_nodes)
        self.use_grid = bool(use_grid)
        self.capacity = 0  # rows initialised
        self.reserved = 0  # rows allocated
        self.first_rows = self.max_nodes if reserve_all else min(INITIAL_CAPACITY, self.max_nodes)
        if self.first_rows > G.MAX_NODES:
            raise MemoryError(f"the tree would grow past {G.MAX_NODES} nodes, the most its index holds; "
                              "give max_iter or max_time a smaller value")
        self._set_record(_aligned_records(0, self._RECORD_WIDTH))
        for name, fill in self._NODE_ARRAYS:
            setattr(self, name, np.full(0, fill, dtype=self._DTYPES.get(name, np.float64)))
        for name, dtype in self._SCRATCH:
            setattr(self, name, np.empty(0, dtype=dtype))
        self.trace_iter = np.zeros(0, dtype=np.int64)
        self.trace_cost = np.zeros(0)
        self.istate = np.zeros(N_ISTATE, dtype=np.int64)
        self.istate[S_FIRST_ITER] = -1
        self.istate[S_BEST] = -1
        self.best_cost = np.full(1, np.inf)
        # Built at the first reserve() that has nodes to index, then at every doubling.
        self.grid = G.BucketGrid(bounds)
        self.reserve(1, 0)
        self.xy[0] = start
        self.istate[S_NODES] = 1

    def _set_record(self, record: np.ndarray) -> None:
        self.record = record
        floats = record.view(np.float64)
        for field, column in self._FLOAT_FIELDS:
            setattr(self, field, floats[:, column])
        for field, column in self._INT_FIELDS:
            setattr(self, field, record[:, column])

    def _reallocate(self, rows: int) -> None:
        """New arrays of ``rows`` rows holding the initialised rows of the old."""
        keep = self.capacity
        record = _aligned_records(rows, self._RECORD_WIDTH)
        record[:keep] = self.record[:keep]
        self._set_record(record)
        for name, fill in self._NODE_ARRAYS:
            array = np.empty(rows, dtype=self._DTYPES.get(name, np.float64))
            array[:keep] = getattr(self, name)[:keep]
            setattr(self, name, array)
        for name, dtype in self._SCRATCH:
            setattr(self, name, np.empty(rows, dtype=dtype))
        self.reserved = rows

    def _initialise(self, first: int, stop: int) -> None:
        first_int = self._INT_FIELDS[0][1]
        self.record[first:stop, :first_int] = 0  # 0.0 in the float fields
        self.record[first:stop, first_int:] = -1
        for name, fill in self._NODE_ARRAYS:
            getattr(self, name)[first:stop] = fill

    @property
    def size(self) -> int:
        return int(self.istate[S_NODES])

    @classmethod
    def bytes_per_node(cls) -> int:
        """Bytes one node costs in the arrays, counted twice (a doubling
        copies them; a tree reserved whole needs about half, so this errs
        on the safe side) plus the bucket grid's and the trace's share."""
        arrays = sum(np.dtype(cls._DTYPES.get(name, np.float64)).itemsize for name, _ in cls._NODE_ARRAYS)
        scratch = sum(np.dtype(dtype).itemsize for _, dtype in cls._SCRATCH)
        return 2 * (8 * cls._RECORD_WIDTH + arrays + scratch) + 32

    def reserve(self, new_nodes: int, new_iterations: int) -> None:
        """Make room for ``new_nodes`` more nodes and ``new_iterations`` more
        trace entries, and rebuild the grid if the tree doubled."""
        n = int(self.istate[S_NODES])
        need = min(n + new_nodes, self.max_nodes)
        if need > G.MAX_NODES:
            raise MemoryError(f"the tree would grow past {G.MAX_NODES} nodes, the most its index holds; "
                              "give max_iter or max_time a smaller value")
        reallocated = need > self.reserved
        if reallocated:
            self._reallocate(min(max(2 * self.reserved, need, self.first_rows), self.max_nodes))
        if need > self.capacity:
            cap = min(max(2 * self.capacity, need, min(INITIAL_CAPACITY, self.max_nodes)), self.reserved)
            self._initialise(self.capacity, cap)
            self.capacity = cap
        t = int(self.istate[S_TRACE])
        if t + new_iterations > len(self.trace_iter):
            cap = max(2 * len(self.trace_iter), t + new_iterations, 64)
            self.trace_iter = grown(self.trace_iter[:t], cap)
            self.trace_cost = grown(self.trace_cost[:t], cap)
        if self.use_grid and n > 0:
            if n >= G.REBUILD_GROWTH * self.grid.built_at:
                self.grid.rebuild(self.xy, self.cost, self.next_in_cell, self.grid_slot, n,
                                  min(G.REBUILD_GROWTH * n, self.max_nodes))
            elif reallocated:  # the grid links the tree's per-node arrays: give it the new ones
                self.grid.with_nodes(self.next_in_cell, self.grid_slot)

    def record_cost(self, iteration: int) -> None:
        """Note the current best cost as reached at ``iteration``."""
        self.reserve(0, 1)
        _record_cost(iteration, self.best_cost[0], self.trace_iter, self.trace_cost, self.istate)

    def cost_trace(self, iterations: int) -> np.ndarray:
        """Best cost after each of the first ``iterations`` iterations."""
        t = int(self.istate[S_TRACE])
        its = self.trace_iter[:t]
        keep = its < iterations
        its, vals = its[keep], self.trace_cost[:t][keep]
        lengths = np.diff(np.append(its, iterations))
        head = np.full(int(its[0]) if len(its) else iterations, np.inf)
        return np.concatenate((head, np.repeat(vals, lengths)))

    def grow(self, samples: np.ndarray, it0: int, geom, fparams: np.ndarray, mode: int) -> int:
        """Consume ``samples`` as iterations ``it0, it0 + 1, ...`` (see :func:`grow`)."""
        self.reserve(len(samples), len(samples))
        return grow(samples, it0, geom, self.xy, self.parent, self.cost, self.child, self.sibling,
                    self.goal_node, self.goal_extra, self.goal_slot, self.trace_iter, self.trace_cost, self.istate,
                    self.best_cost, fparams, mode, self.scratch_idx, self.scratch_val, self.scratch_dist,
                    self.scratch_cost, self.scratch_x, self.scratch_y, self.scratch_state, self.scratch_cand,
                    self.scratch_queue, self.use_grid, self.grid.arrays)

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


def _aligned_records(rows: int, width: int) -> np.ndarray:
    """An uninitialised C-contiguous ``(rows, width)`` int64 array whose rows
    start on 64-byte boundaries (numpy aligns only to 16 bytes)."""
    line = 64 // 8
    flat = np.empty(rows * width + line, dtype=np.int64)
    skip = (-flat.ctypes.data % 64) // 8
    return flat[skip: skip + rows * width].reshape(rows, width)


@njit(cache=True)
def _record_cost(it, value, trace_iter, trace_cost, istate):
    t = istate[S_TRACE]
    if t > 0 and trace_iter[t - 1] == it:
        trace_cost[t - 1] = value
        return
    if t > 0 and trace_cost[t - 1] == value:
        return
    trace_iter[t] = it
    trace_cost[t] = value
    istate[S_TRACE] = t + 1


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
def _shift_subtree(child, sibling, cost, root, delta, queue, goal_slot, goal_extra, istate, best_cost,
                   use_grid, grid):
    """Add delta (< 0) to the cost of root's subtree; goal candidates in it
    are offered as the new best (costs only fall, so no other can become it)."""
    block, slot = grid[1], grid[4]
    # Breadth first over the first-child / next-sibling links: a queue of
    # known nodes, so consecutive visits do not wait on each other's cache
    # misses (a stack walking each sibling chain would, one miss at a time).
    queue[0] = root
    head, tail = 0, 1
    while head < tail:
        u = queue[head]
        head += 1
        cost[u] += delta
        if use_grid:
            G.set_cost(u, cost[u], block, slot)
        if goal_slot[u] >= 0:
            _offer_goal(goal_slot[u], cost[u] + goal_extra[goal_slot[u]], istate, best_cost)
        c = child[u]
        if c >= 0:
            queue[tail] = c
            tail += 1
        s = sibling[u]
        if s >= 0 and u != root:
            queue[tail] = s
            tail += 1


@njit(cache=True, inline="always")
def _offer_goal(g, value, istate, best_cost):
    """Keep (best cost, goal index) the lexicographic minimum over the goal
    candidates, as a forward scan with a strict ``<`` finds it."""
    if value < best_cost[0] or (value == best_cost[0] and g < istate[S_BEST]):
        best_cost[0] = value
        istate[S_BEST] = g


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
def add_goal_candidate(k, geom, xy, goal_node, goal_extra, goal_slot, istate, fparams, mode):
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
    goal_slot[k] = g
    istate[S_GOALS] = g + 1
    return True


@njit(cache=True, inline="always")
def _before(a, b, val, idx, by_cost):
    """Whether candidate a comes first: by ``val`` (when ``by_cost``), then
    by node index (distinct, so the order is total and any correct ordering
    gives the same sequence)."""
    if by_cost and val[a] != val[b]:
        return val[a] < val[b]
    return idx[a] < idx[b]


@njit(cache=True, inline="always")
def _sift_down(heap, root, m, val, idx, by_cost):
    while True:
        first = 2 * root + 1
        if first >= m:
            return
        if first + 1 < m and _before(heap[first + 1], heap[first], val, idx, by_cost):
            first += 1
        if not _before(heap[first], heap[root], val, idx, by_cost):
            return
        heap[root], heap[first] = heap[first], heap[root]
        root = first


@njit(cache=True, inline="always")
def _heap_build(heap, m, val, idx, by_cost):
    """Order ``heap[:m]`` (positions into ``val``/``idx``) as a binary heap,
    the first candidate at the top: cheapest by ``val`` then lowest index
    when ``by_cost``, else lowest index."""
    for root in range(m // 2 - 1, -1, -1):
        _sift_down(heap, root, m, val, idx, by_cost)


@njit(cache=True, inline="always")
def _heap_pop(heap, m, val, idx, by_cost):
    """Take the first of the ``m`` candidates off the heap (``m - 1`` remain)."""
    top = heap[0]
    heap[0] = heap[m - 1]
    _sift_down(heap, 0, m - 1, val, idx, by_cost)
    return top


@njit(cache=True, inline="always")
def _near_r2(n, gamma, step_max):
    """The squared RRT* near radius with n nodes in the tree."""
    radius = min(gamma * math.sqrt(math.log(n + 1) / (n + 1)), step_max)
    return radius * radius


@njit(cache=True, inline="always")
def _nearest_of(m, d2, idx):
    """Position of the nearest of m found nodes (lowest index on a tie)."""
    best = 0
    for o in range(1, m):
        if d2[o] < d2[best] or (d2[o] == d2[best] and idx[o] < idx[best]):
            best = o
    return best


@njit(cache=True)
def _nearest_scan(qx, qy, xy, cost, n):
    nearest = 0
    best_d2 = np.inf
    for j in range(n):
        dx = xy[j, 0] - qx
        dy = xy[j, 1] - qy
        d2 = dx * dx + dy * dy
        if d2 < best_d2:
            best_d2 = d2
            nearest = j
    return nearest, best_d2, xy[nearest, 0], xy[nearest, 1], cost[nearest]


@njit(cache=True)
def _near_scan(qx, qy, r2, xy, cost, n, out_idx, out_d2, out_cost, out_x, out_y):
    m = 0
    for j in range(n):
        dx = xy[j, 0] - qx
        dy = xy[j, 1] - qy
        d2 = dx * dx + dy * dy
        if d2 <= r2:
            out_idx[m] = j
            out_d2[m] = d2
            out_cost[m] = cost[j]
            out_x[m] = xy[j, 0]
            out_y[m] = xy[j, 1]
            m += 1
    return m


@njit(cache=True)
def grow(samples, it0, geom, xy, parent, cost, child, sibling, goal_node, goal_extra,
         goal_slot, trace_iter, trace_cost, istate, best_cost, fparams, mode, near_idx, near_val, near_dist,
         near_cost, near_x, near_y, near_state, cand, queue, use_grid, grid):
    """Consume ``samples`` as iterations ``it0, it0 + 1, ...``.

    The arrays must have room for one node and one trace entry per sample.
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
        # A sample in collision with a node within the step becomes the new
        # node itself, so the iteration adds nothing: know that before the
        # nearest search, which is costliest for such samples (deep inside an
        # obstacle, far from every node). The bucket grid's coarse counts
        # often prove a node within reach; otherwise the search decides.
        blocked = False
        if mode != MODE_GROWTH:
            istate[S_POINT_CHECKS] += 1
            blocked = not segment_free(qx, qy, qx, qy, geom)
            if blocked and use_grid and G.node_within(qx, qy, step_max, grid):
                continue
        # RRT* asks for the near set of the new node, which at all but the
        # first few hundred iterations is the sample itself; and the sample's
        # near set, when not empty, holds its nearest node. So the grid asks
        # the near query first and the nearest query only when it came back empty.
        near_at_sample = False
        n_near = 0
        if use_grid and mode == MODE_RRT_STAR and not blocked:
            n_near = G.near(qx, qy, _near_r2(n, gamma, step_max), xy, cost, grid, near_idx, near_dist, near_cost,
                            near_x, near_y)
            near_at_sample = True
        if n_near > 0:
            o = _nearest_of(n_near, near_dist, near_idx)
            nearest, best_d2, px, py, pc = near_idx[o], near_dist[o], near_x[o], near_y[o], near_cost[o]
        elif use_grid:
            nearest, best_d2, px, py, pc = G.nearest(qx, qy, xy, cost, grid)
        else:
            nearest, best_d2, px, py, pc = _nearest_scan(qx, qy, xy, cost, n)
        d = math.sqrt(best_d2)
        if d <= 1e-12 or (blocked and d <= step_max):
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
        if step == d:  # the sample itself, exactly
            nx, ny = qx, qy
        else:
            nx = px + (qx - px) / d * step
            ny = py + (qy - py) / d * step
        istate[S_EDGE_CHECKS] += 1
        if not segment_free(px, py, nx, ny, geom):
            continue
        k = n
        xy[k, 0] = nx
        xy[k, 1] = ny
        best_parent = nearest
        best_c = pc + step
        best_before = best_cost[0]
        if mode == MODE_RRT_STAR:
            # Grid and scan return the same set in different orders; nothing
            # below depends on the order (candidates are ranked explicitly).
            if not (near_at_sample and nx == qx and ny == qy):
                r2 = _near_r2(n, gamma, step_max)
                if use_grid:
                    n_near = G.near(nx, ny, r2, xy, cost, grid, near_idx, near_dist, near_cost, near_x, near_y)
                else:
                    n_near = _near_scan(nx, ny, r2, xy, cost, n, near_idx, near_dist, near_cost, near_x, near_y)
            m = 0
            for o in range(n_near):
                j = near_idx[o]
                near_dist[o] = math.sqrt(near_dist[o])  # it held the squared distance
                near_val[o] = near_cost[o] + near_dist[o]
                near_state[o] = 0  # edge not checked yet
                if near_val[o] < best_c and j != nearest:
                    cand[m] = o
                    m += 1
            # Choose parent: the candidates cheaper than through the nearest
            # node, cheapest first (lower index on a tie); the first free wins.
            # A heap, not a sort: usually the first candidate is free, and at
            # 10⁶ nodes there are a hundred of them.
            _heap_build(cand, m, near_val, near_idx, True)
            while m > 0:
                o = _heap_pop(cand, m, near_val, near_idx, True)
                m -= 1
                j = near_idx[o]
                istate[S_EDGE_CHECKS] += 1
                if segment_free(near_x[o], near_y[o], nx, ny, geom):
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
        if use_grid:
            G.insert(k, xy, cost, grid)
        if mode == MODE_RRT_STAR:
            # Rewire in ascending index order: rewiring a node lowers the cost
            # of its subtree, which may hold a later candidate. Costs only fall,
            # so the nodes that fail the test now fail it at their turn too.
            m = 0
            for o in range(n_near):
                j = near_idx[o]
                if j != best_parent and near_state[o] != 2 and best_c + near_dist[o] < near_cost[o] - 1e-12:
                    cand[m] = o
                    m += 1
            _heap_build(cand, m, near_val, near_idx, False)
            while m > 0:
                o = _heap_pop(cand, m, near_val, near_idx, False)
                m -= 1
                j = near_idx[o]
                new_c = best_c + near_dist[o]
                if new_c >= cost[j] - 1e-12:
                    continue
                if near_state[o] == 0 and j != nearest:
                    istate[S_EDGE_CHECKS] += 1
                    if not segment_free(nx, ny, near_x[o], near_y[o], geom):
                        continue
                _remove_child(child, sibling, parent[j], j)
                parent[j] = k
                sibling[j] = child[k]
                child[k] = j
                _shift_subtree(child, sibling, cost, j, new_c - cost[j], queue, goal_slot, goal_extra,
                               istate, best_cost, use_grid, grid)
                istate[S_REWIRES] += 1
        if add_goal_candidate(k, geom, xy, goal_node, goal_extra, goal_slot, istate, fparams, mode):
            g = istate[S_GOALS] - 1
            _offer_goal(g, cost[k] + goal_extra[g], istate, best_cost)
        if best_cost[0] != best_before:
            _record_cost(it, best_cost[0], trace_iter, trace_cost, istate)
            if istate[S_FIRST_ITER] < 0:
                istate[S_FIRST_ITER] = it
        if mode != MODE_RRT_STAR and istate[S_GOALS] > 0:
            istate[S_DONE] = 1
            return i + 1
    return samples.shape[0]
