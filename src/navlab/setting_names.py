"""Which planners and samplers take a setting: the names of the grid algorithms', A* on a costmap's
and Hybrid A*'s settings, and a hint naming who takes a setting a query's planner does not
(:func:`taken_elsewhere`).

A module of its own because :mod:`navlab.queries` and :mod:`navlab.pose_queries` both read it: in either
of them, the other would import it, and the package's imports must not go round in a circle.
"""

from __future__ import annotations

from typing import Tuple

from .wording import listed

#: settings of the grid algorithms, routed by name like sampler settings
GRID_PARAMS = ("allow_unknown", "connectivity", "heuristic", "resolution", "smooth", "weight")
#: grid settings astar alone uses (the others search unweighted, with a note)
ASTAR_ONLY = ("weight",)
#: settings of A* on a Nav2-style costmap (``costmap=True``; see :func:`navlab.queries.costmap_query`)
COSTMAP_PARAMS = ("costmap", "inflation_radius", "cost_scaling_factor", "cost_travel_multiplier", "resolution",
                  "allow_unknown")
#: planners that plan between poses for a curvature-bounded robot
POSE_PLANNERS = ("hybrid_astar",)
#: tree planners that also plan between poses when ``motion`` is dubins or reeds_shepp
TREE_POSE_PLANNERS = ("rrt", "rrt_star", "informed_rrt_star")
#: the settings of every query between poses (Hybrid A*'s and a car-like tree's): its motion, robot and raster
CAR_QUERY_PARAMS = ("motion", "turning_radius", "footprint", "resolution", "allow_unknown")
#: settings of ``hybrid_astar`` (see :func:`navlab.grid.hybrid_astar.plan_hybrid`), plus the query's own
HYBRID_PARAMS = (*CAR_QUERY_PARAMS, "heading_bins",
                 "reverse_penalty", "change_penalty", "non_straight_penalty", "analytic_expansion",
                 "analytic_expansion_max_length", "analytic_expansion_ratio", "max_expansions", "smooth",
                 "waypoint_spacing", "exact_retry", "distance_table", "weight")
#: the settings of ``hybrid_astar`` that no other planner takes (an experiment's shared ones go to it alone):
#: all but the grid planners' and those a car-like tree's query takes too
HYBRID_ONLY = tuple(k for k in HYBRID_PARAMS if k not in GRID_PARAMS and k not in CAR_QUERY_PARAMS and
                    k != "heading_bins")


def car_tree_params() -> Tuple[str, ...]:
    """The settings of a tree planner between poses: the query's (:data:`CAR_QUERY_PARAMS`) and the SE(2)
    tree's (:data:`~navlab.sampling.se2_planners.SE2_TREE_PARAMS`)."""
    from .sampling.se2_planners import SE2_TREE_PARAMS  # (when asked: this module loads without the trees')

    return (*CAR_QUERY_PARAMS, *SE2_TREE_PARAMS)


def setting_hint(key: str, planner: str, valid, sampler: str = "") -> str:
    """The hint after an unknown setting: who takes it (:func:`taken_elsewhere`), else the nearest setting
    name, the planner's own or another's, with who takes that. "smoth" given to rrt_star was asked "Did you
    mean 'motion'?", its own nearest name (attack, session 21).

    Parameters
    ----------
    key : str
        The setting given.
    planner : str
        The planner it was given to.
    valid : sequence of str
        The settings the query takes.
    sampler : str, optional
        A tree planner's sampler.

    Returns
    -------
    str
        `` Did you mean 'x'?`` and/or `` 'x' is a setting of ...``, or "" when nothing is near.
    """
    from .registry import closest

    elsewhere = taken_elsewhere(key, planner, sampler)
    if elsewhere or not isinstance(key, str):
        return elsewhere
    close = closest(key, list(valid) + _every_setting())
    if close is None:
        return ""
    return f" Did you mean '{close}'?" + ("" if close in valid else taken_elsewhere(close, planner, sampler))


def _every_setting() -> list:
    """Every setting name some planner, sampler or query takes."""
    from .registry import parameters_of
    from .sampling.planners import PLANNERS
    from .sampling.samplers import SAMPLERS

    names = set(GRID_PARAMS) | set(COSTMAP_PARAMS) | set(HYBRID_PARAMS)
    for registry in (PLANNERS, SAMPLERS):
        for name in registry.names():
            names |= set(parameters_of(registry.get(name)))
    return sorted(names - {"sampler", "self"})


def taken_elsewhere(key: str, planner: str, sampler: str = "", own: str = "") -> str:
    """A hint naming the planners and samplers that do take ``key`` (`` 'smooth' is a setting of the grid
    planners (...) and planner hybrid_astar, not of planner rrt_star.``), or "" when none does. Rather than
    the nearest name: --param smooth=true with rrt_star was asked "Did you mean 'motion'?" (newcomer check,
    session 20). ``own``: who does not take it, as the sentence ends (else ``planner`` and ``sampler``)."""
    # (here, not at the top: the hint is for a mistake, and the grid search's module loads its kernels)
    from .grid.planner import GRID_ALGORITHMS
    from .registry import parameters_of
    from .sampling.planners import PLANNERS
    from .sampling.samplers import SAMPLERS

    planners_keys = {k for name in PLANNERS.names() for k in parameters_of(PLANNERS.get(name))}
    planners = [name for name in PLANNERS.names() if key in parameters_of(PLANNERS.get(name))]
    planners += [name for name in POSE_PLANNERS if key in HYBRID_PARAMS]
    samplers = [name for name in SAMPLERS.names() if key in parameters_of(SAMPLERS.get(name))]
    takers = []
    if key in ASTAR_ONLY:
        planners.insert(0, "astar")  # (named with the others: "planners astar and hybrid_astar")
    elif key in GRID_PARAMS:
        takers.append(f"the grid planners ({', '.join(GRID_ALGORITHMS.names())})")
    if key == "costmap":  # (not "a setting of planner astar with costmap=true")
        takers.append("planner astar")
    elif key in COSTMAP_PARAMS and key not in GRID_PARAMS:
        takers.append("planner astar with costmap=true")
    # a car-like tree's: its lattice's heading_bins, and the query's motion, turning radius, footprint and raster
    # (astar was told turning_radius was hybrid_astar's alone: review, session 22)
    car_tree = car_tree_params()
    if key in car_tree and key not in planners_keys:
        takers.append(f"planners {listed(sorted(TREE_POSE_PLANNERS))}"
                      + ("" if key == "motion" else " with motion=dubins or reeds_shepp"))
    if planners:
        takers.append(f"planner{'s' if len(planners) > 1 else ''} {listed(planners)}")
    if samplers:
        takers.append(f"the {listed(samplers)} sampler{'s' if len(samplers) > 1 else ''}")
    if not takers:
        return ""
    own = own or f"planner {planner}" + (f" with the {sampler} sampler" if sampler else "")
    if planner in TREE_POSE_PLANNERS and key in car_tree and key not in planners_keys:
        own = f"planner {planner} with holonomic motion"  # (what is missing is the motion, not a sampler)
    return f" '{key}' is a setting of {listed(takers)}, not of {own}."
