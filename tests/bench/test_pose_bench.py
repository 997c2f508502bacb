"""Planners between poses in the benchmark harness: Hybrid A* and RRT* with
Reeds–Shepp steering on a heading scene, rows as navlab.plan gives them."""

import re

import pytest

import navlab
from navlab.bench import ExperimentError, load_experiment, run_experiment

POSES = {"name": "poses", "worlds": ["trap_car"], "planners": ["rrt_star", "hybrid_astar"], "samplers": ["uniform"],
         "params": {"motion": "reeds_shepp"}, "budget": {"max_iter": 800}, "trials": 2, "seed": 3}


def test_hybrid_astar_and_se2_rrt_star_run_as_cells(tmp_path):
    run = run_experiment(load_experiment(POSES), tmp_path / "run", executor="serial", progress=False, plots=True)
    assert run.errors == 0 and len(run.rows) == 4
    hybrid = [r for r in run.rows if r["planner"] == "hybrid_astar"]
    assert all(r["status"] == "EXACT" for r in hybrid)
    direct = navlab.plan("trap_car", planner="hybrid_astar", motion="reeds_shepp")
    assert hybrid[0]["cost"] == pytest.approx(direct.cost, rel=1e-12)
    tree = [r for r in run.rows if r["planner"] == "rrt_star"]
    for row in tree:
        again = navlab.plan("trap_car", planner="rrt_star", motion="reeds_shepp", max_iter=800, seed=row["seed"])
        assert row["status"] == again.status.name and (not again.success or row["cost"] == again.cost)
    assert list((tmp_path / "run" / "plots").glob("*.png"))


def test_a_point_planner_asked_for_car_motion_is_refused_before_any_trial():
    with pytest.raises((ExperimentError, ValueError), match="planners for reeds_shepp motion"):
        exp = load_experiment({**POSES, "planners": ["growth_ratio_rrt"]})
        from navlab.bench.experiment import validate

        validate(exp)


@pytest.mark.parametrize("grid, message", [
    ({"distance_table": ["yes"]}, "distance_table must be true or false, got 'yes'"),
    ({"exact_retry": [1]}, "exact_retry must be true or false, got 1"),
    ({"heading_bins": [3]}, "heading_bins must be a whole number from 4 to 1440, got 3"),
    ({"turning_radius": [-1]}, "turning_radius"),
])
def test_a_pose_planners_bad_setting_is_refused_before_any_trial(grid, message):
    """Hybrid A*'s and the car-like trees' own settings were checked only by each trial, so a bad one ran
    every trial as an ERROR row, exit 1 (attack, session 22); a grid planner's were refused up front."""
    with pytest.raises((ExperimentError, ValueError), match=message):
        load_experiment({**POSES, "grid": grid, "planners": ["hybrid_astar"]})
    # a car-like tree is told the same of the settings it shares (and that Hybrid A*'s are not its own)
    message = message if "bins" in message or "radius" in message else "is a setting of planner hybrid_astar, not"
    with pytest.raises((ExperimentError, ValueError), match=message):
        load_experiment({**POSES, "grid": grid, "planners": ["rrt_star"]})


@pytest.mark.parametrize("where", ["grid", "params"])
def test_a_swept_values_refusal_names_the_planner_and_its_grid_values(where):
    """``grid: {motion: [holonomic, reeds_shepp]}`` for hybrid_astar was refused as "motion: hybrid_astar
    plans for a car-like robot ...", as a ``params:`` motion is, so a sweep's bad value read as the
    planner's own setting (left alone in sessions 23-24); a value from ``params:`` stays as it was."""
    value = ["holonomic", "reeds_shepp"] if where == "grid" else "holonomic"
    with pytest.raises(ExperimentError) as caught:
        load_experiment({**POSES, where: {"motion": value}, "planners": ["hybrid_astar"]})
    said = str(caught.value)
    assert "motion must be dubins or reeds_shepp, got 'holonomic'" in said
    assert ("grid: planner 'hybrid_astar' where motion=holonomic: motion:" in said) == (where == "grid")


def test_a_grid_algorithms_swept_connectivity_is_named_too():
    with pytest.raises(ExperimentError, match="grid: planner 'jps' where connectivity=4: jps needs connectivity 8"):
        load_experiment({"worlds": ["trap"], "planners": ["jps"], "grid": {"connectivity": [4, 8], "smooth": [True]}})


BASE = {"name": "x", "worlds": ["trap"], "trials": 1}


@pytest.mark.parametrize("experiment, said", [
    # a swept sampler setting names the sampler
    ({"planners": ["rrt"], "samplers": ["gaussian"], "grid": {"sigma": [-1, 1]}},
     "grid: sampler 'gaussian' of planner 'rrt' where sigma=-1: sigma must be positive"),
    # a planner's label names it, as the report does
    ({"planners": [{"name": "jps", "label": "fast"}], "grid": {"connectivity": [4, 8]}},
     "grid: planner 'fast' where connectivity=4: "),
    # a setting of a planner's own entry names the entry: of two astar, which (attack, session 25)
    ({"planners": [{"name": "astar", "label": "a"}, {"name": "astar", "label": "b", "smooth": 1}]},
     "planner 'b': smooth must be true or false, got 1"),
    ({"planners": ["rrt"], "samplers": [{"name": "gaussian", "sigma": -1}], "grid": {"expand_dis": [0.5, 1.0]}},
     "sampler 'gaussian' of planner 'rrt': sigma must be positive"),
    # text that reads as a number stays quoted in the cell's name (newcomer, session 25)
    ({"planners": ["jps"], "grid": {"connectivity": ["8"]}}, "grid: planner 'jps' where connectivity='8': "),
    # the sweep that made the cell holonomic is the cause, not rrt's own turning_radius (second review)
    ({"planners": [{"name": "rrt", "turning_radius": 1.0}], "grid": {"motion": ["holonomic", "dubins"]}},
     "grid: planner 'rrt' where motion=holonomic: turning_radius applies only"),
])
def test_a_swept_refusal_names_whose_setting_it_is(experiment, said):
    with pytest.raises(ExperimentError, match=re.escape(said)):
        load_experiment({**BASE, **experiment})


@pytest.mark.parametrize("experiment", [
    {"planners": [{"name": "jps", "connectivity": 4}], "grid": {"smooth": [True, False]}},  # the planner's own
    {"planners": ["jps"], "params": {"connectivity": 4}, "grid": {"smooth": [True, False]}},  # shared
    {"planners": [{"name": "jps", "connectivity": 4}], "grid": {"connectivity": [8]}},  # own over the sweep
    {"planners": ["rrt_star"], "budget": {"max_iter": 10**12}, "grid": {"expand_dis": [0.5, 1.0]}},  # budget
    # a refusal that lists the valid names, a swept one among them
    {"planners": [{"name": "astar", "connectivty": 4}], "grid": {"weight": [1.0, 2.0]}},
    {"planners": [{"name": "rrt", "keep_tree": "yes"}], "grid": {"expand_dis": [0.5, 1.0]}},
])
def test_a_refusal_of_what_is_not_swept_does_not_blame_the_sweep(experiment):
    """The first version prefixed every refusal in a cell with swept values with all of them (review,
    session 25: 'with grid values smooth=True: jps needs connectivity 8' for the planner's own connectivity)."""
    with pytest.raises(ExperimentError) as caught:
        load_experiment({**BASE, **experiment})
    assert "grid:" not in str(caught.value) and " where " not in str(caught.value), str(caught.value)
