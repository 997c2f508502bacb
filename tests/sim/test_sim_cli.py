"""``navlab sim``: moving worlds, tree planners on maps, timings, one-line errors, GIF writing."""

import errno
import math

import pytest
from click.testing import CliRunner

from navlab.cli import main

CROSSING = """name: crossing
bounds: {x: [0, 10], y: [0, 4]}
start: [1, 2]
goal: [9, 2]
obstacles:
  - {type: circle, center: [5, 0.6], radius: 0.3, motion: {waypoints: [[5, 3.5], [5, 0.5]], speed: 0.2}}
"""


@pytest.fixture()
def crossing(tmp_path):
    path = tmp_path / "crossing.yaml"
    path.write_text(CROSSING)
    return path


def test_replanning_follower_on_a_moving_world_and_its_gif(tmp_path, crossing):
    from navlab.sim.runner import simulate
    from navlab.viz.sim_plot import animate_run

    res = CliRunner().invoke(main, ["sim", str(crossing), "--robot", "diff", "--controller-param", "replan=true",
                                    "--json"])
    assert res.exit_code == 0 and '"status": "REACHED"' in res.output
    result, world, sim = simulate(str(crossing), robot="diff", controller_params={"replan": True}, max_time=10.0)
    gif = tmp_path / "run.gif"
    animate_run(world, result, str(gif), sim.robot.radius, max_frames=4, progress=True)
    assert gif.read_bytes()[:3] == b"GIF"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["crossing.yaml", "run.gif"]  # no temporary left


def test_disk_full_while_writing_a_gif_is_one_line_and_leaves_no_file(tmp_path, monkeypatch):
    from PIL import Image

    def full(self, filename, *args, **kwargs):
        with open(filename, "wb") as f:
            f.write(b"GIF89a")  # a torn start
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", full)
    gif = tmp_path / "run.gif"
    res = CliRunner().invoke(main, ["sim", "one_obstacle", "--gif", str(gif)])
    assert res.exit_code == 2 and len(res.output.strip().splitlines()) == 1
    assert "run.gif" in res.output and "No space left" in res.output
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, words", [
    (["clutter", "--start", "1", "1", "inf"], "Invalid value for '--start': coordinates and headings must be finite"),
    (["clutter", "--goal", "nan", "2"], "Invalid value for '--goal': coordinates and headings must be finite"),
    (["one_obstacle", "--lidar-timing", "latency=-0.5"], "lidar: field 'latency'"),
    (["one_obstacle", "--odom-timing", "rate=0"], "odometry: field 'rate'"),
])
def test_bad_input_is_one_line_and_exit_2(args, words):
    res = CliRunner().invoke(main, ["sim", *args])
    assert res.exit_code == 2 and words in res.output and len(res.output.strip().splitlines()) == 1


def test_tree_planner_on_a_map(tmp_path):
    from navlab.grid import make_maze
    from navlab.grid.mapio import save_map

    save_map(make_maze(4, 4, seed=1, cell_size=0.6, wall=0.1, resolution=0.05), tmp_path / "maze.yaml")
    res = CliRunner().invoke(main, ["sim", str(tmp_path / "maze.yaml"), "--robot", "diff", "--start", "0.35", "0.35",
                                    "0", "--goal", "2.15", "2.15", "--planner", "rrt_star", "--sampler",
                                    "integration"])
    assert res.exit_code == 0, res.output
    assert res.output.startswith("REACHED")


def test_latency_on_the_command_line_still_reaches():
    res = CliRunner().invoke(main, ["sim", "one_obstacle", "--controller", "potential_field", "--lidar-timing",
                                    "rate=10,latency=0.5", "--odom-timing", "rate=50", "--odom-timing", "latency=0.08"])
    assert res.exit_code == 0 and res.output.startswith("REACHED")


def test_the_simulator_takes_any_finite_heading_as_the_planners_do():
    """The simulator refused a start θ beyond ±1e7 rad ("out of range") where the planners take any
    finite heading, wrapped (session 16's left-alone list): the same run either way, and a note
    beyond ±2π, since that is most often degrees."""
    import math
    import warnings

    import numpy as np

    from navlab.angles import HeadingWarning
    from navlab.sim.runner import simulate

    far = 1e8
    with pytest.warns(HeadingWarning, match="start theta 1e\\+08 is beyond ±2π"):
        a, _, _ = simulate("one_obstacle", robot="diff", start=(1.0, 1.0, far), seed=2, max_time=5.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b, _, _ = simulate("one_obstacle", robot="diff", start=(1.0, 1.0, math.remainder(far, 2 * math.pi)), seed=2,
                           max_time=5.0)
    assert a.status == b.status and np.array_equal(a.true_poses, b.true_poses)
    res = CliRunner().invoke(main, ["sim", "one_obstacle", "--start", "1", "1", "1e300"])
    assert "Error" not in res.output and "note: start theta 1e+300 is beyond ±2π" in res.output, res.output


def test_a_run_reports_its_simulated_time_at_every_step_to_the_progress_callback():
    """The command line draws its bar from these calls (a terminal only: CliRunner's stderr is none)."""
    from navlab.sim.runner import simulate

    seen = []
    result, *_ = simulate("one_obstacle", robot="diff", progress=lambda t, limit: seen.append((t, limit)))
    times, limits = zip(*seen)
    # every step's time, the step that ended the run included (dt 0.05 s, the default)
    assert times == tuple(k * 0.05 for k in range(result.steps + 1))
    assert set(limits) == {limits[0]} and limits[0] == int(limits[0]) > result.time_s  # whole seconds, not reached
    out = CliRunner().invoke(main, ["sim", "one_obstacle", "--robot", "diff"])
    assert out.exit_code == 0 and "simulated [" not in out.output  # no bar off a terminal


@pytest.mark.parametrize("world, extra", [("one_obstacle", []),
                                          ("jackal_world", ["--start", "-2", "3", "1.57", "--controller", "dwa"])])
def test_a_footprint_robots_goal_off_the_map_is_invalid_goal(world, extra):
    """(an IndexError, an internal error, for the jackal with every costmap controller: attack run, session 18)"""
    from pathlib import Path

    if world == "jackal_world":
        world = Path(__file__).parents[2] / ".." / "shared" / "data" / "barn" / "world_0.world"
        if not world.is_file():
            pytest.skip("needs ../shared/data/barn")
    out = CliRunner().invoke(main, ["sim", str(world), "--robot", "jackal", "--goal", "100", "100", *extra])
    assert out.exit_code == 1, out.output
    # as a disc robot's is said (it was "the robot's footprint left the bounds", no bounds given: newcomer, s. 30)
    assert out.output.startswith("INVALID_GOAL (the goal (100, 100) is outside the bounds x=[")


def test_a_goal_a_lopsided_footprint_fits_at_one_heading_only_is_not_invalid():
    """A footprint 0.6 m ahead of its wheels and 0.05 m behind fits the corner at (3.85, 1.35) of one_obstacle
    only facing south-west (3.93 rad): half the circle, at 8 headings, was tried, and the goal was refused as
    INVALID_GOAL (attack, session 23). Checked against shapely: the footprint at 3.93 rad lies in the bounds."""
    from shapely.geometry import Polygon, box
    from shapely.affinity import rotate, translate

    from navlab.robots import make_robot
    from navlab.sim.runner import check_endpoints
    from navlab.world.sources import load_source

    outline = [[-0.05, -0.05], [0.6, -0.05], [0.6, 0.05], [-0.05, 0.05]]
    world = load_source("one_obstacle")
    b = world.bounds
    placed = translate(rotate(Polygon(outline), 3.93, origin=(0, 0), use_radians=True), 3.85, 1.35)
    assert box(b.xmin, b.ymin, b.xmax, b.ymax).contains(placed)
    facing_east = translate(Polygon(outline), 3.85, 1.35)
    assert not box(b.xmin, b.ymin, b.xmax, b.ymax).contains(facing_east)
    robot = make_robot("diff", footprint=outline)
    check_endpoints(world, robot, world.start, (3.85, 1.35))  # no NoPathError
    with pytest.raises(Exception, match="the goal is in collision"):
        check_endpoints(world, robot, world.start, (3.85, 1.35), goal_heading=0.0)
    # refused at its own heading only, it is described at that heading (facing +x it read "is free": review,
    # session 29): free facing east 0.3 m from the west edge, the footprint leaves the bounds facing west
    check_endpoints(world, robot, world.start, (-0.7, 1.35), goal_heading=0.0)
    with pytest.raises(Exception, match=r"the goal is in collision: at \(-0.7, 1.35\) the robot's footprint "
                                        "crossed the bounds"):
        check_endpoints(world, robot, world.start, (-0.7, 1.35), goal_heading=math.pi)


def test_a_goal_at_the_start_has_a_tracking_error_not_nan():
    from navlab.sim.runner import simulate

    result, *_ = simulate("one_obstacle", robot="diff", goal=(0.0, 0.0), max_time=5)
    assert result.status.name == "REACHED" and result.tracking_error() == 0.0
    result, *_ = simulate("one_obstacle", robot="diff", goal=(0.02, 0.0), max_time=5)
    assert 0.0 <= result.tracking_error() <= 0.03  # within reach: the start's distance from that point at most


def test_the_bar_draws_simulated_seconds_against_the_limit_on_a_terminal(monkeypatch):
    """The bar itself, on a stand-in terminal (the run's 2 s delay set to 0)."""
    import io
    import sys
    import time

    import navlab.cli.sim as sim_cli

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    terminal = Terminal()
    monkeypatch.setattr(sim_cli, "BAR_DELAY", 0.0)
    monkeypatch.setattr(sys, "stderr", terminal)
    bar = sim_cli.SimulatedTimeBar()
    for step in range(3):  # slower than real time at first, as a run's start-up is
        bar(step * 0.05, 2.5)
        time.sleep(0.15)
    for step in range(3, 51):
        bar(step * 0.05, 2.5)
    bar.close()
    drawn = terminal.getvalue().replace("\r", "\n")
    assert "/2.5 s simulated [" in drawn and "s simulated/s]" in drawn  # the limit as given, not rounded
    assert "s/ s simulated" not in drawn  # (tqdm inverts a rate below 1: "1.83s/ s simulated" at start-up)


def test_a_progress_that_is_not_a_function_is_refused_before_the_run():
    """(progress=3 was a raw TypeError at the run's first step: attack, session 23)"""
    from navlab.errors import ParameterError
    from navlab.sim.runner import simulate

    with pytest.raises(ParameterError, match="^progress must be a function of \\(t, max_time\\) or None, got 3$"):
        simulate("one_obstacle", progress=3)
    seen = []
    result, _, _ = simulate("one_obstacle", progress=lambda t, most: seen.append((t, most)))
    assert result.status.name == "REACHED" and len(seen) == result.steps + 1  # (t = 0 and each step's end)
    assert seen[-1][0] == pytest.approx(result.time_s)
    assert len({most for _, most in seen}) == 1 and seen[0][1] > result.time_s  # the run's max_time throughout


def test_a_gif_to_a_name_that_is_not_a_gif_is_refused_before_the_run(tmp_path):
    """--gif out.png wrote GIF data into out.png without a word (newcomer, session 30)."""
    res = CliRunner().invoke(main, ["sim", "one_obstacle", "--gif", str(tmp_path / "out.png")])
    assert res.exit_code == 2 and "it is written as GIF: give a name ending in .gif" in res.output, res.output
    assert list(tmp_path.iterdir()) == []


def test_a_footprint_crossing_the_bounds_names_them():
    """"the robot's footprint left the bounds" gave no bounds (newcomer, session 30)."""
    out = CliRunner().invoke(main, ["sim", "clutter", "--robot", "jackal", "--goal", "13.9", "6"])
    assert out.exit_code == 1, out.output
    assert "the robot's footprint crossed the bounds x=[0, 14] y=[0, 12]" in out.output
    # a start pose that never was inside: no "left" (it read as driving out: newcomer, session 30)
    start = CliRunner().invoke(main, ["sim", "trap", "--robot", "jackal", "--start", "0.1", "0.1", "0"])
    assert start.exit_code == 1 and "at (0.1, 0.1) the robot's footprint crossed the bounds x=[0, 18] y=[0, 12]" \
        in start.output, start.output


@pytest.mark.parametrize("name, content", [("notes.txt", "x: 1\n"), ("map.pgm", "P5\n1 1\n255\n\x00")])
def test_sim_says_what_a_file_is_not_as_plan_does(name, content, tmp_path):
    """(sim read notes.txt as a world file, "field 'x': unknown field", and a map's image as "not a UTF-8
    text file", where plan said "unknown source format" and "an image alone is not a map": newcomer, s31)"""
    path = tmp_path / name
    path.write_text(content, encoding="latin-1")
    said = {}
    for verb in ("plan", "sim"):
        res = CliRunner().invoke(main, [verb, str(path)])
        assert res.exit_code == 2 and len(res.output.strip().splitlines()) == 1, res.output
        said[verb] = res.output.split(" (see ")[0]
    assert said["sim"] == said["plan"]
    assert ("unknown source format '.txt'" if name.endswith(".txt") else "an image alone is not a map") in said["sim"]


@pytest.mark.parametrize("args, named", [
    (["--experiment", "maze-astar", "--runs", "1", "--max-time", "2", "--dt", "0.2", "--robot", "car", "--plot",
      "e.png", "--gif", "e.gif"], "--robot, --dt, --max-time, --plot, --gif do not apply"),
    (["--experiment", "maze-astar", "--dt", "0.05"], "--dt does not apply"),  # (its default, given: still said)
    (["trap", "--plot-dir", "figs"], "--plot-dir applies to --experiment"),
])
def test_flags_an_experiment_does_not_take_are_refused_not_ignored(args, named, tmp_path, monkeypatch):
    """(--experiment ran with its own time step, time limit and robot whatever the flags said, and wrote no
    --plot or --gif: newcomer, session 32)"""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["sim", *args])
    assert res.exit_code == 2 and named in res.output, res.output
    assert not list(tmp_path.iterdir())
