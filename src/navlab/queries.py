"""The two kinds of planning query, without warm-up: a tree planner on a
world's exact checker (:func:`tree_query`) and a grid algorithm on its
conservative raster (:func:`grid_query`), and how parameters are routed to a
planner and its sampler by name.

:func:`navlab.plan` warms the kernels up first and then calls these;
:mod:`navlab.warmup` calls them directly (it is what warming up runs).
"""

from __future__ import annotations

import time
from typing import Any, Dict, Optional, Tuple

import numpy as np

from .errors import ParameterError
from .limits import MIN_LENGTH, check_flag, check_length, is_finite_real, shown
from .registry import UnknownNameError, parameters_of, suggest
from .result import Result, Status, Tree
from .sampling.planners import PLANNERS, make_planner
from .sampling.samplers import SAMPLERS, GoalBiasSampler, Sampler, make_sampler
from .setting_names import COSTMAP_PARAMS, GRID_PARAMS, setting_hint



#: [m] consecutive path points closer than this are one point (a cell centre computed two ways)
_SAME_POINT = 1e-9
#: settings of the query rather than of a planner, which every tree planner's --param takes
#: (planning.plan reads them before the planner's own; "did you mean" looks among them too)
#: the query's own settings a grid planner takes besides :data:`~navlab.setting_names.GRID_PARAMS`
#: (``robot_radius`` is navlab.plan's argument, and ``--param robot_radius=`` reaches it: a refusal that left it
#: out suggested turning_radius for 'radius')
GRID_QUERY_PARAMS = ("goal_tolerance", "robot_radius")
#: the query's own settings a tree planner's refusal names
QUERY_PARAMS = ("motion", "turning_radius", "footprint", *GRID_QUERY_PARAMS)
QUERY_PARAMS_HELP = ("motion (holonomic, dubins or reeds_shepp; the last two with turning_radius and footprint), "
                     + ", ".join(GRID_QUERY_PARAMS))


def planner_names() -> list[str]:
    """Every planner ``navlab.plan`` accepts: tree planners and grid algorithms."""
    from .grid.planner import GRID_ALGORITHMS
    from .pose_queries import POSE_PLANNERS

    return sorted(PLANNERS.names() + GRID_ALGORITHMS.names() + list(POSE_PLANNERS))


def is_grid_planner(name: str) -> bool:
    """Whether ``name`` is a grid algorithm (else a tree planner); unknown names
    raise :class:`~navlab.registry.UnknownNameError` listing both kinds. A tree
    planner's name is answered from the tree registry first, without importing
    the grid search (its module and compiled kernels, which a tree query never
    calls; the two registries share no name)."""
    if name in PLANNERS:
        return False
    from .grid.planner import GRID_ALGORITHMS

    if name in GRID_ALGORITHMS:
        return True
    valid = planner_names()
    # (an OMPL planner is a benchmark anchor only: --planner ompl:RRTstar was 'unknown planner' without a word)
    ompl = " OMPL's planners (ompl:NAME) run in navlab bench only." if str(name).startswith("ompl:") else ""
    raise UnknownNameError(f"unknown planner '{name}'; valid: {', '.join(valid)}." + suggest(str(name), valid)
                           + ompl)


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
        elif key in ("turning_radius", "footprint"):  # a car's settings, here without a car's motion
            from .pose_queries import POSE_PLANNERS, TREE_POSE_PLANNERS

            if planner in TREE_POSE_PLANNERS:
                raise UnknownNameError(f"{key} applies only with motion dubins or reeds_shepp (add motion=reeds_shepp "
                                       f"or motion=dubins); planner '{planner}' plans for a holonomic point robot "
                                       "here (its size: robot_radius)")
            raise UnknownNameError(f"{key} applies only with motion dubins or reeds_shepp, which planner '{planner}' "
                                   f"does not plan for (the planners that do: "
                                   f"{', '.join(POSE_PLANNERS + TREE_POSE_PLANNERS)}); it plans for a holonomic "
                                   "point robot (its size: robot_radius)")
        else:
            valid = sorted(planner_keys | sampler_keys | {"goal_sample_rate"})
            raise UnknownNameError(f"unknown parameter '{key}' for planner '{planner}' with sampler '{sampler}'; "
                                   f"valid: {', '.join(valid)}; and for the query: {QUERY_PARAMS_HELP}."
                                   + setting_hint(key, planner, valid + list(QUERY_PARAMS), sampler))
    return to_planner, to_sampler


def split_grid_params(planner: str, params: dict) -> dict:
    """Check that every parameter is a grid setting ("did you mean" otherwise)
    with a value it can take (:func:`navlab.grid.settings.check_grid_settings`)."""
    from .grid.settings import check_grid_settings

    for key in params:
        if key not in GRID_PARAMS:
            raise UnknownNameError(f"unknown parameter '{key}' for grid planner '{planner}'; "
                                   f"valid: {', '.join(GRID_PARAMS)}; for the query: {', '.join(GRID_QUERY_PARAMS)}; "
                                   "and costmap=true for A* on a costmap."
                                   + setting_hint(key, planner, [*GRID_PARAMS, *GRID_QUERY_PARAMS, "costmap"]))
    checked = check_grid_settings({**params, "algorithm": planner})  # (the algorithm's own rules too)
    checked.pop("algorithm")
    return checked


def check_tree_allow_unknown(world, allow_unknown: Optional[bool]) -> None:
    """Refuse ``allow_unknown`` for a tree planner's query on a geometric ``world`` (it has no unknown cells;
    a grid planner takes it for its raster). :func:`navlab.plan` and the bench's check both ask here (the
    bench ran every trial of such a cell as an ERROR row: attack, session 23)."""
    if allow_unknown is not None and world.occupancy is None:
        raise ParameterError("allow_unknown applies to maps; this source is a geometric world")


def take_query_params(params: dict, grid: bool) -> Tuple[Optional[float], Optional[bool]]:
    """Remove from a point planner's ``params`` the query's own settings, checked, and return them:
    ``(goal_tolerance, allow_unknown)``, None where not given. ``motion=holonomic`` (every point planner's)
    goes too; a grid planner keeps ``allow_unknown``, one of its own settings, and a tree planner's goes to
    its world. :func:`navlab.plan` and the bench's check of an experiment both split them here (they had a
    copy each: review, session 22)."""
    if params.get("motion") == "holonomic":
        params.pop("motion")
    goal_tolerance = params.pop("goal_tolerance", None)
    allow_unknown = params.get("allow_unknown") if grid else params.pop("allow_unknown", None)
    if goal_tolerance is not None:
        check_length("goal_tolerance", goal_tolerance)
    if allow_unknown is not None:
        allow_unknown = check_flag("allow_unknown", allow_unknown)
    return goal_tolerance, allow_unknown


def take_sampler_params(sampler: str, params: dict) -> dict:
    """Remove from ``params`` and return the settings of ``sampler`` (and ``goal_sample_rate``): a car-like
    tree's query splits them off so, before its own settings are checked (``navlab.plan`` and the bench's
    checks alike)."""
    keys = set(parameters_of(SAMPLERS.get(sampler))) | {"goal_sample_rate"}
    return {k: params.pop(k) for k in list(params) if k in keys}


def build_sampler(sampler: str, params: dict) -> Sampler:
    params = dict(params)
    rate = params.pop("goal_sample_rate", None) if "goal_sample_rate" not in parameters_of(SAMPLERS.get(sampler)) else None
    base = make_sampler(sampler, **params)
    if rate is None:
        return base
    wrapped = GoalBiasSampler(goal_sample_rate=rate, base=base)
    wrapped.registered_name = f"goal_bias({sampler})"  # type: ignore[attr-defined]
    return wrapped


def tree_query(world, planner: str, sampler: str, seed: Any, params: dict) -> Result:
    """A tree planner on ``world`` (its exact checker), without warm-up."""
    to_planner, to_sampler = split_params(planner, sampler, params)
    samp = build_sampler(sampler, to_sampler)
    result = make_planner(planner, sampler=samp, **to_planner).plan(world, seed)
    result.params.update(samp.resolved_params(world))
    # the query's own settings it ran with, which a bench row's params_used left out (newcomer, session 22)
    result.params.update(goal_tolerance=float(world.goal_tolerance), allow_unknown=bool(world.allow_unknown))
    return result


def _with_defaults(grid_plan, settings: dict) -> dict:
    """``settings`` with the grid planner's defaults for those not given (heuristic, connectivity, smooth,
    weight), so a result's params say every setting it ran with (they listed only the given ones); a
    weight as a float (3 and 3.0 alike)."""
    used = {name: default for name, default in parameters_of(grid_plan).items()
            if name in ("heuristic", "connectivity", "smooth", "weight")}
    used.update(settings)
    used["weight"] = float(used["weight"])
    return used


def grid_query(world, algorithm: str, params: dict) -> Result:
    """A grid algorithm on ``world``'s conservative raster (a map: its own
    cells), joined to the exact start and goal by checked straight legs."""
    from .endpoints import attach
    from .grid.planner import as_searched, plan as grid_plan, unknown_hint
    from .grid.rasterize import rasterize

    t0 = time.perf_counter()
    settings = dict(params)
    resolution = settings.pop("resolution", None)
    allow_unknown = settings.pop("allow_unknown", False)  # already applied to the world
    grid = rasterize(world, resolution)
    rasterize_s = time.perf_counter() - t0
    passable = ~grid.blocked
    checker = world.checker()
    out_params = {"algorithm": algorithm, "resolution": grid.resolution,
                  **as_searched(algorithm, **_with_defaults(grid_plan, settings)), "allow_unknown": allow_unknown}
    stats: Dict[str, Any] = {"grid": f"{grid.width}x{grid.height}", "rasterize_s": rasterize_s}
    ends = np.array([world.start, world.goal], dtype=float)
    own = [tuple(int(v) for v in c) for c in grid.world_to_cell(ends)]
    if own[0] == own[1] and checker.segments_free(ends[:1], ends[1:])[0]:
        # both ends in one cell, the straight leg between them free: that leg is the path (start == goal:
        # the start alone), whether or not the conservative raster leaves the cell a free centre
        path = _without_repeats(ends)
        stats.update({"expanded": 0, "cost_cells": 0.0, "collision_checks": checker.checks,
                      "time_s": time.perf_counter() - t0})
        return Result(status=Status.EXACT, path=path, cost=path_length(path), stats=stats, params=out_params,
                      tree=Tree().with_raster(grid))
    cells = {}
    for (label, point, status), cell in zip((("start", world.start, Status.INVALID_START),
                                             ("goal", world.goal, Status.INVALID_GOAL)), own):
        cells[label] = attach(world, grid, passable, point, checker)
        if cells[label] is None:
            stats["time_s"] = time.perf_counter() - t0
            remedy = ("a map is planned on its own cells: a smaller robot radius or a tree planner may reach it"
                      if world.occupancy is not None else "try a finer resolution")
            return Result(status=status, params=out_params, stats=stats,
                          reason=f"{label} ({point[0]:g}, {point[1]:g}) in cell {cell} is free but reaches no free grid "
                                 f"cell centre nearby in a straight line at resolution {grid.resolution:g} m "
                                 f"(cells within the robot radius of an obstacle are blocked); {remedy}")
    r = grid_plan(grid, cells["start"], cells["goal"], algorithm=algorithm, smooth_method="supercover", **settings)
    stats.update(r.stats)
    stats.pop("length_m", None)  # the centre-to-centre part only; cost is the whole path's length
    stats["rasterize_s"] = rasterize_s
    if not r.success:
        stats["time_s"] = time.perf_counter() - t0
        # the raster holds the map's unknown cells as blocked: say so, as navlab grid plan does
        hint = unknown_hint(world.occupancy, world.allow_unknown) if world.occupancy is not None else ""
        return Result(status=Status.FAILED, params=out_params, stats=stats, reason=r.reason + hint, cells=r.cells)
    stats["cost_cells"] = float(r.stats.get("cost_cells", r.cost))
    # (ends joined to one centre: the trim leaves the straight leg between them where it is free)
    path = _without_repeats(_trimmed_ends(np.vstack((world.start, r.path, world.goal)), checker))
    # The raster is conservative, so the cell-to-cell legs are free by
    # construction (and attach() checked the two end legs against the map's
    # squares); one exact check of the whole path guards that promise.
    bad = np.flatnonzero(~checker.segments_free(path[:-1], path[1:])) if len(path) > 1 else []
    stats["collision_checks"] = checker.checks
    stats["time_s"] = time.perf_counter() - t0
    if len(bad):
        return Result(status=Status.FAILED, params=out_params, stats=stats, cells=r.cells,
                      reason=_leg_not_free("grid", path, int(bad[0])))
    cost = path_length(path)
    tree = (r.tree or Tree()).with_raster(grid)
    return Result(status=Status.EXACT, path=path, cost=cost, stats=stats, params=out_params, cells=r.cells, tree=tree)


def _trimmed_ends(path: np.ndarray, checker) -> np.ndarray:
    """``path`` (start, cell centres, goal) without the centre the start or the goal was joined to
    when the straight leg past it is free: joining an end to its nearest free centre can lead away
    from the other end (a point on a cell corner joins the lower-left cell whichever way the goal
    lies), and the leg past that centre is then shorter."""
    if len(path) >= 3 and checker.segments_free(path[:1], path[2:3])[0]:
        path = np.delete(path, 1, axis=0)
    if len(path) >= 3 and checker.segments_free(path[-3:-2], path[-1:])[0]:
        path = np.delete(path, -2, axis=0)
    return path


def _without_repeats(path: np.ndarray) -> np.ndarray:
    """``path`` without a point on the one before (an end that is its cell's centre, up to the
    centre's rounding), keeping the exact start and goal: a centre on the goal gives way to it."""
    keep = np.ones(len(path), dtype=bool)
    keep[1:] = np.hypot(*np.diff(path, axis=0).T) > _SAME_POINT
    if len(path) > 1 and not keep[-1]:
        keep[-1] = not np.array_equal(path[0], path[-1]) or len(path) > 2
        if len(path) > 2:
            keep[-2] = False
    return path[keep]


def check_costmap_settings(algorithm: str, params: dict, robot_radius: Optional[float] = None) -> None:
    """Refuse a setting of A* on a costmap (``costmap=True``) that :func:`costmap_query` would: a planner
    other than astar, an unknown name, a value out of range, and, given the world's ``robot_radius``, an
    inflation radius below it. The bench checks an experiment with it before any trial (its trials of
    ``{name: astar, costmap: true}`` were refused by a line listing costmap=true as valid: attack, session 22)."""
    from .grid.cost_search import DEFAULT_COST_TRAVEL_MULTIPLIER
    from .grid.settings import check_grid_settings
    from .world.costmap import (DEFAULT_COST_SCALING_FACTOR, DEFAULT_INFLATION_RADIUS, check_costmap_resolution,
                                check_inflation)

    if algorithm != "astar":
        raise ParameterError(f"costmap: only astar plans on a costmap's costs, got '{algorithm}'")
    unknown = sorted(set(params) - set(COSTMAP_PARAMS))
    if unknown:
        raise UnknownNameError(f"unknown parameter '{unknown[0]}' with costmap=true; valid: "
                               f"{', '.join(COSTMAP_PARAMS)}." + suggest(unknown[0], list(COSTMAP_PARAMS)))
    check_grid_settings({k: params[k] for k in ("allow_unknown",) if k in params})
    if params.get("resolution") is not None:
        check_costmap_resolution(params["resolution"])
    check_inflation(params.get("inflation_radius", DEFAULT_INFLATION_RADIUS),
                    params.get("cost_scaling_factor", DEFAULT_COST_SCALING_FACTOR),
                    None if robot_radius is None else max(robot_radius, MIN_LENGTH))  # (the query's disc)
    multiplier = params.get("cost_travel_multiplier", DEFAULT_COST_TRAVEL_MULTIPLIER)
    if not is_finite_real(multiplier) or multiplier < 0:  # (10**400: an OverflowError deeper down until session 18)
        raise ParameterError(f"cost_travel_multiplier must be a number ≥ 0, got {shown(multiplier)}")


def costmap_query(world, algorithm: str, params: dict) -> Result:
    """A* over the world's Nav2-style costmap (``costmap=True``): the static layer (the map's
    cells, or the world rasterised), inflated for a disc of the world's robot radius with Nav2's
    formula, step costs weighted by cell cost (:mod:`navlab.grid.cost_search`). The returned
    path is checked against the exact world before it is returned."""
    from .grid.cost_search import DEFAULT_COST_TRAVEL_MULTIPLIER, plan_on_costmap
    from .world.costmap import DEFAULT_COST_SCALING_FACTOR, DEFAULT_INFLATION_RADIUS, LayeredCostmap
    from .world.footprint import Footprint

    check_costmap_settings(algorithm, params)
    t0 = time.perf_counter()
    settings = {"inflation_radius": params.get("inflation_radius", DEFAULT_INFLATION_RADIUS),
                "cost_scaling_factor": params.get("cost_scaling_factor", DEFAULT_COST_SCALING_FACTOR)}
    multiplier = params.get("cost_travel_multiplier", DEFAULT_COST_TRAVEL_MULTIPLIER)
    footprint = Footprint.disc(max(world.robot_radius, MIN_LENGTH))
    source = world.occupancy if world.occupancy is not None else world
    layers = LayeredCostmap(source, footprint, resolution=params.get("resolution"), **settings)
    costmap = layers.static_costmap()
    built_s = time.perf_counter() - t0
    searched: Dict[str, Any] = {}
    allow_unknown = bool(params.get("allow_unknown", False))
    path, weighted, reason = plan_on_costmap(costmap, world.start, world.goal, float(multiplier), allow_unknown,
                                             stats=searched)
    out_params = {"algorithm": algorithm, "costmap": True, "resolution": costmap.resolution,
                  "cost_travel_multiplier": float(multiplier), "allow_unknown": allow_unknown, **settings}
    # rasterize_s: building the costmap (the static layer, rasterised, and its inflation), as a grid query's raster
    stats: Dict[str, Any] = {"grid": f"{costmap.shape[1]}x{costmap.shape[0]}", "costmap_cost_m": weighted,
                             "expanded": searched.get("expanded", 0), "rasterize_s": built_s}
    if path is None:
        stats["time_s"] = time.perf_counter() - t0
        return Result(status=Status.FAILED, params=out_params, stats=stats, reason=reason)
    checker = world.checker()
    bad = np.flatnonzero(~checker.segments_free(path[:-1], path[1:]))
    stats["collision_checks"] = checker.checks
    stats["time_s"] = time.perf_counter() - t0
    if len(bad):
        return Result(status=Status.FAILED, params=out_params, stats=stats,
                      reason=_leg_not_free("costmap", path, int(bad[0])))
    stats["cost_cells"] = stats["raw_cost_cells"] = path_length(path) / costmap.resolution  # as a grid query's
    return Result(status=Status.EXACT, path=path, cost=path_length(path), stats=stats, params=out_params)


def _leg_not_free(kind: str, path: np.ndarray, i: int) -> str:
    """Why a grid or costmap path failed the exact check: its leg ``i`` (in metres, as plain numbers: the
    message showed ``np.float64(5.275)``, attack run of session 18)."""
    a, b = path[i], path[i + 1]
    return (f"the {kind} path's leg {i} from ({a[0]:.6g}, {a[1]:.6g}) to ({b[0]:.6g}, {b[1]:.6g}) is not free in "
            "the exact world")


def path_length(path) -> float:
    """Length (m) of a polyline (0 for fewer than two points)."""
    p = np.asarray(path, dtype=float)
    return float(np.sum(np.hypot(*np.diff(p, axis=0).T))) if len(p) > 1 else 0.0

