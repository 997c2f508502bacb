"""``navlab.plan``: one call from any source, with any planner, to a Result.

Sources (see :mod:`navlab.world.sources`): a scene name, a world YAML, a ROS
map_server YAML, a Moving AI ``.map``, a :class:`~navlab.world.World` or an
:class:`~navlab.grid.OccupancyGrid`. Planners: every registered tree planner
(:data:`navlab.sampling.PLANNERS`) and every grid algorithm
(:data:`navlab.grid.GRID_ALGORITHMS`), seen as one list
(:func:`planner_names`). Tree planners search the world itself through its
exact checker; grid planners search its conservative raster
(:mod:`navlab.grid.rasterize`) and join the exact start and goal to it. The
heading-aware ``hybrid_astar`` plans between poses ``(x, y, θ)`` for a
robot with a footprint and a turning radius (:mod:`navlab.pose_queries`).

Whatever the pair, the Result's path starts at the start and ends at the goal
(or in the goal region), ``cost`` is its length in metres, and
``stats["warmup_s"]`` is the compile/cache-load time spent before the timed
query (never part of ``stats["time_s"]``).
"""

from __future__ import annotations

import functools
import math
import time
from typing import Any, Dict, Optional

import numpy as np

from .compile_clock import compile_clock, first_call_seconds, hold_interrupts_while_compiling
from .errors import ParameterError
from .limits import check_flag, check_seed, shown
from .pose_queries import POSE_PLANNERS, is_pose_query
from .queries import (GRID_PARAMS, build_sampler, check_tree_allow_unknown, costmap_query, grid_query,  # noqa: F401
                      is_grid_planner, path_length, planner_names, split_grid_params, split_params, take_query_params,
                      take_sampler_params, tree_query)
from .result import Result, Status
from .sampling.planners import make_planner
from .sampling.samplers import SAMPLERS


def _warm(planner: str, sampler: Optional[str], grid_settings: Optional[dict], on_map: bool) -> float:
    """Seconds spent warming this query's kernels (0 once they are loaded).

    ``grid_settings`` is None for tree planners; for grid planners it picks
    the A* variant (compiled per connectivity and heuristic) to warm.
    """
    from .warmup import warm_up

    seconds = warm_up(planner, sampler or "uniform", on_map=on_map)
    if grid_settings is not None:
        t0 = time.perf_counter()
        _warm_grid_variant(planner, int(grid_settings.get("connectivity", 8)),
                           str(grid_settings.get("heuristic", "octile")), bool(grid_settings.get("smooth", False)))
        seconds += time.perf_counter() - t0
    return seconds


@functools.lru_cache(maxsize=None)
def _warm_grid_variant(planner: str, connectivity: int, heuristic: str, smooth: bool) -> None:
    """This variant through the whole grid_query path: a geometric world's
    raster, and a map with a robot radius (inflation, exact end legs)."""
    from .grid.occupancy import OccupancyGrid
    from .world import World
    from .world.scenes import SCENES

    settings = {"connectivity": connectivity, "heuristic": heuristic, "smooth": smooth}
    world = SCENES.get("trap")()
    blocked = np.zeros((8, 8), dtype=bool)
    blocked[2:6, 4] = True
    tiny_map = World.from_grid(OccupancyGrid(blocked, 1.0), (1.5, 3.5), (6.5, 3.5), robot_radius=0.25)
    try:
        grid_query(world, planner, {"resolution": world.bounds.diagonal / 20, **settings})
        grid_query(tiny_map, planner, settings)
    except ValueError:
        pass  # an invalid combination: the real query reports it


@functools.lru_cache(maxsize=None)
def _warm_costmap_kernels() -> float:
    """Seconds compiling or loading the costmap query's kernels (inflation, costmap A*, the exact
    check of the path), on a tiny map and a coarse geometric world; counted once per process."""
    from .grid.occupancy import OccupancyGrid
    from .world import World
    from .world.scenes import SCENES

    t0 = time.perf_counter()
    blocked = np.zeros((12, 12), dtype=bool)
    blocked[3:9, 6] = True
    costmap_query(World.from_grid(OccupancyGrid(blocked, 0.25), (0.6, 1.5), (2.4, 1.5), robot_radius=0.1), "astar",
                  {})
    trap = SCENES.get("trap")()
    costmap_query(trap, "astar", {"resolution": trap.bounds.diagonal / 20})
    return time.perf_counter() - t0


def plan(source: Any, planner: str = "rrt_star", sampler: Optional[str] = "uniform", start=None, goal=None,
         seed: Any = 0, robot_radius: Optional[float] = None, **params: Any) -> Result:
    """Plan a path from start to goal in ``source`` with any registered planner.

    Parameters
    ----------
    source : str, os.PathLike, World or OccupancyGrid
        A built-in scene name, a world YAML, a map_server YAML (PGM/PNG), a
        Moving AI ``.map``, a World or an OccupancyGrid.
    planner : str
        A tree planner (``rrt``, ``rrt_star``, ``informed_rrt_star``,
        ``growth_ratio_rrt``), a grid algorithm (``astar``, ``dijkstra``,
        ``jps``, ``theta_star``) or ``hybrid_astar`` (poses, a turning
        radius, a footprint); see :func:`planner_names`.
    sampler : str or None
        A registered sampler for tree planners (None: ``uniform``); grid
        planners take none.
    start, goal : (x, y) or (x, y, θ), optional
        Metres (and radians); override the source's own. Required for maps
        (they have none). The heading matters to ``hybrid_astar`` only
        (default: the world's, else pointing from start to goal).
    seed : int or numpy.random.Generator
        The same seed gives the same result, bit for bit.
    robot_radius : float, optional
        Metres; overrides the source's (maps: 0).
    **params
        Tree planner settings (``expand_dis``, ``max_iter``, ``max_time``,
        ``connect_circle_dist``, ``keep_tree``, ...) and sampler settings
        (``goal_sample_rate``, ``sigma``, ``weights``, ...); grid settings
        (``heuristic``, ``connectivity``, ``smooth``, ``weight``,
        ``resolution`` in metres per cell for geometric worlds, default 1/200 of
        the bounds' longer side); ``allow_unknown`` (maps: unknown cells are
        free); ``goal_tolerance`` (m, overrides the source's; maps: 0; grid
        planners always end exactly at the goal). ``costmap=True`` (astar) plans on a
        Nav2-style costmap instead: cells within the robot radius blocked, each metre
        weighted by ``1 + cost_travel_multiplier · cost / 252`` (settings
        ``inflation_radius`` 0.55 m, ``cost_scaling_factor`` 3.0, ``cost_travel_multiplier``
        2.0, ``resolution``: a map's own, else 0.05 m). ``hybrid_astar``: ``motion`` (``reeds_shepp``, forward and
        reverse, or ``dubins``, forward only), ``turning_radius`` (m, default 0.4),
        ``footprint`` (a radius or ``[[x, y], ...]`` in the body frame; default the world's,
        else a disc of the robot radius), ``resolution`` and the settings of
        :func:`navlab.grid.hybrid_astar.plan_hybrid`; ``motion=holonomic`` is every other
        planner's. Routed by name; an unknown name is an error listing the valid
        ones for that planner.

    Returns
    -------
    Result
        ``status``, ``path`` (from exactly ``start`` to ``goal``), ``cost``
        (path length, m), ``stats`` (``time_s`` without warm-up,
        ``warmup_s``; grid planners also ``cost_cells``, ``expanded``,
        ``rasterize_s``) and ``params``.

    Raises
    ------
    ParameterError
        Bad source, missing start/goal for a map
        (:class:`~navlab.world.sources.MissingQueryError`), unknown planner,
        sampler or parameter, bad value. An unusable start or goal is not an
        error but ``INVALID_START`` / ``INVALID_GOAL`` with the reason.
    """
    from .endpoints import endpoint_problem
    from .numba_start import preload_cython_blas
    from .world.sources import load_source

    preload_cython_blas()  # before the first kernel loads: numba's BLAS check then skips scipy.linalg
    hold_interrupts_while_compiling()  # a Ctrl-C during a first use's compile is not lost (navlab.compile_clock)
    if not isinstance(planner, str):
        raise ParameterError(f"planner must be a planner's name, got {planner!r}; see navlab.planner_names()")
    check_seed(seed)
    if sampler is not None and not isinstance(sampler, str):  # (0 and False were read as "uniform")
        raise ParameterError(f"sampler must be a sampler's name, got {shown(sampler)}; valid: "
                             f"{', '.join(SAMPLERS.names())}")
    params = dict(params)
    grid = planner not in POSE_PLANNERS and is_grid_planner(planner)  # unknown names: "did you mean"
    if is_pose_query(planner, params):  # a bad motion is named before any file is read
        if planner in POSE_PLANNERS and sampler not in (None, "uniform"):
            raise ParameterError(f"sampler: planner '{planner}' draws no samples; leave the sampler out")
        tree_sampler = None if planner in POSE_PLANNERS else "uniform" if sampler is None else sampler
        return _pose_plan(source, planner, tree_sampler, start, goal, seed, robot_radius, params)
    goal_tolerance, allow_unknown = take_query_params(params, grid)  # the query's, for every planner
    on_costs = check_flag("costmap", params.get("costmap", False))
    if not on_costs:
        params.pop("costmap", None)  # costmap=false: the planner's own query, as when it is left out
    if on_costs and not grid:
        raise ParameterError(f"costmap: only the grid planner astar plans on a costmap, not '{planner}'")
    if on_costs:
        if sampler not in (None, "uniform"):
            raise ParameterError(f"sampler: grid planner '{planner}' draws no samples; leave the sampler out")
        settings = dict(params)
    elif grid:
        if sampler not in (None, "uniform"):
            SAMPLERS.get(sampler)
            raise ParameterError(f"sampler: grid planner '{planner}' draws no samples; leave the sampler out "
                                 f"(got '{sampler}')")
        settings = split_grid_params(planner, params)
    else:
        sampler = "uniform" if sampler is None else sampler  # ("" is a name no registry holds: API attack, s. 29)
        SAMPLERS.get(sampler)
        # unknown names and bad values fail before any file is read or kernel loaded (a first compile takes a
        # while: expand_dis=-1 waited 23 s for it; newcomer run, session 21)
        to_planner, to_sampler = split_params(planner, sampler, params)
        make_planner(planner, sampler=build_sampler(sampler, to_sampler), **to_planner)
    world = load_source(source, start=start, goal=goal, robot_radius=robot_radius, goal_tolerance=goal_tolerance,
                        allow_unknown=allow_unknown)
    if not grid:
        check_tree_allow_unknown(world, allow_unknown)
    common = {"planner": planner, "sampler": None if grid else sampler,
              "seed": seed if isinstance(seed, int) else None, "world": world.name,
              "robot_radius": world.robot_radius}

    checker = world.checker()
    for label, point, status in (("start", world.start, Status.INVALID_START), ("goal", world.goal, Status.INVALID_GOAL)):
        why = endpoint_problem(world, point, label, checker)
        if why is not None:
            return _recorded(Result(status=status, reason=why, params=dict(params), stats=_stats_skeleton(grid)),
                             common, world)

    if on_costs:
        warmup_s = first_call_seconds(_warm_costmap_kernels)
        with compile_clock() as compiled:  # a signature the warm-up did not compile: warm-up too
            result = costmap_query(world, planner, settings)
        result.stats = {**_stats_skeleton(grid), **result.stats, "warmup_s": warmup_s}
        return compiled.moved_to_warmup(_recorded(result, common, world))
    warmup_s = _warm(planner, sampler, settings if grid else None, on_map=world.occupancy is not None)
    with compile_clock() as compiled:  # a signature the warm-up did not compile: warm-up too
        result = grid_query(world, planner, settings) if grid else tree_query(world, planner, sampler, seed, params)
    # a grid planner's own clock moved its compiles to its warmup_s already: add the warm-up above
    result.stats = {**_stats_skeleton(grid), **result.stats,
                    "warmup_s": warmup_s + (result.stats.get("warmup_s") or 0.0)}
    return compiled.moved_to_warmup(_recorded(result, common, world))


def _recorded(result: Result, common: Dict[str, Any], world) -> Result:
    """``result`` with what every query records: the query's settings (``common``) in its params, and
    the world it was planned in (``Result.world``, for ``plot_plan(result)``)."""
    result.params.update(common)
    result.world = world
    return result


def _pose_plan(source: Any, planner: str, sampler: Optional[str], start, goal, seed: Any,
               robot_radius: Optional[float], params: Dict[str, Any]) -> Result:
    """A planner between poses (see :mod:`navlab.pose_queries`): Hybrid A*,
    or a tree planner (``sampler`` given) with Dubins or Reeds–Shepp steering."""
    from .pose_queries import check_pose_query, check_radius_not_dropped, hybrid_query, tree_pose_query
    from .world.sources import load_source

    goal_tolerance = params.pop("goal_tolerance", None)
    if goal_tolerance not in (None, 0, 0.0):
        raise ParameterError(f"goal_tolerance: {planner} ends exactly at the goal pose; leave goal_tolerance out")
    if sampler is not None:
        samp = build_sampler(sampler, take_sampler_params(sampler, params))
    world = load_source(source, start=start, goal=goal, robot_radius=robot_radius,
                        allow_unknown=params.get("allow_unknown"))
    check_radius_not_dropped(world, robot_radius, params, planner)
    check_pose_query(world, planner, params, sampler or "")  # before the kernels load (a first compile: minutes)
    t0 = time.perf_counter()
    warm_pose_planner(planner if sampler is None else "se2_tree")
    warmup_s = time.perf_counter() - t0
    with compile_clock() as compiled:  # a signature the warm-up did not compile (a disc robot, ...): warm-up too
        result = hybrid_query(world, params) if sampler is None else tree_pose_query(world, planner, samp, seed, params)
    if sampler is None:
        skeleton = {"expansions": 0, "nodes": 0, "cusps": 0, "rasterize_s": 0.0}
    else:
        result.params.update(samp.resolved_params(world))
        skeleton = {"iterations": 0, "nodes": 0, "collision_checks": 0, "edge_checks": 0, "cusps": 0,
                    "first_solution_iteration": None, "first_solution_time_s": None, "rewires": 0,
                    "cost_trace": np.zeros(0)}
    result.stats = {**skeleton, **result.stats, "warmup_s": warmup_s}
    common = {"planner": planner, "sampler": sampler, "seed": seed if isinstance(seed, int) else None,
              "world": world.name, "robot_radius": world.robot_radius}
    return compiled.moved_to_warmup(_recorded(result, common, world))


@functools.lru_cache(maxsize=None)
def warm_pose_planner(planner: str) -> None:
    """Compile (or load) the kernels of a planner between poses (``hybrid_astar``
    or ``se2_tree``): a tiny query with each motion."""
    from .grid.occupancy import OccupancyGrid
    from .world import World

    blocked = np.zeros((24, 24), dtype=bool)
    blocked[6:18, 12] = True
    world = World.from_grid(OccupancyGrid(blocked, resolution=0.25, name="warm-up map"), (1.5, 3.0), (4.5, 3.0))
    box = [[0.2, 0.15], [-0.2, 0.15], [-0.2, -0.15], [0.2, -0.15]]
    for motion in ("reeds_shepp", "dubins"):
        if planner == "hybrid_astar":
            from .pose_queries import hybrid_query

            hybrid_query(world, {"motion": motion, "turning_radius": 0.5, "footprint": box, "max_expansions": 2000})
        else:
            from .pose_queries import tree_pose_query

            for name in ("rrt", "rrt_star"):
                tree_pose_query(world, name, build_sampler("uniform", {}), 0,
                                {"motion": motion, "turning_radius": 0.5, "footprint": box, "max_iter": 64})


def _stats_skeleton(grid: bool) -> Dict[str, Any]:
    """The stats every ``plan`` result of this kind of planner carries, whatever
    its status (a query that stopped early has them as zeros / ``inf`` / None)."""
    if grid:
        from .grid.planner import STATS_KEYS

        keys = dict.fromkeys(k for k in STATS_KEYS if k != "length_m")
        keys.update(expanded=0, cost_cells=math.inf, raw_cost_cells=math.inf, grid=None, rasterize_s=0.0,
                    collision_checks=0)
    else:
        keys = {"iterations": 0, "nodes": 0, "collision_checks": 0, "edge_checks": 0, "first_solution_iteration": None,
                "first_solution_time_s": None, "rewires": 0, "cost_trace": np.zeros(0)}
    keys.update(time_s=0.0, warmup_s=0.0)
    return keys
