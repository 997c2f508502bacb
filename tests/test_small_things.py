"""Small things a newcomer run found: each one line naming what is wrong, or the right output."""

import subprocess
import sys

import pytest

import navlab
from navlab.world.io import save_world


def navlab_cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "navlab", *map(str, args)], capture_output=True, text=True, cwd=cwd)


@pytest.mark.parametrize("seed", [-5, 1.5, "3", True])
def test_a_bad_seed_is_named(seed):
    with pytest.raises(ValueError, match="seed must be a non-negative whole number"):
        navlab.plan("trap", seed=seed)


@pytest.mark.parametrize("planner", [["rrt"], None, 3])
def test_a_planner_that_is_not_a_name_is_named(planner):
    with pytest.raises(ValueError, match="planner"):
        navlab.plan("trap", planner=planner)


def test_an_invalid_start_for_a_grid_planner_prints_no_empty_grid_line():
    done = navlab_cli("plan", "trap", "--planner", "astar", "--start", "100", "100")
    assert done.returncode in (1, 2) and "grid None" not in done.stdout + done.stderr


def test_grid_plan_on_a_world_file_says_to_use_navlab_plan(tmp_path):
    save_world(navlab.load_world("trap"), tmp_path / "trap.yaml")
    done = navlab_cli("grid", "plan", tmp_path / "trap.yaml", "--start", "0", "0", "--goal", "1", "1")
    assert done.returncode == 2 and "this is a world file" in done.stderr and "navlab plan" in done.stderr


def test_a_missing_scenario_file_says_where_they_come_from(tmp_path):
    done = navlab_cli("grid", "scen", tmp_path / "arena.map.scen")
    assert done.returncode == 2 and "movingai.com/benchmarks" in done.stderr


def test_max_iter_help_states_the_defaults():
    assert "5000 for rrt_star" in navlab_cli("plan", "--help").stdout.replace("\n", " ").replace("  ", " ")


def test_durations_read_in_ms_then_seconds():
    """(newcomer run, session 21: a first use's warm-up printed as "53881 ms")"""
    from navlab.wording import duration

    assert [duration(t) for t in (0.0412, 9.9994, 9.9996, 10.0, 53.881)] == ["41 ms", "9999 ms", "10.0 s", "10.0 s",
                                                                             "53.9 s"]


def test_decimals_lose_only_a_fractions_trailing_zeros():
    """(review, session 31: to no places, 10 and 100 both read "1", and -0.4 read "-")"""
    from navlab.wording import decimal

    assert [decimal(x, 0) for x in (10.0, 100, -0.4, 2.5)] == ["10", "100", "0", "2"]
    assert [decimal(x) for x in (0.3, 4.8, -0.0, -1e-7, -0.5, 12345.675, 2)] == \
        ["0.3", "4.8", "0", "0", "-0.5", "12345.675", "2"]
    assert decimal(5.5e-7, 8) == "0.00000055"


def test_one_expanded_cell_is_singular():
    """"(1 cells expanded)" was a failed grid search's reason (session 28's left-alone list)."""
    import numpy as np

    from navlab.grid import OccupancyGrid, plan

    walled = OccupancyGrid(np.array([[False, True, False]]))
    assert plan(walled, (0, 0), (2, 0)).reason == "no path from (0, 0) to (2, 0) (1 cell expanded)"
    wider = OccupancyGrid(np.array([[False, False, True, False]]))
    assert plan(wider, (0, 0), (3, 0)).reason == "no path from (0, 0) to (3, 0) (2 cells expanded)"


def test_a_tree_that_did_not_grow_has_no_path_at_an_infinite_cost():
    """A FAILED tree plan reported the root as a path of cost 0.0: the best of any runs compared by cost
    (API attack, session 29). Result says: no path, cost inf."""
    import math

    r = navlab.plan("trap", planner="rrt", max_iter=1, max_time=0.5, seed=0)
    assert r.status.name == "FAILED" and r.reason == "the tree did not grow in 1 iteration"
    assert r.path.shape == (0, 2) and r.cost == math.inf and r.to_dict()["cost"] is None


def test_numpy_numbers_are_numbers_for_the_time_settings():
    """np.float32(0.5) was refused as "max_time must be a positive number" (API attack, session 29)."""
    import numpy as np

    from navlab.sim.runner import simulate

    r = navlab.plan("trap", planner="rrt_star", max_iter=200, max_time=np.float32(5), connect_circle_dist=np.float32(30))
    assert r.success and type(r.params["max_time"]) is float
    result, _, _ = simulate("trap", dt=np.float32(0.05), max_time=np.float32(1))
    assert result.time_s == pytest.approx(1.0)
    with pytest.raises(ValueError, match=r"max_time must be a positive number, got np.float32\(-1.0\)"):
        navlab.plan("trap", planner="rrt", max_iter=10, max_time=np.float32(-1))


@pytest.mark.parametrize("call", [
    lambda: navlab.plan("trap", planner="rrt", sampler="", max_iter=50),
    lambda: __import__("navlab.sim.runner", fromlist=["simulate"]).simulate("trap", controller="", max_time=1),
    lambda: __import__("navlab.sim.runner", fromlist=["simulate"]).simulate("trap", planner="", max_time=1),
])
def test_an_empty_name_is_no_name_not_the_default(call):
    """'' fell back to the default sampler, controller or planner where None does (API attack, session 29)."""
    from navlab.registry import UnknownNameError

    with pytest.raises(UnknownNameError, match="unknown (sampler|controller|planner) ''"):
        call()
