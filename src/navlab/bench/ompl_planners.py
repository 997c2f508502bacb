"""OMPL's planners on navlab worlds, as a comparison baseline (``ompl`` extra).

OMPL sees the world through navlab's exact checker: states through
``points_free`` and motions through ``segments_free`` (a custom motion
validator), so both libraries solve the same problem and paths never clip
an obstacle. The budget is navlab's: ``max_iter`` counts OMPL's iterations
(a termination condition reading ``numIterations()``, where the planner has
it) and ``max_time`` is wall-clock time.

OMPL draws from its own generator, which can be seeded only once per
process before its first draw, so OMPL rows are not reproducible trial by
trial; the seed recorded with them is the one navlab would have used.

References
----------
I. A. Şucan, M. Moll, L. E. Kavraki, "The Open Motion Planning Library",
IEEE Robotics & Automation Magazine 19(4):72–82, 2012.
"""

from __future__ import annotations

import time
from typing import Any, Dict, Optional, Tuple

import numpy as np

from ..errors import ParameterError
from ..limits import check_length
from ..registry import UnknownNameError, suggest
from ..result import Result, Status
from ..sampling.planners import _check_query

#: OMPL geometric planners offered by name (``ompl:RRTstar``, ...).
OMPL_NAMES = ("RRT", "RRTConnect", "RRTstar", "InformedRRTstar", "PRMstar", "BITstar")


def check_ompl_name(name: str) -> None:
    if name not in OMPL_NAMES:
        named = [f"ompl:{n}" for n in OMPL_NAMES]  # (the hint as the name is written: 'ompl:PRMstar')
        raise UnknownNameError(f"unknown OMPL planner 'ompl:{name}'; valid: " + ", ".join(named) + "."
                               + suggest(f"ompl:{name}", named))


#: the settings navlab passes to an OMPL planner (``expand_dis``: its range; ``goal_tolerance``: the query's)
OMPL_PARAMS = ("expand_dis", "goal_tolerance")
#: the planners of :data:`OMPL_NAMES` that have a range (``setRange``), so take ``expand_dis``
RANGED = ("RRT", "RRTConnect", "RRTstar", "InformedRRTstar")
#: the planners of :data:`OMPL_NAMES` that count iterations (``numIterations``), so stop on ``max_iter``
COUNTING = ("RRTstar", "InformedRRTstar", "BITstar")


def ompl_params(name: str) -> Tuple[str, ...]:
    """The settings OMPL planner ``name`` takes (PRMstar and BITstar have no range)."""
    return OMPL_PARAMS if name in RANGED else ("goal_tolerance",)


def check_ompl_query(name: str, params: Dict[str, Any], budget: Dict[str, Any]) -> None:
    """Refuse what :func:`plan_ompl` would refuse, without planning: an OMPL planner's settings other than
    :func:`ompl_params`, a range that is not a positive length, and a budget with neither ``max_iter`` nor
    ``max_time`` (each trial was an ERROR row: review and attack, session 22)."""
    valid = ompl_params(name)
    unknown = sorted(set(params) - set(valid))
    if unknown:
        raise ParameterError(f"unknown parameter(s) {', '.join(unknown)} for ompl:{name}; valid: "
                             f"{', '.join(valid)}" + ("" if "expand_dis" in valid else " (it has no range)"))
    if "expand_dis" in params:
        check_length("expand_dis", params["expand_dis"], allow_zero=False)
    if params.get("goal_tolerance") is not None:
        check_length("goal_tolerance", params["goal_tolerance"])
    if budget.get("max_time") is None and name not in COUNTING:  # (first: it was told max_iter would do)
        raise ParameterError(f"budget: ompl:{name} does not count iterations; give it max_time")
    if budget.get("max_iter") is None and budget.get("max_time") is None:
        raise ParameterError(f"budget: ompl:{name} needs max_iter or max_time (an OMPL run stops on its budget)")


def ompl_available() -> bool:
    try:
        import ompl.geometric  # noqa: F401
    except ImportError:
        return False
    return True


def plan_ompl(world, name: str, seed: int, max_iter: Optional[int] = None, max_time: Optional[float] = None,
              goal_tolerance: Optional[float] = None, **params: Any) -> Result:
    """Solve ``world``'s query with OMPL planner ``name``.

    Parameters
    ----------
    world : World
    name : str
        One of :data:`OMPL_NAMES`.
    seed : int
        Recorded only (see the module docstring).
    max_iter, max_time :
        Budget; at least one is needed. ``range`` (OMPL's step) may be given
        as ``expand_dis``.
    goal_tolerance : float, optional
        [m] The query's, replacing the world's (as ``navlab.plan`` takes it).
    """
    check_ompl_name(name)
    try:
        from ompl import base as ob, geometric as og, util as ou
    except ImportError:
        from ..extras import install_command

        raise ImportError(f"OMPL is not installed: {install_command('ompl')}") from None
    ou.setLogLevel(ou.LOG_ERROR)
    if max_iter is None and max_time is None:
        raise ParameterError("an OMPL run needs max_iter or max_time")
    t0 = time.perf_counter()
    checker = world.checker()
    invalid = _check_query(world, checker)
    if invalid is not None:
        return invalid

    space = ob.RealVectorStateSpace(2)
    bounds = ob.RealVectorBounds(2)
    b = world.bounds
    for axis, (lo, hi) in enumerate(((b.xmin, b.xmax), (b.ymin, b.ymax))):
        bounds.setLow(axis, lo)
        bounds.setHigh(axis, hi)
    space.setBounds(bounds)
    si = ob.SpaceInformation(space)
    si.setStateValidityChecker(lambda s: bool(checker.points_free(np.array((s[0], s[1])))[0]))

    class ExactMotions(ob.MotionValidator):
        def checkMotion(self, s1, s2, *_):  # noqa: N802 (OMPL's name)
            return bool(checker.segments_free(np.array((s1[0], s1[1])), np.array((s2[0], s2[1])))[0])

    validator = ExactMotions(si)
    si.setMotionValidator(validator)
    si.setup()
    pdef = ob.ProblemDefinition(si)
    start, goal = space.allocState(), space.allocState()
    start[0], start[1] = world.start
    goal[0], goal[1] = world.goal
    tolerance = world.goal_tolerance if goal_tolerance is None else float(goal_tolerance)
    pdef.setStartAndGoalStates(start, goal, max(tolerance, 1e-9))
    pdef.setOptimizationObjective(ob.PathLengthOptimizationObjective(si))
    planner = getattr(og, name)(si)
    if "expand_dis" in params and hasattr(planner, "setRange"):
        planner.setRange(float(params.pop("expand_dis")))
    if params:
        raise ParameterError(f"unknown parameter(s) {', '.join(sorted(params))} for ompl:{name}; valid: expand_dis")
    planner.setProblemDefinition(pdef)
    planner.setup()
    step = planner.getRange() if hasattr(planner, "getRange") else None  # (set up: its default computed)
    counts = hasattr(planner, "numIterations")

    def done() -> bool:
        if max_time is not None and time.perf_counter() - t0 >= max_time:
            return True
        return counts and max_iter is not None and planner.numIterations() >= max_iter

    if not counts and max_time is None:
        raise ParameterError(f"ompl:{name} does not count iterations; give it max_time")
    t_solve = time.perf_counter()
    if counts:
        planner.solve(ob.PlannerTerminationCondition(done))
    else:  # OMPL's own clock: PRM asks the condition from a second thread, which waited for Python's lock
        # while the first held it joining that thread, forever (newcomer, session 23); the time alone stops these
        planner.solve(ob.timedPlannerTerminationCondition(max(0.0, max_time - (t_solve - t0))))
    elapsed = time.perf_counter() - t0
    stats: Dict[str, Any] = {"iterations": planner.numIterations() if counts else None, "time_s": elapsed,
                             "solve_time_s": time.perf_counter() - t_solve, "collision_checks": checker.checks,
                             "nodes": None, "first_solution_iteration": None, "first_solution_time_s": None}
    # what it ran with, as navlab's planners record theirs (its range and goal tolerance were left out)
    params_out = {"planner": f"ompl:{name}", "max_iter": max_iter, "max_time": max_time, "seed": seed,
                  "expand_dis": step, "goal_tolerance": tolerance}
    if not pdef.hasSolution():
        return Result(Status.FAILED, stats=stats, params=params_out, reason="OMPL found no path within the budget")
    path = pdef.getSolutionPath()
    pts = np.array([[path.getState(i)[0], path.getState(i)[1]] for i in range(path.getStateCount())])
    status = Status.EXACT if pdef.hasExactSolution() else Status.APPROXIMATE
    cost = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    # an APPROXIMATE row says why, as navlab's planners' do (it gave none: attack, session 22)
    spent = f"{stats['iterations']} iterations" if counts and stats["iterations"] is not None else \
        f"{elapsed:.3g} s"
    reason = "" if status == Status.EXACT else (
        f"goal not reached in {spent}; the path ends {np.linalg.norm(pts[-1] - np.asarray(world.goal, float)):.4g} m "
        "from the goal")
    return Result(status, path=pts, cost=cost, stats=stats, params=params_out, reason=reason)
