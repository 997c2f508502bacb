"""The compiled loop of RRT and RRT* in SE(2) with Dubins or Reeds–Shepp steering.

LaValle and Kuffner's RRT (2001) was made for non-holonomic robots: a tree
of poses ``(x, y, θ)`` grown by *steering*, each edge an exact shortest
curve of the car (:mod:`navlab.sampling.dubins`: forward only;
:mod:`navlab.sampling.reeds_shepp`: forward and reverse). RRT* (Karaman and
Frazzoli, IJRR 2011) keeps the same steering for choosing parents and
rewiring, with the near radius of a 3-dimensional space,
``γ (log n / n)^(1/3)``, in steering distance.

Nearest neighbours are exact under the steering distance: the steering
length is never below the Euclidean distance of the positions, so a uniform
grid of cells over the positions is visited ring by ring from the sample and
the search stops once the next ring is farther (in Euclidean distance) than
the best steering length found; within it a node steers only when a lower
bound (the larger of the Euclidean distance and r·|Δθ|, :func:`lower_bound`)
is below the best found. Near sets gather the nodes whose positions
lie within the near radius and keep those whose steering length does.

Every edge is checked with the robot's footprint on the map's cells
(:mod:`navlab.sampling.footprint_lattice`: certified, conservative by at
most ``√2·res + δ/2 + R·sin(Δθ/2)``). Choosing a parent and rewiring use
that lower bound first: a near node steers (a Reeds–Shepp solve costs
about as much as a hundred distances) only when the bound could improve a
cost, and an edge is collision-checked only when its exact cost does.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from . import dubins, reeds_shepp, reeds_shepp_length
from .curves import MAX_SEGMENTS, NOP, advance
from .footprint_lattice import NO_EXACT, curve_free
from .tree_kernel import _remove_child

#: istate fields
S_SIZE, S_EDGE_CHECKS, S_REWIRES, S_GOALS, S_FIRST_ITER, S_BEST = 0, 1, 2, 3, 4, 5
#: fparams fields: step η [m], γ, turning radius, reverse (0/1), goal x, y, θ,
#: mode (0: RRT, stop at the first goal connection; 1: RRT*), rewire tolerance [m]
(F_ETA, F_GAMMA, F_RADIUS, F_REVERSE, F_GX, F_GY, F_GT, F_MODE, F_EPS) = range(9)
#: lattice arrays passed as one tuple: blocked, res, ds, theta0, step, bins, pose_cells, pose_start


@njit(cache=True)
def steer(x0, y0, t0, x1, y1, t1, radius, reverse, seg, kinds, lengths, known=math.inf):
    """The shortest curve from pose 0 to pose 1: fills ``kinds`` (NOP-padded)
    and signed ``lengths`` [m]; returns its length [m]. ``known`` [m], when given, is
    :func:`steer_length`'s answer: a Reeds–Shepp word that cannot be as short is then
    dropped by cheap bounds before it is solved (the same word, bit for bit)."""
    if reverse:
        local = reeds_shepp._local(x0, y0, t0, x1, y1, t1, radius)
        total = reeds_shepp_length.word(local[0], local[1], local[2], known / radius, seg, kinds, lengths)
        for i in range(MAX_SEGMENTS):
            lengths[i] *= radius
        return total * radius
    d, a, b = dubins._normalised(x0, y0, t0, x1, y1, t1, radius)
    word, t, p, q = dubins.solve(d, a, b)
    kinds[:] = NOP
    lengths[:] = 0.0
    for i in range(3):
        kinds[i] = dubins.WORDS[word, i]
    lengths[0], lengths[1], lengths[2] = t * radius, p * radius, q * radius
    return (t + p + q) * radius


@njit(cache=True)
def steer_length(x0, y0, t0, x1, y1, t1, radius, reverse, seg, kinds, lengths, cutoff=math.inf):
    """:func:`steer`'s length only (Dubins without filling the word). A Reeds–Shepp length above
    ``cutoff`` may come back as inf (a nearest search passes its best so far: most candidates are
    then dropped by cheap bounds); at or below it, it is exact (the cutoff is widened by 1e-9 so
    that a tie with the best is still seen, bit for bit)."""
    if reverse:
        local = reeds_shepp._local(x0, y0, t0, x1, y1, t1, radius)
        return reeds_shepp_length.length_below(local[0], local[1], local[2],
                                               cutoff / radius * (1.0 + 1e-9)) * radius
    d, a, b = dubins._normalised(x0, y0, t0, x1, y1, t1, radius)
    return dubins.length(d, a, b) * radius  # solve's t + p + q bit for bit, sooner


@njit(cache=True)
def truncate(x, y, theta, kinds, lengths, radius, limit):
    """Cut the word after ``limit`` metres; returns the end pose."""
    left = limit
    for i in range(MAX_SEGMENTS):
        if kinds[i] == NOP:
            continue
        s = lengths[i]
        if left <= 0.0:
            kinds[i], lengths[i] = NOP, 0.0
            continue
        if abs(s) > left:
            s = left if s > 0 else -left
            lengths[i] = s
        left -= abs(s)
        x, y, theta = advance(x, y, theta, kinds[i], s, radius)
    return x, y, theta


@njit(cache=True)
def end_pose(x, y, theta, kinds, lengths, radius):
    for i in range(MAX_SEGMENTS):
        if kinds[i] != NOP:
            x, y, theta = advance(x, y, theta, kinds[i], lengths[i], radius)
    return x, y, theta


@njit(cache=True, inline="always")
def lower_bound(x0, y0, t0, x1, y1, t1, radius):
    """A lower bound on the Dubins or Reeds–Shepp length between two poses: the
    positions' distance, and the heading change times the turning radius (only
    arcs turn the car, by their length over r, so the shortest turn between the
    headings needs r·|Δθ| of arc)."""
    turn = abs(t1 - t0)
    if turn >= 2.0 * math.pi:  # (fmod would return a smaller one unchanged: skip the call)
        turn = np.fmod(turn, 2.0 * math.pi)
    turn = min(turn, 2.0 * math.pi - turn)
    dx, dy = x1 - x0, y1 - y0
    # a relative 1e-9 below: rounding must never lift the bound above an exact length (the square root of
    # the squared norm, within 2 ulp of hypot, instead of hypot: the scan of a small tree bounds every
    # node per sample, ~10% of a narrow-aisle run at 10^5 iterations)
    return max(math.sqrt(dx * dx + dy * dy), radius * turn) * (1.0 - 1e-9)


@njit(cache=True, inline="always")
def _cell(v, v0, cell, n):
    k = int(math.floor((v - v0) / cell))
    return 0 if k < 0 else (n - 1 if k >= n else k)


@njit(cache=True)
def _insert(k, pose, head, nxt, gridp, dims):
    i = _cell(pose[k, 0], gridp[0], gridp[2], dims[0])
    j = _cell(pose[k, 1], gridp[1], gridp[2], dims[1])
    c = j * dims[0] + i
    nxt[k] = head[c]
    head[c] = k


@njit(cache=True)
def index_positions(pose, n, head, nxt, gridp, dims):
    """(Re)build the position grid over the first ``n`` nodes (``head`` cleared first)."""
    head[:] = -1
    for k in range(n):
        _insert(k, pose, head, nxt, gridp, dims)


#: up to this many nodes the nearest one is found by a scan: the grid, sized for the whole run, would be
#: mostly empty cells to walk (a narrow aisle keeps its tree at a few dozen nodes for thousands of samples)
SCAN_NODES = 256


@njit(cache=True)
def _nearest(qx, qy, qt, pose, n, head, nxt, gridp, dims, radius, reverse, seg, kinds, lengths, bound):
    """The node of least steering length to (qx, qy, qt) among the ``n`` in the tree; ties: the lowest index.
    ``bound`` is scratch for ``n`` lower bounds."""
    if n <= SCAN_NODES:
        # candidates by increasing lower bound (each picked by a scan: a query steers to a few of them
        # before the next bound is above the best length, cheaper than sorting all): the first ones set
        # a small cutoff, which drops most of the rest inside the length solver or before it
        for k in range(n):
            bound[k] = lower_bound(pose[k, 0], pose[k, 1], pose[k, 2], qx, qy, qt, radius)
        best, best_d = -1, math.inf
        while True:
            k, e = -1, math.inf
            for j in range(n):
                if bound[j] < e:
                    k, e = j, bound[j]
            if k < 0 or e > best_d or (e == best_d and k > best):
                return best, best_d
            bound[k] = math.inf  # visited
            d = steer_length(pose[k, 0], pose[k, 1], pose[k, 2], qx, qy, qt, radius, reverse, seg, kinds, lengths,
                             best_d)
            if d < best_d or (d == best_d and k < best):
                best, best_d = k, d
    ci = _cell(qx, gridp[0], gridp[2], dims[0])
    cj = _cell(qy, gridp[1], gridp[2], dims[1])
    best, best_d = -1, math.inf
    ring = 0
    most = max(dims[0], dims[1])
    while ring <= most:
        for j in range(cj - ring, cj + ring + 1):
            if j < 0 or j >= dims[1]:
                continue
            edge_row = j == cj - ring or j == cj + ring
            step = 1 if edge_row else 2 * ring
            i = ci - ring
            while i <= ci + ring:
                if 0 <= i < dims[0]:
                    k = head[j * dims[0] + i]
                    while k >= 0:
                        e = lower_bound(pose[k, 0], pose[k, 1], pose[k, 2], qx, qy, qt, radius)
                        if e < best_d or (e == best_d and k < best):
                            d = steer_length(pose[k, 0], pose[k, 1], pose[k, 2], qx, qy, qt, radius, reverse, seg,
                                             kinds, lengths, best_d)
                            if d < best_d or (d == best_d and k < best):
                                best, best_d = k, d
                        k = nxt[k]
                i += step if step > 0 else 1
        # every unvisited node lies at least ring·cell away (border cells reach outwards: their
        # nodes are visited in the ring of their clamped cell, which only makes the bound looser)
        if best >= 0 and ring * gridp[2] - 1e-9 > best_d:
            break
        ring += 1
    return best, best_d


@njit(cache=True)
def _near(qx, qy, reach, pose, head, nxt, gridp, dims, out):
    """Nodes whose positions lie within ``reach`` of (qx, qy); returns their count (in ``out``)."""
    lo_i = _cell(qx - reach, gridp[0], gridp[2], dims[0])
    hi_i = _cell(qx + reach, gridp[0], gridp[2], dims[0])
    lo_j = _cell(qy - reach, gridp[1], gridp[2], dims[1])
    hi_j = _cell(qy + reach, gridp[1], gridp[2], dims[1])
    m = 0
    r2 = reach * reach
    for j in range(lo_j, hi_j + 1):
        for i in range(lo_i, hi_i + 1):
            k = head[j * dims[0] + i]
            while k >= 0:
                dx, dy = pose[k, 0] - qx, pose[k, 1] - qy
                if dx * dx + dy * dy <= r2 and m < out.shape[0]:
                    out[m] = k
                    m += 1
                k = nxt[k]
    return m


@njit(cache=True)
def _edge_free(pose, a, x1, y1, t1, kinds, lengths, radius, lat_blocked, lat_res, lat_ds, lat_theta0, lat_step,
               lat_bins, lat_cells, lat_start, lat_clear, lat_disc, istate):
    istate[S_EDGE_CHECKS] += 1
    return curve_free(lat_blocked, lat_res, pose[a, 0], pose[a, 1], pose[a, 2], kinds, lengths, radius, lat_ds,
                      lat_theta0, lat_step, lat_bins, lat_cells, lat_start, lat_clear, lat_disc, *NO_EXACT)


@njit(cache=True)
def _attach(k, p, parent, child, sibling):
    parent[k] = p
    sibling[k] = child[p]
    child[p] = k


@njit(cache=True)
def _shift(root, delta, cost, child, sibling, stack):
    """Add ``delta`` to the cost of every descendant of ``root``."""
    top = 0
    c = child[root]
    while c >= 0:
        stack[top] = c
        top += 1
        c = sibling[c]
    while top > 0:
        top -= 1
        k = stack[top]
        cost[k] += delta
        c = child[k]
        while c >= 0:
            stack[top] = c
            top += 1
            c = sibling[c]


@njit(cache=True)
def _best_goal(goal_node, goal_extra, cost, istate):
    best, best_cost = -1, math.inf
    for g in range(istate[S_GOALS]):
        v = cost[goal_node[g]] + goal_extra[g]
        if v < best_cost:
            best, best_cost = g, v
    istate[S_BEST] = best
    return best_cost


@njit(cache=True)
def try_goal(k, it, pose, goal_node, goal_extra, goal_kinds, goal_len, istate, fparams, lat_blocked, lat_res,
             lat_ds, lat_theta0, lat_step, lat_bins, lat_cells, lat_start, lat_clear, lat_disc):
    """Connect node ``k`` to the goal pose, exactly, by steering: kept when
    within the step η and collision-free. Returns whether it was kept."""
    seg = np.zeros(MAX_SEGMENTS)
    kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    lengths = np.zeros(MAX_SEGMENTS)
    radius, reverse = fparams[F_RADIUS], fparams[F_REVERSE] > 0.5
    dg = steer(pose[k, 0], pose[k, 1], pose[k, 2], fparams[F_GX], fparams[F_GY], fparams[F_GT], radius, reverse, seg,
               kinds, lengths)
    if dg > fparams[F_ETA] or istate[S_GOALS] >= goal_node.shape[0]:
        return False
    if dg > 1e-12 and not _edge_free(pose, k, fparams[F_GX], fparams[F_GY], fparams[F_GT], kinds, lengths, radius,
                                     lat_blocked, lat_res, lat_ds, lat_theta0, lat_step, lat_bins, lat_cells,
                                     lat_start, lat_clear, lat_disc, istate):
        return False
    g = istate[S_GOALS]
    goal_node[g], goal_extra[g] = k, dg
    goal_kinds[g, :] = kinds
    goal_len[g, :] = lengths
    istate[S_GOALS] += 1
    if istate[S_FIRST_ITER] < 0:
        istate[S_FIRST_ITER] = it
    return True


@njit(cache=True)
def grow(samples, it0, pose, parent, cost, child, sibling, edge_kinds, edge_len, head, nxt, gridp, dims, goal_node,
         goal_extra, goal_kinds, goal_len, trace, istate, fparams, lat_blocked, lat_res, lat_ds, lat_theta0, lat_step,
         lat_bins, lat_cells, lat_start, lat_clear, lat_disc):
    """Run one iteration per sample (M, 3); returns the iterations run (fewer
    when RRT reached the goal). ``trace[it]`` is the best goal cost after iteration ``it``.

    Each node keeps the word of the edge from its parent exactly as it was
    checked (``edge_kinds``, ``edge_len``), and each goal connection its own:
    the path is rebuilt from those, never by steering again (two words of
    equal length may join the same poses, and only the checked one is known free)."""
    eta, gamma, radius = fparams[F_ETA], fparams[F_GAMMA], fparams[F_RADIUS]
    reverse = fparams[F_REVERSE] > 0.5
    star = fparams[F_MODE] > 0.5
    eps = fparams[F_EPS]
    seg = np.zeros(MAX_SEGMENTS)
    kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    lengths = np.zeros(MAX_SEGMENTS)
    near = np.empty(pose.shape[0], dtype=np.int64)
    near_d = np.empty(pose.shape[0])
    order = np.empty(pose.shape[0], dtype=np.int64)
    stack = np.empty(pose.shape[0], dtype=np.int64)
    best_cost = _best_goal(goal_node, goal_extra, cost, istate)
    for s in range(samples.shape[0]):
        it = it0 + s
        n = istate[S_SIZE]
        qx, qy, qt = samples[s, 0], samples[s, 1], samples[s, 2]
        a, d = _nearest(qx, qy, qt, pose, n, head, nxt, gridp, dims, radius, reverse, seg, kinds, lengths, near_d)
        steer(pose[a, 0], pose[a, 1], pose[a, 2], qx, qy, qt, radius, reverse, seg, kinds, lengths, d)
        if d > eta:
            x, y, t = truncate(pose[a, 0], pose[a, 1], pose[a, 2], kinds, lengths, radius, eta)
            d = eta
        else:
            x, y, t = qx, qy, qt
        if d <= 1e-9 or not _edge_free(pose, a, x, y, t, kinds, lengths, radius, lat_blocked, lat_res, lat_ds,
                                       lat_theta0, lat_step, lat_bins, lat_cells, lat_start, lat_clear, lat_disc,
                                       istate):
            trace[it] = best_cost
            continue
        k = n
        pose[k, 0], pose[k, 1], pose[k, 2] = x, y, t
        edge_kinds[k, :] = kinds
        edge_len[k, :] = lengths
        p, c_new = a, cost[a] + d
        m = 0
        rewires_before = istate[S_REWIRES]
        if star:
            rn = min(eta, gamma * (math.log(n + 1.0) / (n + 1.0)) ** (1.0 / 3.0))
            m = _near(x, y, rn, pose, head, nxt, gridp, dims, near)
            # candidate parents in the order of a lower bound on the cost they would give
            # (lower_bound never exceeds the steering length): steer and check only while
            # that bound is below the best cost found, and check collisions only for improvements
            for i in range(m):
                q = near[i]
                near_d[i] = cost[q] + lower_bound(pose[q, 0], pose[q, 1], pose[q, 2], x, y, t, radius)
            order[:m] = np.argsort(near_d[:m], kind="mergesort")
            for i in range(m):
                j = order[i]
                if near_d[j] >= c_new:
                    break
                q = near[j]
                # the length alone first (inf when it cannot pass: the cutoff allows for rounding),
                # the curve only for an edge that would improve
                dq = steer_length(pose[q, 0], pose[q, 1], pose[q, 2], x, y, t, radius, reverse, seg, kinds,
                                  lengths, min(rn, c_new - cost[q] + 1e-12 * c_new))
                if dq > rn or cost[q] + dq >= c_new:
                    continue
                steer(pose[q, 0], pose[q, 1], pose[q, 2], x, y, t, radius, reverse, seg, kinds, lengths, dq)
                if _edge_free(pose, q, x, y, t, kinds, lengths, radius, lat_blocked, lat_res, lat_ds, lat_theta0,
                              lat_step, lat_bins, lat_cells, lat_start, lat_clear, lat_disc, istate):
                    p, c_new = q, cost[q] + dq
                    edge_kinds[k, :] = kinds
                    edge_len[k, :] = lengths
        cost[k] = c_new
        child[k] = -1
        _attach(k, p, parent, child, sibling)
        _insert(k, pose, head, nxt, gridp, dims)
        istate[S_SIZE] = n + 1
        if star:
            for i in range(m):
                q = near[i]
                if q == p or c_new + lower_bound(x, y, t, pose[q, 0], pose[q, 1], pose[q, 2], radius) >= cost[q] - eps:
                    continue  # not even the lower bound would improve it
                dq = steer_length(x, y, t, pose[q, 0], pose[q, 1], pose[q, 2], radius, reverse, seg, kinds, lengths,
                                  min(rn, cost[q] - eps - c_new + 1e-12 * cost[q]))
                if dq > rn or c_new + dq >= cost[q] - eps:
                    continue
                steer(x, y, t, pose[q, 0], pose[q, 1], pose[q, 2], radius, reverse, seg, kinds, lengths, dq)
                if not _edge_free(pose, k, pose[q, 0], pose[q, 1], pose[q, 2], kinds, lengths, radius, lat_blocked,
                                  lat_res, lat_ds, lat_theta0, lat_step, lat_bins, lat_cells, lat_start, lat_clear,
                                  lat_disc, istate):
                    continue
                delta = c_new + dq - cost[q]
                edge_kinds[q, :] = kinds
                edge_len[q, :] = lengths
                _remove_child(child, sibling, parent[q], q)
                _attach(q, k, parent, child, sibling)
                cost[q] += delta
                _shift(q, delta, cost, child, sibling, stack)
                istate[S_REWIRES] += 1
        rewired = istate[S_REWIRES] > rewires_before
        if try_goal(k, it, pose, goal_node, goal_extra, goal_kinds, goal_len, istate, fparams, lat_blocked, lat_res,
                    lat_ds, lat_theta0, lat_step, lat_bins, lat_cells, lat_start, lat_clear, lat_disc) or rewired:
            best_cost = _best_goal(goal_node, goal_extra, cost, istate)  # costs change only by these two
        trace[it] = best_cost
        if not star and istate[S_GOALS] > 0:
            return s + 1
    return samples.shape[0]
