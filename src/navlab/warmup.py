"""Compile (or load from numba's cache) the kernels a query will use, before it is timed.

A fresh process pays numba's compile or cache-load time on its first call of
each kernel (seconds), and OMPL's first import. That time is not planning
time: :func:`warm_up` runs a tiny query of the same planner and sampler, so the
timed query that follows starts warm and its time budget (``max_time``) is
spent on planning. The benchmark harness calls it in every worker process
before the first timed trial of each planner and sampler, and reports the
seconds apart (``warmup_s``).
"""

from __future__ import annotations

import functools
import time

import numpy as np

#: iterations of the warm-up query: enough to reach every kernel (sampling,
#: steering, rewiring, goal connection), too few to cost time once compiled
WARM_ITERATIONS = 64
OMPL_PREFIX = "ompl:"


def _tiny_map_world():
    """A 16 × 16 map with a wall, start and goal on either side (0.25 m cells)."""
    from .grid.occupancy import OccupancyGrid
    from .world import World

    blocked = np.zeros((16, 16), dtype=bool)
    blocked[2:14, 8] = True
    return World.from_grid(OccupancyGrid(blocked, resolution=0.25, name="warm-up map"), (0.6, 2.0), (3.4, 2.0))


def _warm_tree(planner: str, sampler: str, on_map: bool) -> None:
    # tree_query, not plan: plan() warms up first, which would recurse here
    from .queries import tree_query
    from .world import load_world

    if _SIBLINGS["helpers_first"] and not _SIBLINGS["helpers_done"]:
        _warm_tree_helpers()
        _SIBLINGS["helpers_done"] = True
    tree_query(load_world("trap"), planner, sampler, 0, {"max_iter": WARM_ITERATIONS})
    if on_map:
        tree_query(_tiny_map_world(), planner, sampler, 0, {"max_iter": WARM_ITERATIONS})


def _warm_tree_helpers() -> None:
    """Compile the tree loop's helpers (bucket grid, cost propagation) with
    exactly the argument types the loop passes them: taken from a real
    :class:`~navlab.sampling.tree_kernel.Tree`'s arrays."""
    from .sampling import bucket_grid as G
    from .sampling import tree_kernel as K
    from .world import Bounds

    tree = K.Tree((0.5, 0.5), Bounds(0.0, 1.0, 0.0, 1.0), max_nodes=64)
    tree.reserve(1, 1)  # builds the bucket grid over the root
    grid = tree.grid.arrays
    G.nearest(0.25, 0.25, tree.xy, tree.cost, grid)
    G.near(0.25, 0.25, 0.01, tree.xy, tree.cost, grid, tree.scratch_idx, tree.scratch_dist, tree.scratch_cost,
           tree.scratch_x, tree.scratch_y)
    zero = np.int64(0)  # not a Python 0: numba would compile a literal-0 variant the loop never calls
    G.insert(zero, tree.xy, tree.cost, grid)  # the root a second time: a throwaway tree
    K._shift_subtree(tree.child, tree.sibling, tree.cost, zero, -0.0, tree.scratch_queue, tree.goal_slot,
                     tree.goal_extra, tree.istate, tree.best_cost, True, grid)


#: This process's part in a pool's warm-up (set once per worker by
#: :func:`claim_warm_up_role`): the first worker to claim compiles the tree
#: loop's helpers first, while its siblings start with the collision
#: checker's kernels; each then loads what the other wrote to numba's cache
#: instead of compiling it again (about half the compile time of a cold pool).
_SIBLINGS = {"helpers_first": False, "helpers_done": False, "lock": None}


def claim_warm_up_role(lock_path: str) -> None:
    """Pool initializer: the worker that takes ``lock_path``'s lock first
    (and keeps it while it lives) compiles the tree helpers first."""
    import os

    try:
        import fcntl
    except ImportError:  # not POSIX: every worker compiles everything, as before
        return
    fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return
    _SIBLINGS["helpers_first"], _SIBLINGS["lock"] = True, fd


def _warm_grid(algorithm: str) -> None:
    from .grid import plan as grid_plan
    from .grid.occupancy import OccupancyGrid

    blocked = np.zeros((16, 16), dtype=bool)
    blocked[2:14, 8] = True
    grid = OccupancyGrid(blocked, name="warm-up map")
    for smooth in (False, True):
        grid_plan(grid, (1, 8), (14, 8), algorithm=algorithm, smooth=smooth)


def _warm_ompl() -> None:
    """OMPL's modules load on first import; OMPL sees the world through
    navlab's exact checker, whose kernels are warmed here."""
    import ompl.base  # noqa: F401 - the import is the warm-up
    import ompl.geometric  # noqa: F401
    from .world import load_world

    checker = load_world("trap").checker()
    pts = np.array([[1.0, 1.0], [2.0, 2.0]])
    checker.points_free(pts)
    checker.segments_free(pts, pts[::-1].copy())


@functools.lru_cache(maxsize=None)
def _warm(planner: str, sampler: str, on_map: bool) -> None:
    from .sampling.planners import PLANNERS

    if planner.startswith(OMPL_PREFIX):
        _warm_ompl()
    elif planner in PLANNERS:  # asked first: a tree planner's warm-up then never loads the grid search
        _warm_tree(planner, sampler, on_map)
    else:
        _warm_grid(planner)


def warm_up(planner: str = "rrt_star", sampler: str = "uniform", *, on_map: bool = False) -> float:
    """Warm the kernels of ``planner`` with ``sampler``; return the seconds spent.

    Parameters
    ----------
    planner : str
        A tree planner (``rrt_star``, ...), a grid algorithm (``astar``,
        ``jps``, ``theta_star``, ``dijkstra``) or an OMPL planner
        (``ompl:RRTstar``: loads OMPL and warms the exact checker it uses).
    sampler : str
        The tree planner's sampler (ignored by the others).
    on_map : bool
        Also warm the query on an occupancy-grid world (the map checker's kernels).

    Returns
    -------
    float
        Seconds spent. The second and later calls in a process with the same
        arguments return at once (about 0 s): the kernels are loaded.
    """
    from .compile_clock import hold_interrupts_while_compiling
    from .numba_start import preload_cython_blas

    t0 = time.perf_counter()
    preload_cython_blas()  # a process's first kernel then loads without scipy.linalg (see navlab.numba_start)
    hold_interrupts_while_compiling()  # a Ctrl-C during the compile is not lost (navlab.compile_clock)
    _warm(planner, sampler, bool(on_map))
    return time.perf_counter() - t0
