"""Wrong types to every argument of the public API.

An outside attack found 33 of 167 wrong-type calls answered with a raw
``TypeError`` / ``AttributeError`` (``navlab.plan(..., planner=['rrt'])``:
"unhashable type"). Each call here gets one argument replaced by something a
script or a YAML file could hand over (None, lists, dicts, strings, bools,
NaN, inf, huge and negative numbers): the call must either work or raise the
project's own error, ``navlab.NavlabError`` (a ``ValueError``) — never another
exception type, and not a bare ``ValueError`` either (until session 17, 79 % of
an attack's 1 102 bad-input calls were plain ``ValueError``s).
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import navlab
from navlab import NavlabError
from navlab.grid import OccupancyGrid, make_maze
from navlab.grid import plan as grid_plan

from fuzz.strategies import wild_values

GRID = make_maze(4, 4, seed=1)
JUNK = st.one_of(wild_values(), st.just(-1), st.just(-0.5), st.just(10 ** 30), st.just(float("nan")))


def _plan(**changes):
    args = {"source": "trap", "planner": "rrt_star", "sampler": "uniform", "seed": 0, "max_iter": 50}
    args.update(changes)
    return navlab.plan(args.pop("source"), **args)


def _grid_plan(**changes):
    args = {"start": (1, 1), "goal": (5, 5), "algorithm": "astar", "heuristic": "octile", "connectivity": 8,
            "smooth": False, "weight": 1.0, "allow_unknown": False, "smooth_method": "bresenham"}
    args.update(changes)
    return grid_plan(GRID, **args)


def _occupancy(**changes):
    args = {"blocked": np.zeros((3, 4), bool), "resolution": 0.5, "origin": (0.0, 0.0, 0.0), "name": "g"}
    args.update(changes)
    return OccupancyGrid(**args)


def _simulate(**changes):
    from navlab.sim.runner import simulate

    args = {"world": "one_obstacle", "robot": "omni3", "controller": "potential_field", "dt": 0.05,
            "max_time": 2.0, "seed": 0}
    args.update(changes)
    return simulate(**args)


CALLS = {
    "plan": (_plan, ["source", "planner", "sampler", "seed", "start", "goal", "robot_radius", "max_iter",
                     "expand_dis", "goal_sample_rate", "keep_tree"]),
    "grid.plan": (_grid_plan, ["start", "goal", "algorithm", "heuristic", "connectivity", "smooth", "weight",
                               "allow_unknown", "smooth_method"]),
    "OccupancyGrid": (_occupancy, ["blocked", "resolution", "origin", "name"]),
    "load_world": (lambda source: navlab.load_world(source), ["source"]),
    "simulate": (_simulate, ["world", "robot", "controller", "start", "goal", "dt", "max_time", "seed",
                             "robot_params", "controller_params"]),
}


def _acceptable(call, argument, value):
    try:
        call(**{argument: value})
    except NavlabError:
        pass  # navlab's errors, with a message naming the field
    except Exception as exc:  # anything else is the defect this test is for
        raise AssertionError(f"{argument}={value!r} raised {type(exc).__name__}: {exc}") from None


@pytest.mark.parametrize("name", sorted(CALLS))
@given(data=st.data())
def test_wrong_types_are_a_value_error_or_work(name, data):
    call, arguments = CALLS[name]
    argument = data.draw(st.sampled_from(arguments), label="argument")
    value = data.draw(JUNK, label="value")
    _acceptable(call, argument, value)


@pytest.mark.parametrize("name, argument, value", [
    ("plan", "planner", ["rrt"]), ("plan", "sampler", {"a": 1}), ("plan", "start", "ab"),
    ("plan", "goal", [1, 2, 3, 4]), ("plan", "robot_radius", math.nan), ("plan", "source", 3),
    ("grid.plan", "heuristic", 0), ("grid.plan", "connectivity", [1]), ("grid.plan", "start", None),
    ("OccupancyGrid", "origin", "x"), ("OccupancyGrid", "resolution", None), ("load_world", "source", None),
    ("simulate", "robot", ["diff"]), ("simulate", "controller_params", [1]), ("simulate", "dt", "0.1"),
])
def test_known_wrong_type_calls(name, argument, value):
    call, _ = CALLS[name]
    with pytest.raises(NavlabError):
        call(**{argument: value})
