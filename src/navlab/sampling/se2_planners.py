"""RRT, RRT* and Informed RRT* between poses, with Dubins or Reeds–Shepp
steering (the compiled loop: :mod:`navlab.sampling.se2_tree`).

Samples: the positions come from any registered sampler (uniform, goal
bias, Gaussian, boundary, integration: where in the plane they fall is what
distinguishes them), the headings are uniform on [−π, π), except that a
sample the goal-bias sampler places on the goal takes the goal's heading,
so goal bias steers at the goal pose itself. Informed RRT* draws positions
from the ellipse |x − start| + |x − goal| ≤ c_best: the steering length is
never below the Euclidean distance, so no pose outside it can improve the path.
"""

from __future__ import annotations

import math
import time
from typing import Any, Dict, Tuple

import numpy as np

from ..limits import check_length
from ..result import Result, Status, Tree
from . import se2_tree as K
from .curves import MAX_SEGMENTS, NOP
from .footprint_lattice import clearance_map
from .regions import BoxRegion, InformedRegion
from .samplers import Sampler

#: planners with an SE(2) version, and the kernel mode each runs
SE2_MODES = {"rrt": 0, "rrt_star": 1, "informed_rrt_star": 1}
#: settings they take (beyond the query's motion, turning_radius, footprint, resolution)
SE2_TREE_PARAMS = ("expand_dis", "max_iter", "max_time", "connect_circle_dist", "batch_size", "keep_tree",
                   "heading_bins")
#: iterations when max_iter is not given
DEFAULT_MAX_ITER = {"rrt": 10_000, "rrt_star": 5_000, "informed_rrt_star": 5_000}
#: the tree's arrays hold this many nodes (and trace entries) at first, then double as needed
INITIAL_NODES = 4096


def se2_tree_params(planner: str) -> Tuple[str, ...]:
    """The settings of :data:`SE2_TREE_PARAMS` ``planner`` takes: all but ``connect_circle_dist`` for rrt, which
    does not rewire (its mode 0)."""
    return tuple(k for k in SE2_TREE_PARAMS if k != "connect_circle_dist" or SE2_MODES.get(planner) != 0)


def se2_gamma(bounds) -> float:
    """γ of Karaman and Frazzoli's RRT* radius in d = 3 (x, y, θ) with OMPL's rewire factor 1.1:
    γ = 1.1 · 2 (1 + 1/3)^(1/3) (μ(X)/ζ_3)^(1/3), μ(X) = area · 2π, ζ_3 = 4π/3."""
    volume = bounds.area * 2.0 * math.pi
    return 1.1 * 2.0 * (4.0 / 3.0) ** (1.0 / 3.0) * (volume / (4.0 * math.pi / 3.0)) ** (1.0 / 3.0)


class _TreeArrays:
    """The tree's per-node arrays (and the goal connections' and the cost
    trace), grown by doubling when a run bounded by time outgrows them."""

    NODE = {"pose": ((3,), float, 0.0), "parent": ((), np.int64, -1), "cost": ((), float, 0.0),
            "child": ((), np.int64, -1), "sibling": ((), np.int64, -1), "edge_kinds": ((MAX_SEGMENTS,), np.int64, NOP),
            "edge_len": ((MAX_SEGMENTS,), float, 0.0), "nxt": ((), np.int64, -1), "goal_node": ((), np.int64, 0),
            "goal_extra": ((), float, 0.0), "goal_kinds": ((MAX_SEGMENTS,), np.int64, NOP),
            "goal_len": ((MAX_SEGMENTS,), float, 0.0)}

    def __init__(self, nodes: int, trace_length: int) -> None:
        for name, (shape, dtype, fill) in self.NODE.items():
            setattr(self, name, np.full((nodes, *shape), fill, dtype=dtype))
        self.trace = np.full(max(trace_length, 0), np.inf)

    def ensure(self, nodes: int, iterations: int) -> None:
        """Room for ``nodes`` nodes and ``iterations`` trace entries."""
        if nodes > len(self.pose):
            size = max(nodes, 2 * len(self.pose))
            for name, (shape, dtype, fill) in self.NODE.items():
                old = getattr(self, name)
                new = np.full((size, *shape), fill, dtype=dtype)
                new[:len(old)] = old
                setattr(self, name, new)
        if iterations > len(self.trace):
            self.trace = np.concatenate([self.trace, np.full(max(iterations, 2 * len(self.trace)) - len(self.trace),
                                                             np.inf)])


def check_se2_settings(settings: Dict[str, Any]) -> Dict[str, Any]:
    """A car-like tree's settings checked as the holonomic trees check theirs (one set of checks: theirs).

    ``expand_dis=-1``, ``max_time=-1`` and ``keep_tree='no'`` (taken as true) were accepted, and
    ``expand_dis=0`` fell back to the default (review, session 21).

    Parameters
    ----------
    settings : dict
        Any of :data:`SE2_TREE_PARAMS` (``heading_bins`` is the lattice's, checked by its query).

    Returns
    -------
    dict
        ``settings`` with ``max_iter`` and ``batch_size`` as ints where given.

    Raises
    ------
    ParameterError
        Naming the first bad setting.
    """
    from .planners import make_planner

    shared = {k: settings[k] for k in ("expand_dis", "max_iter", "max_time", "batch_size", "keep_tree")
              if settings.get(k) is not None}
    checked = make_planner("rrt", **shared)
    if settings.get("connect_circle_dist") is not None:
        check_length("connect_circle_dist", settings["connect_circle_dist"], allow_zero=False)
    return {**settings, **{k: getattr(checked, k) for k in ("max_iter", "batch_size") if k in shared}}


def plan_se2_tree(planner: str, world, sampler: Sampler, lattice, blocked: np.ndarray, to_grid, start, goal,
                  motion: str, turning_radius: float, rng, settings: Dict[str, Any]) -> Result:
    """Grow an SE(2) tree from pose ``start`` to pose ``goal`` (grid-frame poses via ``to_grid``).

    Parameters
    ----------
    planner : {"rrt", "rrt_star", "informed_rrt_star"}
    world : World
        What the sampler draws positions in (world frame).
    lattice : navlab.sampling.footprint_lattice.Lattice
        The footprint's cells per heading bin on ``blocked`` (the grid).
    to_grid : callable
        World poses (x, y, θ; numbers or arrays) → grid-frame poses (the map's origin and yaw).
    settings : dict
        ``expand_dis`` (η, m; default the smaller of 0.2 × the bounds' diagonal, OMPL's
        range, and two turning radii: a longer curve rarely fits between obstacles),
        ``max_iter``, ``max_time`` (s), ``connect_circle_dist`` (γ; default
        :func:`se2_gamma`), ``batch_size``, ``keep_tree``.
    """
    t0 = time.perf_counter()
    settings = check_se2_settings(settings)
    b = world.bounds
    diagonal = math.hypot(b.xmax - b.xmin, b.ymax - b.ymin)
    given = {k: v for k, v in settings.items() if v is not None}
    eta = float(given.get("expand_dis", min(0.2 * diagonal, 2.0 * turning_radius)))
    gamma = float(given.get("connect_circle_dist", se2_gamma(b)))
    max_iter = given.get("max_iter", DEFAULT_MAX_ITER[planner])
    max_time = given.get("max_time")
    batch = given.get("batch_size", 64)
    params = {"expand_dis": eta, "connect_circle_dist": gamma, "max_iter": max_iter, "max_time": max_time,
              "batch_size": batch, "keep_tree": bool(settings.get("keep_tree", False))}
    # arrays grown by doubling from a few thousand nodes: a tree often keeps far fewer nodes than it
    # has iterations (a narrow aisle: a few dozen in 10^5), and sizing them for the whole run took
    # 50-90 ms at 10^5 iterations, ~40 ms of a 0.2 s budget (sized for 2^16)
    expected = min(max_iter + 1, INITIAL_NODES)
    a = _TreeArrays(expected, trace_length=expected - 1)
    gs, gg = to_grid(*start), to_grid(*goal)
    a.pose[0] = gs
    # the position index: about two nodes per cell, cells no smaller than the map's; rebuilt each time the
    # tree has grown fourfold (sized for max_iter, a narrow aisle's few thousand nodes sat in 50 000 mostly
    # empty cells, and every nearest-neighbour query walked them ring by ring)
    h, w = blocked.shape
    extent = (w * lattice.resolution, h * lattice.resolution)
    indexed = [0]

    def index(nodes: int):
        cell = max(lattice.resolution, math.sqrt(extent[0] * extent[1] / max(1.0, nodes / 2.0)))
        dims = np.array([max(1, math.ceil(extent[0] / cell)), max(1, math.ceil(extent[1] / cell))], dtype=np.int64)
        gridp = np.array([0.0, 0.0, cell])
        head = np.full(int(dims[0] * dims[1]), -1, dtype=np.int64)
        n = int(istate[K.S_SIZE])
        K.index_positions(a.pose, n, head, a.nxt, gridp, dims)
        indexed[0] = n
        return head, gridp, dims

    istate = np.zeros(6, dtype=np.int64)
    istate[K.S_SIZE] = 1
    head, gridp, dims = index(min(expected, 4 * K.SCAN_NODES))
    istate[K.S_FIRST_ITER], istate[K.S_BEST] = -1, -1
    fparams = np.zeros(9)
    fparams[[K.F_ETA, K.F_GAMMA, K.F_RADIUS, K.F_REVERSE]] = (
        eta, gamma, turning_radius, 1.0 if motion == "reeds_shepp" else 0.0)
    fparams[[K.F_GX, K.F_GY, K.F_GT]] = gg
    fparams[K.F_MODE] = SE2_MODES[planner]
    fparams[K.F_EPS] = 1e-9 * max(1.0, diagonal)
    lat = (blocked, lattice.resolution, lattice.ds, lattice.theta0, lattice.step, lattice.bins, lattice.pose_cells,
           lattice.pose_start, clearance_map(blocked, lattice.resolution), lattice.clear_disc)
    K.try_goal(0, 0, a.pose, a.goal_node, a.goal_extra, a.goal_kinds, a.goal_len, istate, fparams, *lat)
    if planner == "rrt" and istate[K.S_GOALS] > 0:
        max_iter = 0  # the start reaches the goal in one step: nothing to grow
    box = BoxRegion(b)
    checker = world.checker()
    it, first_time = 0, None
    gpoint = np.asarray(goal[:2])
    while it < max_iter:
        if max_time is not None and time.perf_counter() - t0 > max_time:
            break
        region = box
        best = istate[K.S_BEST]
        if planner == "informed_rrt_star" and best >= 0:
            c_best = a.cost[a.goal_node[best]] + a.goal_extra[best]
            region = InformedRegion(start[:2], goal[:2], c_best, b)
        m = min(batch, max_iter - it)
        a.ensure(int(istate[K.S_SIZE]) + m, it + m)
        if istate[K.S_SIZE] >= 4 * max(indexed[0], K.SCAN_NODES):
            head, gridp, dims = index(4 * int(istate[K.S_SIZE]))
        points = np.asarray(sampler.sample(world, rng, m, checker=checker, region=region), dtype=float)
        headings = rng.uniform(-math.pi, math.pi, len(points))
        at_goal = np.all(points == gpoint, axis=1)
        headings[at_goal] = goal[2]
        samples = np.ascontiguousarray(np.column_stack(to_grid(points[:, 0], points[:, 1], headings)), dtype=float)
        used = K.grow(samples, it, a.pose, a.parent, a.cost, a.child, a.sibling, a.edge_kinds, a.edge_len, head,
                      a.nxt, gridp, dims, a.goal_node, a.goal_extra, a.goal_kinds, a.goal_len, a.trace, istate,
                      fparams, *lat)
        it += used
        if first_time is None and istate[K.S_FIRST_ITER] >= 0:
            first_time = time.perf_counter() - t0
        if used < m:
            break
    elapsed = time.perf_counter() - t0
    stats = {"iterations": it, "nodes": int(istate[K.S_SIZE]), "edge_checks": int(istate[K.S_EDGE_CHECKS]),
             "collision_checks": int(istate[K.S_EDGE_CHECKS]), "rewires": int(istate[K.S_REWIRES]),
             "first_solution_iteration": int(istate[K.S_FIRST_ITER]) if istate[K.S_FIRST_ITER] >= 0 else None,
             "first_solution_time_s": first_time, "cost_trace": a.trace[:it].copy(), "time_s": elapsed}
    tree = None
    if params["keep_tree"]:
        n = int(istate[K.S_SIZE])
        tree = Tree(nodes=a.pose[:n].copy(), parent=a.parent[:n].copy())
    best = int(istate[K.S_BEST])
    if best < 0:
        why = f"the goal pose was not reached in {it} iterations (more iterations or time may reach it" + (
            "; dubins drives forward only: a goal reachable only in reverse needs motion='reeds_shepp'"
            if motion == "dubins" else "") + ")"
        return Result(status=Status.FAILED, path=np.empty((0, 3)), cost=math.inf, stats=stats, reason=why,
                      params=params, tree=tree)
    # the chain of nodes, each edge's word as it was checked, then the goal connection's
    chain = [int(a.goal_node[best])]
    while a.parent[chain[-1]] >= 0:
        chain.append(int(a.parent[chain[-1]]))
    chain.reverse()
    words = [(a.edge_kinds[c], a.edge_len[c]) for c in chain[1:]] + [(a.goal_kinds[best], a.goal_len[best])]
    segments = [(int(k), float(s)) for ks, ls in words for k, s in zip(ks, ls) if k != NOP and s != 0.0]
    return Result(status=Status.EXACT, path=np.empty((0, 3)), cost=float(sum(abs(s) for _, s in segments)),
                  stats={**stats, "segments_raw": segments}, params=params, tree=tree)


__all__ = ["SE2_MODES", "SE2_TREE_PARAMS", "plan_se2_tree", "se2_gamma"]
