"""Every on/off setting is checked by one rule (``limits.check_flag``): Python's and numpy's bools are taken
(as a Python bool, so a result's params stay JSON), anything else is one line naming the setting. Before,
ten copies of the check disagreed: ``navlab.plan(costmap=np.True_)``, ``World``'s loader with
``allow_unknown=np.True_``, a follower's ``replan`` and RPP's flags refused numpy's bools that
``navlab.grid.plan`` took (re-read, session 25)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import navlab
from navlab.control.base import make_controller
from navlab.errors import ParameterError
from navlab.grid import plan as grid_plan
from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.occupancy import OccupancyGrid
from navlab.limits import check_flag
from navlab.world.sources import load_source
from navlab.robots import make_robot
from navlab.sim import Simulation
from navlab.world.costmap import LayeredCostmap
from navlab.world.footprint import Footprint
from navlab.world.world import Bounds, World


def _grid() -> OccupancyGrid:
    blocked = np.zeros((12, 12), dtype=bool)
    blocked[3:9, 6] = True
    return OccupancyGrid(blocked, resolution=1.0)


def _world(allow_unknown) -> World:
    return World("open", Bounds(0, 10, 0, 10), (1.0, 1.0), (9.0, 9.0), allow_unknown=allow_unknown)


#: (the setting's name, a call that passes it the value and returns what it built)
CALLS = {
    "grid smooth": ("smooth", lambda v: grid_plan(_grid(), (1, 1), (10, 10), smooth=v)),
    "grid allow_unknown": ("allow_unknown", lambda v: grid_plan(_grid(), (1, 1), (10, 10), allow_unknown=v)),
    "plan costmap": ("costmap", lambda v: navlab.plan(_grid(), "astar", start=(1.5, 1.5), goal=(10.5, 10.5),
                                                      costmap=v)),
    "plan allow_unknown": ("allow_unknown", lambda v: navlab.plan(_grid(), "astar", start=(1.5, 1.5),
                                                                  goal=(10.5, 10.5), allow_unknown=v)),
    "plan keep_tree": ("keep_tree", lambda v: navlab.plan("trap", "rrt", keep_tree=v, max_iter=20)),
    "load_source allow_unknown": ("allow_unknown", lambda v: load_source(_grid(), start=(1.5, 1.5),
                                                                         goal=(10.5, 10.5), allow_unknown=v)),
    "World allow_unknown": ("allow_unknown", lambda v: _world(v)),
    "hybrid smooth": ("smooth", lambda v: plan_hybrid(_grid(), (1.5, 1.5, 0.0), (10.5, 10.5, 0.0), 1.0,
                                                      smooth=v)),
    "follower replan": ("replan", lambda v: make_controller("pure_pursuit", replan=v)),
    "rpp creep_when_blocked": ("creep_when_blocked", lambda v: make_controller("rpp", creep_when_blocked=v)),
    "rpp plan_poses": ("plan_poses", lambda v: make_controller("rpp", plan_poses=v)),
    # the last three that skipped it: static="false" built the static layer, record_scans="no" recorded scans
    # (attack, session 25)
    "costmap static": ("static", lambda v: LayeredCostmap(_world(False), Footprint.disc(0.2), static=v)),
    "simulation record_scans": ("record_scans", lambda v: Simulation(
        _world(False), make_robot("omni3"), make_controller("goto_waypoint"), (1.0, 1.0), (9.0, 9.0),
        path=[(1.0, 1.0), (9.0, 9.0)], record_scans=v)),
}


@pytest.mark.parametrize("call", CALLS)
@pytest.mark.parametrize("value", [True, np.True_, np.False_])
def test_python_and_numpy_bools_are_taken(call, value):
    CALLS[call][1](value)


@pytest.mark.parametrize("call, value", [(call, value) for call in CALLS for value in ("false", 1, None, 0.0, [True])
                                         if not (value is None and call == "load_source allow_unknown")])
def test_anything_else_names_the_setting(call, value):
    """(None is load_source's "the source's own")"""
    name, run = CALLS[call]
    # (a controller's setting is named with the controller: make_controller says whose)
    with pytest.raises(ParameterError, match=f"^(controller '[a-z_]+': )?{name} must be true or false, got "):
        run(value)


def test_a_numpy_bool_is_kept_as_a_python_bool():
    assert check_flag("smooth", np.True_) is True and check_flag("smooth", np.False_) is False
    result = grid_plan(_grid(), (1, 1), (10, 10), smooth=np.False_, allow_unknown=np.True_)
    assert result.params["smooth"] is False and result.params["allow_unknown"] is True
    json.dumps(result.params)  # (numpy's bool is not JSON)
    assert _world(np.True_).allow_unknown is True


def test_a_moving_obstacles_loop_takes_numpys_bool():
    """``motion.loop`` keeps its file-format error (MotionFormatError) but takes numpy's bool, as check_flag does."""
    from navlab.world.motion import MotionFormatError, WaypointMotion

    assert WaypointMotion(((0.0, 0.0), (1.0, 0.0)), 0.5, loop=np.True_).loop is True
    with pytest.raises(MotionFormatError, match="expected true or false, got 'no'"):
        WaypointMotion(((0.0, 0.0), (1.0, 0.0)), 0.5, loop="no")


@pytest.mark.parametrize("name, setting", [("pure_pursuit", "replan"), ("rpp", "creep_when_blocked")])
def test_a_nan_flag_is_told_true_or_false_not_finite(name, setting):
    """make_controller's finite check ran first: 'replan must be finite, got nan', as if a number would do
    (attack, session 25)."""
    with pytest.raises(ParameterError, match=f"{setting} must be true or false, got nan"):
        make_controller(name, **{setting: float("nan")})


def test_numpy_numbers_are_taken_as_grid_settings_and_kept_plain():
    """np.int64(4) connectivity was refused by navlab.plan and kept as numpy's in navlab.grid.plan's params (not
    JSON); np.float32 resolution was 'not a finite number' (attack, session 25)."""
    for connectivity in (np.int64(4), np.uint8(8), np.float64(8.0)):
        result = grid_plan(_grid(), (1, 1), (10, 10), connectivity=connectivity)
        assert type(result.params["connectivity"]) is int
        json.dumps(result.params)
        assert navlab.plan(_grid(), "astar", start=(1.5, 1.5), goal=(10.5, 10.5), connectivity=connectivity).success
    assert navlab.plan("trap", "astar", resolution=np.float32(0.1)).success
    for bad in (4.5, True, "8"):
        with pytest.raises(ParameterError, match="connectivity must be 4 or 8"):
            grid_plan(_grid(), (1, 1), (10, 10), connectivity=bad)


def test_a_bad_smooth_is_refused_before_any_kernel_loads(monkeypatch):
    """smooth=np.array([True, False]) was numpy's 'truth value of an array is ambiguous', and smooth='no' loaded
    the smoothing kernels before it was refused (attack, session 25)."""
    import navlab.grid.planner as grid_planner

    monkeypatch.setattr(grid_planner, "warm_kernels", lambda *a: pytest.fail("warmed before the check"))
    for bad in (np.array([True, False]), "no"):
        with pytest.raises(ParameterError, match="smooth must be true or false"):
            grid_plan(_grid(), (1, 1), (10, 10), smooth=bad)
