"""``navlab.plan``: one call from any source, with any planner, to a Result.

Sources (see :mod:`navlab.world.sources`): a scene name, a world YAML, a ROS
map_server YAML, a Moving AI ``.map``, a :class:`~navlab.world.World` or an
:class:`~navlab.grid.OccupancyGrid`. Planners: every registered tree planner
(:data:`navlab.sampling.PLANNERS`) and every grid algorithm
(:data:`navlab.grid.GRID_ALGORITHMS`), seen as one list
(:func:`planner_names`). Tree planners search the world itself through its
exact checker; grid planners search its conservative raster
(:mod:`navlab.grid.rasterize`) and join the exact start and goal to it.

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

from .registry import UnknownNameError, parameters_of, suggest
from .result import Result, Status
from .sampling.planners import PLANNERS, make_planner
from .sampling.samplers import SAMPLERS, GoalBiasSampler, Sampler, make_sampler

#: settings of the grid algorithms, routed by name like sampler settings
GRID_PARAMS = ("allow_unknown", "connectivity", "heuristic", "resolution", "smooth", "weight")


def planner_names() -> list[str]:
    """Every planner ``navlab.plan`` accepts: tree planners and grid algorithms."""
    from .grid.planner import GRID_ALGORITHMS

    return sorted(PLANNERS.names() + GRID_ALGORITHMS.names())


def is_grid_planner(name: str) -> bool:
    """Whether ``name`` is a grid algorithm (else a tree planner); unknown names
    raise :class:`~navlab.registry.UnknownNameError` listing both kinds."""
    from .grid.planner import GRID_ALGORITHMS

    if name in GRID_ALGORITHMS:
        return True
    if name in PLANNERS:
        return False
    valid = planner_names()
    raise UnknownNameError(f"unknown planner '{name}'; valid: {', '.join(valid)}." + suggest(str(name), valid))


def split_params(planner: str, sampler: str, params: dict) -> tuple[dict, dict]:
    """Route keyword parameters to the tree planner or the sampler by name.

    ``goal_sample_rate`` given with a sampler that has no such parameter wraps
    that sampler in goal bias (with that probability the goal is returned).
    """
    planner_keys = set(parameters_of(PLANNERS.get(planner))) - {"sampler"}
    sampler_keys = set(parameters_of(SAMPLERS.get(sampler)))
    to_planner, to_sampler = {}, {}
    for key, value in params.items():
        if key in planner_keys:
            to_planner[key] = value
        elif key in sampler_keys or key == "goal_sample_rate":
            to_sampler[key] = value
        else:
            valid = sorted(planner_keys | sampler_keys | {"goal_sample_rate"})
            raise ValueError(f"unknown parameter '{key}' for planner '{planner}' with sampler '{sampler}'; "
                             f"valid: {', '.join(valid)}." + suggest(key, valid))
    return to_planner, to_sampler


def split_grid_params(planner: str, params: dict) -> dict:
    """Check that every parameter is a grid setting; "did you mean" otherwise."""
    for key in params:
        if key not in GRID_PARAMS:
            raise ValueError(f"unknown parameter '{key}' for grid planner '{planner}'; "
                             f"valid: {', '.join(GRID_PARAMS)}." + suggest(key, list(GRID_PARAMS)))
    return dict(params)


def build_sampler(sampler: str, params: dict) -> Sampler:
    params = dict(params)
    rate = params.pop("goal_sample_rate", None) if "goal_sample_rate" not in parameters_of(SAMPLERS.get(sampler)) else None
    base = make_sampler(sampler, **params)
    if rate is None:
        return base
    wrapped = GoalBiasSampler(goal_sample_rate=rate, base=base)
    wrapped.registered_name = f"goal_bias({sampler})"  # type: ignore[attr-defined]
    return wrapped


# -- the two kinds of query (no warm-up: plan() does that first) ---------------

def tree_query(world, planner: str, sampler: str, seed: Any, params: dict) -> Result:
    """A tree planner on ``world`` (its exact checker), without warm-up."""
    to_planner, to_sampler = split_params(planner, sampler, params)
    samp = build_sampler(sampler, to_sampler)
    result = make_planner(planner, sampler=samp, **to_planner).plan(world, seed)
    result.params.update(samp.resolved_params(world))
    return result


def grid_query(world, algorithm: str, params: dict) -> Result:
    """A grid algorithm on ``world``'s conservative raster (a map: its own
    cells), joined to the exact start and goal by checked straight legs."""
    from .endpoints import attach
    from .grid.planner import plan as grid_plan
    from .grid.rasterize import rasterize

    t0 = time.perf_counter()
    settings = dict(params)
    resolution = settings.pop("resolution", None)
    settings.pop("allow_unknown", None)  # already applied to the world
    grid = rasterize(world, resolution)
    rasterize_s = time.perf_counter() - t0
    passable = ~grid.blocked
    checker = world.checker()
    out_params = {"algorithm": algorithm, "resolution": grid.resolution, **settings}
    stats: Dict[str, Any] = {"grid": f"{grid.width}x{grid.height}", "rasterize_s": rasterize_s}
    cells = {}
    for label, point, status in (("start", world.start, Status.INVALID_START), ("goal", world.goal, Status.INVALID_GOAL)):
        cells[label] = attach(world, grid, passable, point, checker)
        if cells[label] is None:
            own = tuple(int(v) for v in grid.world_to_cell(np.asarray(point, float)))
            stats["time_s"] = time.perf_counter() - t0
            return Result(status=status, params=out_params, stats=stats,
                          reason=f"{label} ({point[0]:g}, {point[1]:g}) in cell {own} is free but reaches no free grid "
                                 f"cell centre nearby in a straight line at resolution {grid.resolution:g} m "
                                 "(cells within the robot radius of an obstacle are blocked); try a finer resolution")
    r = grid_plan(grid, cells["start"], cells["goal"], algorithm=algorithm, smooth_method="supercover", **settings)
    stats.update(r.stats)
    stats.pop("length_m", None)  # the centre-to-centre part only; cost is the whole path's length
    stats["rasterize_s"] = rasterize_s
    if not r.success:
        stats["time_s"] = time.perf_counter() - t0
        return Result(status=Status.FAILED, params=out_params, stats=stats, reason=r.reason, cells=r.cells)
    stats["cost_cells"] = float(r.stats.get("cost_cells", r.cost))
    path = np.vstack((world.start, r.path, world.goal))
    keep = np.ones(len(path), dtype=bool)
    keep[1:] = np.any(np.diff(path, axis=0) != 0, axis=1)  # a point that is its cell's centre
    path = path[keep]
    # The raster is conservative, so the cell-to-cell legs are free by
    # construction (and attach() checked the two end legs against the map's
    # squares); one exact check of the whole path guards that promise.
    bad = np.flatnonzero(~checker.segments_free(path[:-1], path[1:])) if len(path) > 1 else []
    stats["collision_checks"] = checker.checks
    stats["time_s"] = time.perf_counter() - t0
    if len(bad):
        i = int(bad[0])
        return Result(status=Status.FAILED, params=out_params, stats=stats, cells=r.cells,
                      reason=f"the grid path's leg {i} from {tuple(np.round(path[i], 6))} to "
                             f"{tuple(np.round(path[i + 1], 6))} is not free in the exact world")
    cost = path_length(path)
    tree = dict(r.tree) if isinstance(r.tree, dict) else {}
    tree["raster"] = grid
    return Result(status=Status.EXACT, path=path, cost=cost, stats=stats, params=out_params, cells=r.cells, tree=tree)


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
        ``growth_ratio_rrt``) or a grid algorithm (``astar``, ``dijkstra``,
        ``jps``, ``theta_star``); see :func:`planner_names`.
    sampler : str or None
        A registered sampler for tree planners (None: ``uniform``); grid
        planners take none.
    start, goal : (x, y), optional
        Metres; override the source's own. Required for maps (they have none).
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
        planners always end exactly at the goal). Routed by name; an unknown name is an error listing the valid
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
    ValueError
        Bad source, missing start/goal for a map
        (:class:`~navlab.world.sources.MissingQueryError`), unknown planner,
        sampler or parameter, bad value. An unusable start or goal is not an
        error but ``INVALID_START`` / ``INVALID_GOAL`` with the reason.
    """
    from .endpoints import endpoint_problem
    from .world.sources import load_source

    grid = is_grid_planner(planner)
    params = dict(params)
    goal_tolerance = params.pop("goal_tolerance", None)  # a property of the query, for every planner
    allow_unknown = params.get("allow_unknown") if grid else params.pop("allow_unknown", None)
    if grid:
        if sampler not in (None, "uniform"):
            SAMPLERS.get(sampler)
            raise ValueError(f"sampler: grid planner '{planner}' draws no samples; leave the sampler out "
                             f"(got '{sampler}')")
        settings = split_grid_params(planner, params)
    else:
        sampler = sampler or "uniform"
        SAMPLERS.get(sampler)
        split_params(planner, sampler, params)  # unknown names fail before any file is read
    world = load_source(source, start=start, goal=goal, robot_radius=robot_radius, goal_tolerance=goal_tolerance,
                        allow_unknown=allow_unknown)
    if allow_unknown is not None and world.occupancy is None and not grid:
        raise ValueError("allow_unknown applies to maps; this source is a geometric world")
    common = {"planner": planner, "sampler": None if grid else sampler,
              "seed": seed if isinstance(seed, int) else None, "world": world.name,
              "robot_radius": world.robot_radius}

    checker = world.checker()
    for label, point, status in (("start", world.start, Status.INVALID_START), ("goal", world.goal, Status.INVALID_GOAL)):
        why = endpoint_problem(world, point, label, checker)
        if why is not None:
            result = Result(status=status, reason=why, params=dict(params), stats=_stats_skeleton(grid))
            result.params.update(common)
            return result

    warmup_s = _warm(planner, sampler, settings if grid else None, on_map=world.occupancy is not None)
    result = grid_query(world, planner, settings) if grid else tree_query(world, planner, sampler, seed, params)
    result.stats = {**_stats_skeleton(grid), **result.stats, "warmup_s": warmup_s}
    result.params.update(common)
    return result


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


def path_length(path) -> float:
    """Length (m) of a polyline (0 for fewer than two points)."""
    p = np.asarray(path, dtype=float)
    return float(np.sum(np.hypot(*np.diff(p, axis=0).T))) if len(p) > 1 else 0.0

