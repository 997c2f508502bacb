"""A* on a Nav2-style costmap as a bench cell (``{name: astar, costmap: true}``), as ``navlab.plan`` takes it.

Until session 23 the bench refused it with a line that listed ``costmap=true`` as valid (attack, session 22)."""

import pytest

import navlab
from navlab.bench.experiment import ExperimentError, load_experiment
from navlab.bench.runner import run_experiment

COSTMAP = {"name": "costmap", "worlds": ["trap", "clutter"], "trials": 1, "params": {"resolution": 0.25},
           "planners": ["astar", {"name": "astar", "costmap": True, "inflation_radius": 1.0, "label": "astar-cm"}]}


def test_a_costmap_cell_runs_the_query_navlab_plan_runs(tmp_path):
    run = run_experiment(load_experiment(COSTMAP), tmp_path / "run", executor="serial", progress=False, plots=False)
    assert run.errors == 0 and len(run.rows) == 4
    for row in run.rows:
        costmap = row["planner"] == "astar-cm"
        settings = {"costmap": True, "inflation_radius": 1.0} if costmap else {}
        direct = navlab.plan(row["world"], planner="astar", resolution=0.25, **settings)
        assert row["status"] == "EXACT" and row["cost"] == pytest.approx(direct.cost, rel=1e-12)
        assert row["params"] == {"resolution": 0.25, **settings}
    # the costmap's costs steer the path: its cost is not the plain grid search's on either world
    costs = {(r["world"], r["planner"]): r["cost"] for r in run.rows}
    assert all(costs[w, "astar"] != pytest.approx(costs[w, "astar-cm"]) for w in ("trap", "clutter"))


def test_a_shared_costmap_setting_goes_to_astar_on_a_costmap_alone():
    exp = load_experiment({**COSTMAP, "worlds": ["trap"], "params": {"costmap": True, "inflation_radius": 0.8},
                           "planners": ["astar", "rrt"]})
    from navlab.bench.experiment import routed_params

    taken = {c.planner.name: routed_params(c.planner.name, c.params, c.planner.params) for c in exp.cells()}
    assert taken == {"astar": {"costmap": True, "inflation_radius": 0.8}, "rrt": {}}
    with pytest.raises(ExperimentError, match="'inflation_radius' applies to none of this experiment's planners"):
        load_experiment({**COSTMAP, "params": {"inflation_radius": 0.8}, "planners": ["astar"]})


@pytest.mark.parametrize("planner, message", [
    ({"name": "astar", "costmap": 1}, "costmap must be true or false, got 1"),
    ({"name": "astar", "costmap": 0}, "costmap must be true or false, got 0"),  # (0 == False passed: review, s. 23)
    ({"name": "astar", "costmap": True, "inflation_radius": -1}, "inflation_radius must be a non-negative number"),
    ({"name": "astar", "costmap": True, "inflation_radius": 0.01}, "inflation_radius = 0.01 m is below the "
                                                                    "footprint's inscribed radius 0.15 m"),
    ({"name": "astar", "costmap": True, "connectivity": 4}, "unknown parameter 'connectivity' with costmap=true"),
    ({"name": "astar", "costmap": True, "cost_travel_multiplier": float("inf")},
     "cost_travel_multiplier: numbers must be finite"),
    ({"name": "jps", "costmap": True}, "only astar plans on a costmap's costs, got 'jps'"),
])
def test_a_bad_costmap_cell_is_refused_before_any_trial(planner, message):
    with pytest.raises(ExperimentError, match=message):
        load_experiment({**COSTMAP, "worlds": ["trap"], "params": {}, "planners": [planner]})


def test_a_shared_costmap_value_that_is_not_true_or_false_is_named():
    """(costmap=yes from the flags was "applies to none of this experiment's planners": attack, session 23)"""
    with pytest.raises(ExperimentError, match="costmap must be true or false, got 'yes'"):
        load_experiment({**COSTMAP, "worlds": ["trap"], "params": {"costmap": "yes"}, "planners": ["astar"]})
    exp = load_experiment({**COSTMAP, "worlds": ["trap"], "params": {"costmap": True}, "planners": ["astar", "jps"]})
    from navlab.bench.experiment import routed_params

    assert [routed_params(c.planner.name, c.params, c.planner.params) for c in exp.cells()] == [
        {"costmap": True}, {}]  # the shared costmap goes to astar, the one planner that takes it


def test_a_map_worlds_robot_is_held_against_the_inflation_radius_before_any_trial(tmp_path):
    """(a map world's robot_radius was not read by the check: every trial was an ERROR row; review and attack,
    session 23)"""
    import numpy as np

    from navlab.grid import OccupancyGrid
    from navlab.grid.mapio import save_map

    save_map(OccupancyGrid(np.zeros((40, 40), bool), resolution=0.25), tmp_path / "open.yaml")
    world = {"map": str(tmp_path / "open.yaml"), "queries": [[1, 1, 8, 8]], "robot_radius": 0.45}
    cell = {"name": "astar", "costmap": True, "inflation_radius": 0.3}
    with pytest.raises(ExperimentError, match="inflation_radius = 0.3 m is below the footprint's inscribed radius 0.45 m"):
        load_experiment({**COSTMAP, "worlds": [world], "params": {}, "planners": [cell]})
    load_experiment({**COSTMAP, "worlds": [world], "params": {}, "planners": [{**cell, "inflation_radius": 0.5}]})
