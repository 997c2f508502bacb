"""Issue 22's "clear errors for the rest": each bad value is one line naming
the file and the field, from Python (the project's ValueError) and from the
command line (exit 2, no traceback)."""

import re
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import navlab
from navlab.bench.experiment import ExperimentError, load_experiment
from navlab.control.base import make_controller
from navlab.grid import load_map, read_scen
from navlab.grid.mapio import MapFormatError
from navlab.robots import make_robot
from navlab.sim.runner import simulate


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "navlab", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd)


@pytest.mark.parametrize("setting, value, words", [
    ("heuristic", 0, "heuristic must be one of"),
    ("connectivity", [1], "connectivity must be 4 or 8"),
    ("connectivity", float("inf"), "connectivity must be 4 or 8"),
    ("resolution", 1e-300, "resolution must be between"),
    ("smooth", 3, "smooth must be true or false"),
    ("weight", float("nan"), "weight must be a finite number"),
])
def test_grid_settings_of_the_wrong_type_name_the_setting(setting, value, words):
    with pytest.raises(ValueError, match=words):
        navlab.plan("trap", planner="astar", **{setting: value})


@pytest.mark.parametrize("param", ["heuristic=0", "connectivity=[1]", "connectivity=.inf", "resolution=1e-300"])
def test_grid_settings_from_the_command_line(param):
    done = cli("plan", "trap", "--planner", "astar", "--param", param)
    assert done.returncode == 2 and "internal error" not in done.stderr and "Traceback" not in done.stderr
    assert done.stderr.strip().count("\n") == 0 and param.split("=")[0] in done.stderr


@pytest.mark.parametrize("body, words", [
    ("grid: {heuristic: [0]}", "heuristic must be one of"),
    ("grid: {connectivity: [[1]]}", "connectivity must be 4 or 8"),
    # (any non-finite number in an experiment is refused where it stands, since session 25: JSON cannot hold it)
    ("grid: {connectivity: [.inf]}", r"grid.connectivity\[0\]: numbers must be finite, got inf"),
    ("grid: {resolution: [1.0e-300]}", "resolution must be between"),
    ("params: [1]", "'params' must be a mapping"),
    ("params: {heuristic: 0}", "heuristic must be one of"),
    ("budget: {max_iter: 2.5}", "max_iter must be a positive integer"),  # (1.0e+12, a whole number, is taken)
    ("claims: [{text: x, metric: cost, lower: nothere, higher: astar}]", "nothere"),
    # YAML values no experiment can hold were internal errors in a trial or the results file (an attack on
    # the command, session 17)
    ("claims: [{text: {a: 1}, lower: astar, higher: astar}]", "claim text must be text"),
    ("claims: [{text: x, lower: [1], higher: astar}]", "claim lower must be a group name or a list of them"),
    ("grid: {1: [2]}", "grid: keys must be names, got 1"),
    ("params: {weight: !!binary aGVsbG8=}", "params.weight: binary data is not an experiment value"),
    ("grid: {weight: [!!timestamp 2001-01-01]}", "grid.weight\\[0\\]: a date is not an experiment value"),
    ("params: {weight: !!set {a}}", "params.weight: a set is not an experiment value"),
    ("study: {title: [1]}", "study.title must be text"),
])
def test_experiment_files_are_checked_before_any_trial(tmp_path, body, words):
    path = tmp_path / "e.yaml"
    path.write_text(f"name: t\nworlds: [trap]\nplanners: [astar]\ntrials: 1\n{body}\n")
    with pytest.raises(ExperimentError, match=words):
        load_experiment(path)


@pytest.mark.parametrize("planners, grid, words", [
    # a grid search's setting swept where no cell uses it ran, noted as unused (attack, session 25)
    ("[dijkstra]", "{weight: [1, 0.5]}", "grid: weight=0.5: weight must be a finite number >= 1"),
    ("[jps]", "{weight: [1, yes], heuristic: [octile, eucl]}", "grid: "),
    ("[{name: astar, heuristic: none}]", "{weight: [1, .nan]}", r"grid.weight\[1\]: numbers must be finite"),
    ("[rrt]", "{sigma: [.inf]}", r"grid.sigma\[0\]: numbers must be finite"),  # (experiment.json held NaN)
])
def test_a_swept_value_no_cell_uses_is_checked_too(tmp_path, planners, grid, words):
    path = tmp_path / "e.yaml"
    path.write_text(f"name: t\nworlds: [trap]\nplanners: {planners}\ntrials: 1\ngrid: {grid}\n")
    with pytest.raises(ExperimentError, match=words):
        load_experiment(path)


def test_an_experiment_mapping_takes_numpys_scalars():
    """load_experiment refused np.True_ and np.int64 ("a bool is not an experiment value ... got np.True_"),
    which navlab.plan takes (attack, session 25); they are read as Python's."""
    exp = load_experiment({"name": "z", "worlds": ["trap"], "trials": np.int64(2),
                           "planners": [{"name": "astar", "connectivity": np.int64(4)}],
                           "params": {"smooth": np.True_}, "grid": {"weight": [np.float32(1.5)]}})
    assert exp.trials == 2 and type(exp.trials) is int
    assert exp.planners[0].params == {"connectivity": 4} and type(exp.planners[0].params["connectivity"]) is int
    assert exp.params["smooth"] is True and type(exp.grid["weight"][0]) is float
    # (a namedtuple of values, which the first version rebuilt by its class: a raw TypeError; second review)
    from collections import namedtuple

    pair = namedtuple("pair", "low high")
    assert load_experiment({"name": "z", "worlds": ["trap"], "planners": ["astar"], "trials": 1,
                            "grid": {"weight": pair(1.0, 2.0)}}).grid == {"weight": [1.0, 2.0]}


def test_an_experiment_file_without_worlds_is_named(tmp_path):
    """"'worlds' is empty: nothing to run" named no file (an attack on the command, session 17)."""
    path = tmp_path / "e.yaml"
    path.write_text("worlds: []\nplanners: [astar]\n")
    with pytest.raises(ExperimentError, match="e.yaml: 'worlds' is empty"):
        load_experiment(path)


def test_a_raster_too_fine_to_count_is_one_line():
    from navlab.grid.rasterize import grid_shape
    from navlab.world.world import Bounds

    with pytest.raises(ValueError, match="more than 1e\\+08"):
        grid_shape(Bounds(0, 10, 0, 10), 1e-200)


@pytest.mark.parametrize("kind, name, params, words", [
    ("robot", "omni3", {"wheel_angles_deg": [float("nan"), 120, 240]}, "wheel_angles_deg must be finite"),
    ("robot", "diff", {"wheel_radius": float("inf")}, "wheel_radius"),
    ("controller", "potential_field", {"heading_gain": float("inf")}, "heading_gain must be finite"),
    ("controller", "goto_waypoint", {"heading_gain": float("nan")}, "heading_gain must be finite"),
    ("controller", "hybrid", {"replan_interval": 0}, "replan_interval must be > 0"),
    ("controller", "goto_waypoint", {"replan": True, "replan_interval": 0}, "replan_interval must be a positive"),
])
def test_non_finite_robot_and_controller_settings_are_named(kind, name, params, words):
    make = make_robot if kind == "robot" else make_controller
    with pytest.raises(ValueError, match=words):
        make(name, **params)


@pytest.mark.parametrize("name, params", [
    ("rpp", {"desired_linear_vel": -1}), ("dwa", {"max_vel_x": -1}), ("mppi", {"vx_max": 0}),
    ("pure_pursuit", {"speed": -1}), ("potential_field", {"max_speed": -1}),
])
def test_an_out_of_range_controller_setting_names_the_controller(name, params):
    setting = next(iter(params))
    with pytest.raises(ValueError, match=rf"{name}\b.*{setting}|{setting}.*{name}\b") as raised:
        make_controller(name, **params)
    assert str(raised.value).count(name) >= 1 and "Error" not in str(raised.value)


def test_the_cli_names_a_nan_wheel_angle():
    done = cli("sim", "one_obstacle", "--robot", "omni3", "--robot-param", "wheel_angles_deg=[.nan, 120, 240]")
    assert done.returncode == 2 and "wheel_angles_deg must be finite" in done.stderr


def _map_yaml(tmp_path, image):
    path = tmp_path / "m.yaml"
    path.write_text(f"image: {image}\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n"
                    "free_thresh: 0.2\nnegate: 0\n")
    return path


def test_pgm_pixels_that_are_not_whole_numbers(tmp_path):
    (tmp_path / "bad.pgm").write_text("P2\n2 2\n255\n0 255\n1.5 x\n")
    with pytest.raises(MapFormatError, match="bad.pgm: PGM pixel data must be whitespace-separated whole numbers"):
        load_map(_map_yaml(tmp_path, "bad.pgm"))


def test_moving_ai_headers_that_are_not_numbers(tmp_path):
    (tmp_path / "bad.map").write_text("type octile\nheight abc\nwidth 4\nmap\n....\n....\n")
    with pytest.raises(MapFormatError, match="bad.map: header 'height'"):
        load_map(tmp_path / "bad.map")


def test_nan_pixels_in_a_float_tiff(tmp_path):
    values = np.full((4, 4), 0.5, np.float32)
    values[1, 2] = np.nan
    Image.fromarray(values, mode="F").save(tmp_path / "nan.tif")
    with pytest.raises(MapFormatError, match=r"nan.tif: pixel \(row 1, column 2\) is nan"):
        load_map(_map_yaml(tmp_path, "nan.tif"))
    done = cli("grid", "plan", _map_yaml(tmp_path, "nan.tif"), "--start", "0", "0", "--goal", "3", "3")
    assert done.returncode == 2 and "RuntimeWarning" not in done.stderr


@pytest.mark.parametrize("optimum", ["nan", "-2", "inf"])
def test_scenario_optima_must_be_finite_and_non_negative(tmp_path, optimum):
    path = tmp_path / "bad.scen"
    path.write_text(f"version 1\n0\tarena.map\t49\t49\t1\t1\t3\t3\t{optimum}\n")
    with pytest.raises(MapFormatError, match="line 2: the optimal length must be a finite number >= 0"):
        read_scen(path)


def test_ros_parameters_with_a_floor_or_non_finite():
    pytest.importorskip("rclpy")
    from navlab.ros.base import Param, coerce

    with pytest.raises(ValueError, match="scan_rate must be at least 0"):
        coerce(Param("scan_rate", 10.0, "", low=0.0), -5.0)
    with pytest.raises(ValueError, match="scan_latency must be a finite number"):
        coerce(Param("scan_latency", 0.0, "", low=0.0), float("nan"))
    assert np.isnan(coerce(Param("x", float("nan"), ""), float("nan")))  # NaN means "unset" where it is the default


@pytest.mark.parametrize("call", ["plan", "plan_world", "line_of_sight", "plan_hybrid"])
@pytest.mark.parametrize("grid", [np.zeros((20, 20), bool), None, [[0, 0], [0, 0]]])
def test_a_grid_that_is_not_an_occupancy_grid_is_named(call, grid):
    """An array of cells is the usual mistake: every grid function names ``grid`` (an AttributeError before)."""
    from navlab.grid import line_of_sight, plan, plan_world
    from navlab.grid.hybrid_astar import plan_hybrid

    args = {"plan": (plan, ((1, 1), (5, 5))), "plan_world": (plan_world, ((0.3, 0.3), (0.8, 0.8))),
            "line_of_sight": (line_of_sight, ((1, 1), (5, 5))),
            "plan_hybrid": (plan_hybrid, ((0.3, 0.3, 0.0), (0.8, 0.8, 0.0), 0.4))}
    fn, rest = args[call]
    with pytest.raises(ValueError, match="grid must be an OccupancyGrid"):
        fn(grid, *rest)


@pytest.mark.parametrize("footprint, words", [("abc", "footprint must be a disc's radius [m] or 3 or more"),
                                              ([[np.nan, 0.1], [-0.1, 0.1], [0, -0.1]], "must be finite"),
                                              ([0, 0, 1, 1, 2, 2], "got shape (6,)")])
def test_a_footprint_that_is_no_outline_is_named(footprint, words):
    from navlab.grid.hybrid_astar import plan_hybrid
    from navlab.grid.occupancy import OccupancyGrid

    with pytest.raises(ValueError) as err:
        plan_hybrid(OccupancyGrid(np.zeros((20, 20), bool), resolution=0.1), (0.5, 0.5, 0), (1.5, 1.5, 0), 0.4,
                    footprint=footprint)
    assert words in str(err.value) and "footprint" in str(err.value)


@pytest.mark.parametrize("call", ["plan", "plan_hybrid", "dubins"])
def test_a_heading_too_large_for_a_float_is_named_and_longdouble_is_a_heading(call):
    """10**400 as a heading was a raw OverflowError from navlab.plan and 'too large (≤ 1e7)' from
    plan_hybrid and the solvers, and np.longdouble was refused by navlab.plan only (attack check,
    session 16)."""
    from navlab.grid import OccupancyGrid
    from navlab.grid.hybrid_astar import plan_hybrid
    from navlab.sampling import dubins

    grid = OccupancyGrid(np.zeros((40, 60), bool), 0.1)
    run = {"plan": lambda h: navlab.plan(grid, "hybrid_astar", start=(1.0, 1.0, h), goal=(4.0, 2.0, 0.0),
                                         turning_radius=0.5),
           "plan_hybrid": lambda h: plan_hybrid(grid, (1.0, 1.0, h), (4.0, 2.0, 0.0), 0.5),
           "dubins": lambda h: dubins.shortest((0, 0, h), (3, 1, 0.5), 1.0)}[call]
    with pytest.raises(ValueError, match=r"^start theta must be a finite heading in radians, got an integer of 401"):
        run(10 ** 400)
    long, plain = run(np.longdouble(1.25)), run(1.25)
    assert getattr(long, "cost", None) == getattr(plain, "cost", None)
    assert getattr(long, "length", None) == getattr(plain, "length", None)


def test_a_weight_too_large_for_a_float_is_named():
    """grid.plan(weight=10**400) was a raw OverflowError (attack check, session 16)."""
    from navlab.grid import OccupancyGrid, plan

    with pytest.raises(ValueError, match="weight must be a finite number >= 1, got an integer of 401 digits"):
        plan(OccupancyGrid(np.zeros((10, 10), bool)), (1, 1), (8, 8), weight=10 ** 400)


@pytest.mark.parametrize("shape, across", [({"robot_radius": 100.0}, 200),
                                           ({"footprint": [[-6, -5], [6, -5], [6, 5], [-6, 5]]}, 10)])
def test_a_robot_wider_than_the_map_is_told_before_any_table(shape, across):
    """A 100 m disc on a 6 x 8 m map took 19 s and 7.7 GB of footprint tables to be told its start
    leaves the map (attack check, session 16): told at once that it fits nowhere. A robot that fits
    one way (10 x 0.4 m: no wider than the map) gets the start's answer as before."""
    from navlab.grid import OccupancyGrid
    from navlab.grid.hybrid_astar import plan_hybrid

    grid = OccupancyGrid(np.zeros((60, 80), bool), 0.1)
    r = plan_hybrid(grid, (1.0, 1.0, 0.0), (5.05, 3.05, 0.0), 0.5, **shape)
    assert r.status is navlab.Status.INVALID_START
    assert r.reason == (f"the robot's footprint is {across} m across at its narrowest, {across - 8} m wider than the "
                        "map's longer side (8 x 6 m): it fits nowhere on it")
    thin = plan_hybrid(grid, (1.0, 1.0, 0.0), (5.05, 3.05, 0.0), 0.5,
                       footprint=[[-5, -0.2], [5, -0.2], [5, 0.2], [-5, 0.2]])
    assert thin.status is navlab.Status.INVALID_START and "leaves the map" in thin.reason


def test_a_robot_that_fits_nowhere_is_told_so_whatever_its_turning_radius():
    """A 1e6 m disc was told its turning radius of 0.5 m was too small (the scale check ran first), and
    a disc 0.2 µm wider than a 1 m map read '1 m across ..., wider than the map (1 x 1 m)' (attack check)."""
    from navlab.grid import OccupancyGrid
    from navlab.grid.hybrid_astar import plan_hybrid

    square = OccupancyGrid(np.zeros((10, 10), bool), 0.1)
    huge = plan_hybrid(square, (0.5, 0.5, 0.0), (0.5, 0.5, 1.0), 0.5, robot_radius=1e6)
    assert huge.status is navlab.Status.INVALID_START and "fits nowhere" in huge.reason
    hair = plan_hybrid(square, (0.5, 0.5, 0.0), (0.5, 0.5, 1.0), 0.5, robot_radius=0.5000001)
    assert "1 m across at its narrowest, 2e-07 m wider than the map's longer side (1 x 1 m)" in hair.reason


def test_a_footprint_lattice_larger_than_memory_is_refused(monkeypatch):
    """The lattice's footprint cells grow with (reach / resolution)^2 x bins: refused with the estimate
    when the machine has less (here: a machine said to have 64 MiB)."""
    import navlab.limits
    from navlab.grid import OccupancyGrid
    from navlab.grid.hybrid_astar import plan_hybrid

    monkeypatch.setattr(navlab.limits, "available_memory", lambda: 64 * 2 ** 20)
    with pytest.raises(ValueError, match=r"^robot_radius: a robot of 28.7 m² \(with a margin of two cells\) on 0.01 m "
                                         r"cells with 72 heading bins needs about .* more than the 64 MiB"):
        plan_hybrid(OccupancyGrid(np.zeros((800, 800), bool), 0.01), (4.0, 4.0, 0.0), (5.0, 4.0, 0.0), 0.5,
                    robot_radius=3.0)


@pytest.mark.parametrize("heading, planned", [("1e8", 1.9427), ("400", -2.1239)])
def test_a_world_file_takes_any_finite_heading_as_the_api_does(tmp_path, heading, planned):
    """A world file's start heading of 1e8 was refused as 'out of range (≤ 1e+07 m)' while the API and
    the flags took it (attack check, session 16): wrapped, with the HeadingWarning."""
    from navlab.angles import HeadingWarning

    path = tmp_path / "w.yaml"
    path.write_text(f"bounds: {{x: [0, 10], y: [0, 10]}}\nstart: [1, 1, {heading}]\ngoal: [9, 9]\n")
    with pytest.warns(HeadingWarning, match=re.escape(f"start theta {float(heading):g} is beyond")):
        world = navlab.load_world(path)
    assert world.start_heading == pytest.approx(planned, abs=1e-4)
    path.write_text("bounds: {x: [0, 10], y: [0, 10]}\nstart: [1, 1, .nan]\ngoal: [9, 9]\n")
    with pytest.raises(ValueError, match=r"field 'start\[2\]' must be a finite heading in radians"):
        navlab.load_world(path)


def test_a_heading_beyond_floats_range_is_named_as_such():
    """np.longdouble('1e4000') was 'must be a finite heading' though finite, and Fraction(10**400, 3)
    'an integer of 400 digits' (attack check, session 16)."""
    from fractions import Fraction

    from navlab.angles import finite_heading

    for value in (np.longdouble("1e4000"), Fraction(10 ** 400, 3)):
        with pytest.raises(ValueError, match="^goal theta must be a finite heading in radians, got a number beyond "
                                             "float's range$"):
            finite_heading("goal theta", value)


HUGE = 10 ** 400  # an int past float's range: math.isfinite raises OverflowError on it


@pytest.mark.parametrize("call, words", [
    (lambda: navlab.plan("clutter", planner="astar", weight=HUGE), "weight must be a finite number >= 1, got an "
                                                                   "integer of 401 digits"),
    (lambda: navlab.plan("clutter", planner="jps", resolution=HUGE), "resolution must be a finite number"),
    (lambda: navlab.plan("clutter", planner="astar", costmap=True, cost_scaling_factor=HUGE), "cost_scaling_factor"),
    (lambda: simulate("one_obstacle", robot_params={"max_speed": HUGE}), "max_speed must be finite, got an integer of 401 digits"),
    (lambda: simulate("one_obstacle", dt=HUGE), "time step dt must be a positive number of seconds, got an "
                                                       "integer of 401 digits"),
    (lambda: simulate("one_obstacle", max_time=HUGE), "max_time must be a positive"),
    # a length past navlab's range overflowed squaring it in the collision check
    (lambda: simulate("one_obstacle", robot_params={"radius": 1e300}), "radius = 1e\\+300 is out of range"),
    (lambda: simulate("one_obstacle", robot="car", robot_params={"wheelbase": HUGE}), "wheelbase"),
    (lambda: simulate("one_obstacle", lidar=3), "lidar must be 'none', 'exact' or a noise model's name"),
])
def test_settings_past_floats_range_or_of_the_wrong_kind_are_named(call, words):
    """An OverflowError ('int too large to convert to float', no field named) from four settings'
    checks, an OverflowError from a 1e300 m robot radius and an AttributeError from lidar=3 (an
    attack on the API, session 17): each is a ValueError naming the setting."""
    with pytest.raises(ValueError, match=words):
        call()


def test_a_setting_past_floats_range_is_a_usage_error_on_the_command_line():
    """The same reached the command as 'internal error: OverflowError' with exit 1."""
    for args in (["plan", "clutter", "--planner", "astar", "--param", f"weight={HUGE}"],
                 ["sim", "one_obstacle", "--robot-param", f"max_speed={HUGE}"],
                 ["sim", "one_obstacle", "--robot-param", "radius=1e300"]):
        res = cli(*args)
        assert res.returncode == 2 and "internal error" not in res.stderr and len(res.stderr.splitlines()) == 1, \
            res.stderr


def test_a_lidar_noise_that_is_no_model_is_named():
    from navlab.sensors.lidar import Lidar

    with pytest.raises(ValueError, match="lidar noise must be a model's name"):
        Lidar(noise=3)


@pytest.mark.parametrize("planner", ["rrt", "rrt_star", "informed_rrt_star", "growth_ratio_rrt"])
@pytest.mark.parametrize("value", ["yes", 2, None])
def test_keep_tree_must_be_true_or_false(planner, value):
    """keep_tree='yes' and 2 were taken as true, where the grid planners refuse smooth='yes'
    (an attack on the API, session 17)."""
    with pytest.raises(ValueError, match="keep_tree must be true or false"):
        navlab.plan("trap", planner=planner, keep_tree=value, max_iter=20)


def test_a_goal_bias_base_that_is_no_sampler_names_the_field():
    from navlab.registry import UnknownNameError

    with pytest.raises(UnknownNameError, match="^base: unknown sampler 'bogus'"):
        navlab.plan("trap", sampler="goal_bias", base="bogus", max_iter=20)


@pytest.mark.parametrize("args, words", [
    (["plan", "trap", "--param", "sampler=gaussian", "--max-iter", "50"], "give --sampler gaussian instead"),
    (["sim", "one_obstacle", "--max-time", "1", "--plan-param", "sampler=gaussian"],
     "plan_params: 'sampler' is the run's own setting"),
    (["sim", "one_obstacle", "--max-time", "1", "--controller", "potential_field", "--controller-param", "alpha=abc"],
     "potential field alpha must be a finite number, got 'abc'"),
    (["sim", "one_obstacle", "--max-time", "1", "--controller", "potential_field", "--controller-param",
      "stall_window=abc"], "stall_window must be a finite number"),
    (["sim", "one_obstacle", "--max-time", "1", "--robot", "diff", "--controller", "pure_pursuit",
      "--controller-param", "lookahead=1e300"], "pure_pursuit lookahead = 1e+300 is out of range"),
    (["sim", "one_obstacle", "--max-time", "1", "--robot", "diff", "--controller", "dwa", "--controller-param",
      "sim_granularity=1e-9"], "give rollouts of up to 2.2e+08 steps, more than 10000"),
    (["grid", "maze", "--cells", "3", "3", "--out", ""], "'': not a file name for the map's YAML"),
    (["bench", "--world", "trap", "--planner", "rrt", "--grid", "expand_dis=[!!timestamp 2001-01-01]", "--trials", "1"],
     "Error: grid.expand_dis[0]: a date is not an experiment value"),
    (["bench", "--suite", "smoke", "--out", ""], "--out must name a folder, got ''"),  # it wrote into '.'
    # (a field of the experiment the flags make, "worlds[0].queries[0][0]: numbers must be finite", and the
    # node's "goal y must be finite": review, session 31)
    (["bench", "--world", "maze.yaml", "--start", "nan", "0.3", "--goal", "1", "1", "--planner", "astar"],
     "Invalid value for '--start': 'nan' is not a finite number"),
    (["ros", "demo", "--goal", "3.5", "nan"], "Invalid value for '--goal': 'nan' is not a finite number"),
    (["ros", "demo", "--yaw", "inf"], "Invalid value for '--yaw': 'inf' is not a finite number"),
])
def test_bad_input_an_attack_found_reaching_internal_errors_is_one_line(args, words, tmp_path, monkeypatch):
    """An attack on the command (session 17, after only navlab's own errors counted as bad input) found
    these reaching 'internal error' (TypeError, OverflowError, a ValueError of pathlib's) or, for DWA's
    sim_granularity, a run that never ended."""
    from click.testing import CliRunner

    from navlab.cli import main

    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, args, prog_name="navlab")
    assert result.exit_code == 2 and "internal error" not in result.output, result.output
    lines = [x for x in result.output.splitlines() if x.strip()]
    assert len(lines) == 1 and words in lines[0], result.output


def test_a_map_reaching_past_the_coordinate_range_is_named(tmp_path):
    """A map whose origin is in range but whose far edge is not said 'bounds.xmax = 1e+07 is out of
    range (≤ 1e+07)', naming neither the map nor the true value (an attack on the command, session 17)."""
    Image.fromarray(np.full((4, 4), 254, dtype=np.uint8)).save(tmp_path / "ok.pgm")
    (tmp_path / "far.yaml").write_text("image: ok.pgm\nresolution: 0.5\norigin: [9999999, 0, 0]\nnegate: 0\n"
                                       "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    with pytest.raises(navlab.ParameterError, match="far.yaml: bounds.xmax = 10000001 is out of range"):
        navlab.plan(str(tmp_path / "far.yaml"), planner="rrt", start=(9999999.5, 0.5), goal=(9999999.9, 1.5))


@pytest.mark.parametrize("what", ["footprint", "padding", "circle", "rear_wheel_feedback", "goto_waypoint",
                                  "sensor timing"])
def test_the_classes_themselves_name_an_integer_past_floats_range(what):
    """Beneath make_controller's and the world file's own checks (an OverflowError until session 18, review)."""
    from navlab.control.followers import GotoWaypoint
    from navlab.control.path_tracking import RearWheelFeedback
    from navlab.sensors.timing import SensorTiming
    from navlab.world.footprint import Footprint
    from navlab.world.shapes import Circle

    make = {"footprint": lambda: Footprint(radius=HUGE), "padding": lambda: Footprint(radius=0.2).padded(HUGE),
            "circle": lambda: Circle((0, 0), HUGE), "rear_wheel_feedback": lambda: RearWheelFeedback(speed=HUGE),
            "goto_waypoint": lambda: GotoWaypoint(replan_interval=HUGE),
            "sensor timing": lambda: SensorTiming(rate=HUGE)}[what]
    with pytest.raises(navlab.NavlabError, match="an integer of 401 digits"):
        make()


@pytest.mark.parametrize("params, words", [
    ({"costmap": True, "cost_travel_multiplier": HUGE}, "cost_travel_multiplier must be a number ≥ 0, got an integer"),
    ({"planner": "hybrid_astar", "footprint": [[0, 0], [1, 0], [1, HUGE]]}, "footprint points must be")])
def test_planner_settings_past_floats_range_are_named(params, words):
    """(an OverflowError, an internal error, until session 18's second attack)"""
    params = {"planner": "astar", **params}
    with pytest.raises(navlab.NavlabError, match=words):
        navlab.plan("narrow_aisle" if params["planner"] == "hybrid_astar" else "squarefield", **params)


def test_a_path_that_fails_the_exact_check_names_its_leg_in_plain_numbers():
    """(it showed "(np.float64(5.275), np.float64(6.725))": costmap A* with cost_travel_multiplier=0 on squarefield)"""
    from navlab.queries import _leg_not_free

    path = np.array([[5.225, 6.725], [5.275, 6.725], [5.325, 6.725]])
    assert _leg_not_free("costmap", path, 1) == ("the costmap path's leg 1 from (5.275, 6.725) to (5.325, 6.725) is "
                                                 "not free in the exact world")


@pytest.mark.parametrize("sampler", [0, False, 1.5])
def test_a_sampler_that_is_not_a_name_is_refused(sampler):
    """(0 and False were read as "uniform": second attack run, session 18)"""
    with pytest.raises(navlab.NavlabError, match="sampler"):
        navlab.plan("squarefield", planner="rrt", sampler=sampler, max_iter=100)


def test_a_resolution_too_fine_to_count_names_no_inf():
    with pytest.raises(navlab.NavlabError, match=r"to 6e\+300 x 6e\+300 cells, more than 1e\+08") as err:
        navlab.plan("narrow_aisle", planner="hybrid_astar", resolution=1e-300)
    assert "inf" not in str(err.value)


@pytest.mark.parametrize("call, words", [
    (lambda: load_map(None), "path: expected a file name (text without NUL), got None"),
    (lambda: read_scen(3), "path: expected a file name (text without NUL), got 3"),
    (lambda: load_map("a\0b.yaml"), "path: expected a file name"),
    (lambda: navlab.grid.OccupancyGrid(np.zeros((4, 4), bool)).world_to_cell("ab"),
     "world points: expected (x, y) numbers or an (N, 2) array, got 'ab'"),
    (lambda: navlab.grid.OccupancyGrid(np.zeros((4, 4), bool)).world_to_cell([1.0, 2.0, 3.0]),
     "world points: expected (x, y) numbers"),
    (lambda: navlab.grid.OccupancyGrid(np.zeros((4, 4), bool)).cell_to_world("ab"),
     "cells: expected (x, y) numbers or an (N, 2) array"),
    # checked before the view is copied: 40 GB were asked for first
    (lambda: navlab.grid.OccupancyGrid(np.broadcast_to(np.zeros(1, bool), (200_000, 200_000))),
     "blocked has 40000000000 cells, more than the 1e+08"),
])
def test_wrong_types_in_the_grid_api_are_named(call, words):
    """Each was Python's or numpy's own TypeError, ValueError or MemoryError (API attack, session 29)."""
    with pytest.raises(navlab.errors.ParameterError, match=re.escape(words)):
        call()


def test_world_to_cell_still_takes_one_point_and_many():
    grid = navlab.grid.OccupancyGrid(np.zeros((4, 4), bool), resolution=0.5)
    assert grid.world_to_cell((1.2, 0.3)).tolist() == [2, 0]
    assert grid.world_to_cell([[1.2, 0.3], [0.1, 1.9]]).tolist() == [[2, 0], [0, 3]]


@pytest.mark.parametrize("make, words", [
    (lambda: navlab.world.Circle((1, "b"), 1.0), "circle center must be two finite numbers [x, y], got (1, 'b')"),
    (lambda: navlab.world.Rectangle("ab", (1, 1)), "rectangle min must be two finite numbers"),
    (lambda: navlab.world.Polygon("abc"), "polygon point must be two finite numbers [x, y], got 'a'"),
])
def test_shapes_given_text_name_the_field(make, words):
    """numpy's "could not convert string to float" before (API attack, session 29)."""
    with pytest.raises(navlab.errors.ParameterError, match=re.escape(words)):
        make()


def test_robot_lengths_as_numpy_floats_are_taken_as_floats():
    """np.float32(0.05) was refused as "must be a positive number" (API attack, session 29)."""
    robot = make_robot("diff", wheel_radius=np.float32(0.05), track=np.float64(0.2), radius=np.int64(1))
    assert type(robot.wheel_radius) is float and robot.wheel_radius == pytest.approx(0.05)
    assert type(robot.radius) is float and robot.radius == 1.0
    with pytest.raises(navlab.errors.ParameterError, match="wheel_radius must be a positive number, got True"):
        make_robot("diff", wheel_radius=True)
