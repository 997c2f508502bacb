"""Fuzzing planner and sampler parameters, and simulation start poses.

Each call returns a Result (checked with shapely) or raises navlab's error (NavlabError, a ValueError) whose
message names the parameter. Values that could allocate gigabytes before a
size check are left to test_fuzz_memory.py, which runs them under a memory limit.
"""

import math

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import navlab
from navlab import NavlabError
from navlab.registry import UnknownNameError, parameters_of
from navlab.sampling import PLANNERS, SAMPLERS
from navlab.world import world_from_dict

from fuzz.checks import check_world_result
from fuzz.strategies import EXTREME_FLOATS, HUGE_INTS, NON_FINITE, WRONG_TYPES, examples

WORLD = world_from_dict({
    "name": "fuzz", "bounds": {"x": [0, 10], "y": [0, 10]}, "start": [1, 1], "goal": [9, 9], "robot_radius": 0.1,
    "obstacles": [{"type": "circle", "center": [5, 5], "radius": 1.5},
                  {"type": "rectangle", "min": [2, 6], "max": [4, 7]},
                  {"type": "polygon", "points": [[6, 1], [8, 2], [7, 3.5]]}]})

#: parameters that size arrays: in this process only values too small to matter or too large to allocate at all
COUNTS = {"max_iter", "batch_size", "directions", "max_rounds"}
BASE = {"max_iter": 60}  # keeps every run short; a fuzzed max_iter replaces it


def values_for(key):
    sane = {
        "max_iter": st.integers(-3, 300), "batch_size": st.integers(-3, 300), "directions": st.integers(-3, 64),
        "max_rounds": st.integers(-3, 100), "max_time": st.floats(0.001, 0.3),
        "goal_sample_rate": st.floats(-0.5, 1.5), "sigma": st.floats(1e-4, 5), "tolerance": st.floats(1e-6, 1),
        "expand_dis": st.floats(1e-3, 20), "connect_circle_dist": st.floats(1e-3, 100), "p_min": st.floats(1e-3, 5),
        "keep_tree": st.booleans(), "base": st.sampled_from(sorted(SAMPLERS.names())),
        "weights": st.fixed_dictionaries({k: st.floats(0, 1) for k in ("goal", "uniform", "gaussian", "boundary")}),
    }.get(key, st.floats(-10, 10))
    wild_number = st.one_of(HUGE_INTS, NON_FINITE, EXTREME_FLOATS)
    if key in COUNTS:  # never a count a process could try to allocate (those: test_fuzz_memory.py, and test_huge_counts_are_refused_by_name)
        wild_number = st.one_of(st.sampled_from([-(10**30), -(2**63)]), NON_FINITE, EXTREME_FLOATS)
    return st.one_of(sane, wild_number, WRONG_TYPES)


def run_and_check(planner, sampler, params):
    if "max_time" in params:  # the time limit stops the run, not the iteration cap
        params = {"max_iter": 3000, **params}
    try:
        result = navlab.plan(WORLD, planner=planner, sampler=sampler, seed=0, **{**BASE, **params})
    except NavlabError as exc:
        (key,) = params.keys() - {"max_iter"} or params.keys()
        named = key in str(exc) or (key == "base" and isinstance(exc, UnknownNameError))  # "unknown sampler 'x'"
        assert named, f"{key}={params[key]!r}: {exc}"
        return
    check_world_result(WORLD, result)


@examples(80)
@given(st.sampled_from(sorted(PLANNERS.names())), st.data())
def test_planner_parameters(planner, data):
    keys = sorted(set(parameters_of(PLANNERS.get(planner))) - {"sampler", "max_time"})
    key = data.draw(st.sampled_from(keys), label="key")
    value = data.draw(values_for(key), label="value")
    run_and_check(planner, "uniform", {key: value})


@pytest.mark.parametrize("planner", sorted(PLANNERS.names()))
def test_batch_size_none_is_refused_by_name(planner):
    run_and_check(planner, "uniform", {"batch_size": None})


@examples(10)
@given(st.sampled_from(sorted(PLANNERS.names())), st.sampled_from(["max_iter", "batch_size"]),
       st.sampled_from([10**12, 10**20, 2**63, 10**400]))
@example("rrt_star", "max_iter", 10**12)
def test_huge_counts_are_refused_by_name(planner, key, value):
    run_and_check(planner, "uniform", {key: value})


@examples(20)
@given(st.sampled_from(sorted(PLANNERS.names())), st.one_of(st.floats(0.001, 0.05), NON_FINITE, WRONG_TYPES,
                                                           st.sampled_from([0, -1, 1e300, 10**400])))
def test_max_time(planner, value):
    run_and_check(planner, "uniform", {"max_time": value})


@examples(80)
@given(st.sampled_from(sorted(SAMPLERS.names())), st.data())
@example("integration", None).via("issue 13: weights=5")
def test_sampler_parameters(sampler, data):
    if data is None:
        run_and_check("rrt", "integration", {"weights": 5})
        return
    keys = sorted(parameters_of(SAMPLERS.get(sampler))) + ["goal_sample_rate"]
    key = data.draw(st.sampled_from(keys), label="key")
    run_and_check("rrt", sampler, {key: data.draw(values_for(key), label="value")})


@examples(20)
@given(st.sampled_from(sorted(SAMPLERS.names())), st.sampled_from(sorted(PLANNERS.names())), st.integers(0, 2**63 - 1))
def test_every_planner_with_every_sampler_and_any_seed(sampler, planner, seed):
    check_world_result(WORLD, navlab.plan(WORLD, planner=planner, sampler=sampler, seed=seed, max_iter=80))


# --- simulation start poses ----------------------------------------------------------------------

def simulate(start):
    import warnings

    from navlab.angles import HeadingWarning
    from navlab.sim.runner import simulate as run

    try:
        with warnings.catch_warnings():  # any finite heading is one, noted beyond ±2π (its own test)
            warnings.simplefilter("ignore", HeadingWarning)
            result, _, _ = run("one_obstacle", robot="omni3", start=start, max_time=0.5)
    except NavlabError as exc:
        assert "start" in str(exc), f"start {start}: {exc}"
        return None
    assert np.isfinite(result.final_true).all() and np.isfinite(result.final_odom).all(), (start, result.final_true)
    return result


@examples(25)
@given(st.tuples(st.one_of(st.floats(-5.5, 5.5), st.floats(-1e7, 1e7)), st.one_of(st.floats(-5.5, 5.5), st.floats(-1e7, 1e7)),
                 st.one_of(st.floats(-7, 7), st.floats(-1e300, 1e300))))
@example((0.0, 0.0, 1e300))
@example((-5.0, -5.0, 0.0))
def test_simulation_from_any_finite_start(start):
    simulate(start)


@examples(15)
@given(st.tuples(st.one_of(st.floats(-4, 4), NON_FINITE), st.one_of(st.floats(-4, 4), NON_FINITE),
                 st.one_of(NON_FINITE, st.floats(-4, 4))))
@example((0.0, 0.0, math.inf))
@example((0.0, 0.0, math.nan))
def test_simulation_from_a_non_finite_start(start):
    simulate(start)
