"""Built-in experiment suites (``navlab bench --suite NAME``), as plain data
in the experiment-file format (``navlab bench --suite NAME --show`` prints
one as YAML to start your own from)."""

from __future__ import annotations

from typing import Any, Callable, Dict

from ..registry import Registry

SUITES: Registry[Callable[[], Dict[str, Any]]] = Registry("suite")


@SUITES.register("seed000")
def seed000() -> Dict[str, Any]:
    """Seed 000: RRT* with five samplers in three environments, 20 trials
    each, stopping at max_iter only (as the seed did)."""
    return {
        "name": "seed000",
        "description": "RRT* with the integration, Gaussian and boundary samplers (uniform and goal "
                       "bias as baselines) in clutter, SquareField BW and trap; 20 trials each, "
                       "stop at max_iter (seed 000, Tables I-VI).",
        "worlds": ["clutter", "squarefield", "trap"],
        "planners": ["rrt_star"],
        "samplers": ["integration", "gaussian", "boundary", "uniform", "goal_bias"],
        "budget": {"max_iter": 5000},
        "trials": 20,
        "seed": 0,
        "claims": [
            {"text": "integration gives shorter paths than Gaussian", "metric": "cost",
             "lower": "integration", "higher": "gaussian"},
            {"text": "integration gives shorter paths than boundary", "metric": "cost",
             "lower": "integration", "higher": "boundary"},
            {"text": "integration is faster than Gaussian", "metric": "time_s",
             "lower": "integration", "higher": "gaussian"},
            {"text": "boundary is faster than integration and Gaussian", "metric": "time_s",
             "lower": "boundary", "higher": ["integration", "gaussian"]},
            {"text": "plain random (uniform) sampling is faster than boundary", "metric": "time_s",
             "lower": "uniform", "higher": "boundary"},
            {"text": "plain random (uniform) sampling gives longer paths than integration", "metric": "cost",
             "lower": "integration", "higher": "uniform"},
        ],
    }


@SUITES.register("seed003")
def seed003() -> Dict[str, Any]:
    """Seed 003: the growth-ratio RRT against RRT with a fixed step, iterations
    to reach the goal and path length over 100 seeds, on the seed's set-up
    and on the other scenes."""
    return {
        "name": "seed003",
        "description": "Growth-ratio RRT vs. fixed-step RRT (steps 0.2 m and 0.5 m): iterations to "
                       "reach p_min of the goal and path length (seed 003).",
        "worlds": ["growth_ratio", "clutter", "squarefield", "trap"],
        "planners": ["growth_ratio_rrt",
                     {"name": "rrt", "expand_dis": 0.2, "label": "rrt_step0.2"},
                     {"name": "rrt", "expand_dis": 0.5, "label": "rrt_step0.5"}],
        "samplers": ["uniform"],
        "budget": {"max_iter": 5000},
        "trials": 100,
        "seed": 3,
        "claims": [
            {"text": "the growth ratio reaches the goal in fewer iterations than a 0.2 m fixed step",
             "metric": "first_solution_iteration", "lower": "growth_ratio_rrt", "higher": "rrt_step0.2"},
            {"text": "the growth ratio reaches the goal in fewer iterations than a 0.5 m fixed step",
             "metric": "first_solution_iteration", "lower": "growth_ratio_rrt", "higher": "rrt_step0.5"},
        ],
    }


@SUITES.register("anchors")
def anchors() -> Dict[str, Any]:
    """navlab's RRT* and Informed RRT* beside OMPL's planners (``ompl``
    extra) on the same worlds, budgets and exact collision checker."""
    return {
        "name": "anchors",
        "description": "navlab RRT* / Informed RRT* vs OMPL RRTstar / InformedRRTstar / RRTConnect, "
                       "5000 iterations (RRTConnect stops at its first solution).",
        "worlds": ["pythonrobotics", "clutter", "trap"],
        "planners": ["rrt_star", "informed_rrt_star", "ompl:RRTstar", "ompl:InformedRRTstar", "ompl:RRTConnect"],
        "samplers": ["uniform"],
        "budget": {"max_iter": 5000, "max_time": 20.0},
        "trials": 10,
        "seed": 0,
    }


@SUITES.register("smoke")
def smoke() -> Dict[str, Any]:
    """A tiny suite that runs in seconds (the tests and a first try)."""
    return {
        "name": "smoke",
        "description": "Two samplers, two worlds, 4 trials of 300 iterations.",
        "worlds": ["squarefield", "trap"],
        "planners": ["rrt_star"],
        "samplers": ["integration", "uniform"],
        "budget": {"max_iter": 300},
        "trials": 4,
        "seed": 0,
    }
