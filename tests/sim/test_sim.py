"""The simulator: statuses, determinism, bad input, the seeds' experiments."""

import json
import math
import re

import numpy as np
import pytest
from click.testing import CliRunner

from navlab.cli import main
from navlab.control import GotoWaypoint, PotentialField
from navlab.robots import DiffDrive, Omni3
from navlab.sensors import Lidar
from navlab.sim import SimStatus, Simulation
from navlab.control.base import make_controller
from navlab.robots.kinematics import make_robot
from navlab.sim.runner import simulate
from navlab.world import load_world
from navlab.sim.experiments import seed002, seed004, seed004_world
from navlab.world import load_world


def test_driving_into_a_wall_is_a_collision_at_the_wall():
    world = load_world("trap")  # closed side x ∈ [7.6, 8.0]
    sim = Simulation(world, DiffDrive(), GotoWaypoint(), (6.0, 6.0, 0.0), (9.0, 6.0),
                     path=np.array([[6.0, 6.0], [9.0, 6.0]]))
    r = sim.run(0)
    assert r.status is SimStatus.COLLIDED
    assert 7.6 - 0.105 - 0.02 < r.final_true[0] <= 7.6 - 0.105 + 0.011  # within one step of contact


def test_potential_field_stalls_in_a_trap_and_says_so():
    world = load_world("trap")
    sim = Simulation(world, Omni3(), PotentialField(), (6.0, 6.0, 0.0), world.goal, lidar=Lidar(), max_time=120)
    r = sim.run(0)
    assert r.status is SimStatus.STALLED and r.time_s < 60


def test_same_seed_same_run_and_timeout():
    sim = Simulation(seed004_world((3.0, 0.0), True), Omni3(), PotentialField(), (0, 0, 0), (3.0, 0.0),
                     lidar=Lidar(noise="rplidar_a1"), max_time=4.0)
    a, b = sim.run(11), sim.run(11)
    assert a.status is SimStatus.TIMEOUT and a.time_s == pytest.approx(4.0)
    assert np.array_equal(a.true_poses, b.true_poses) and np.array_equal(a.odom_poses, b.odom_poses)


@pytest.mark.parametrize("kwargs, message", [
    ({"goal": (0.0, 1.5)}, "goal"),  # inside the obstacle
    ({"goal": (9.0, 0.0)}, "goal"),  # outside the world
    ({"start": (0.0, 1.45, 0.0)}, "starts in collision"),
    ({"dt": 0.0}, "dt"),
])
def test_bad_simulations_fail_before_running(kwargs, message):
    args = {"start": (0.0, 0.0, 0.0), "goal": (0.0, 3.0), "dt": 0.05, **kwargs}
    with pytest.raises(ValueError, match=message):
        Simulation(seed004_world((0.0, 3.0), True), Omni3(), PotentialField(), args["start"], args["goal"],
                   lidar=Lidar(), dt=args["dt"])


def test_seed004_reaches_every_target_within_tens_of_millimetres():
    rows = seed004(runs=1)
    assert len(rows) == 8 and all(r["status"] == "REACHED" for r in rows)
    assert all(r["error_true_mm"] < 60 and r["error_odom_mm"] < 40 for r in rows)
    assert all(10 < r["time_s"] < 25 for r in rows)


def test_seed002_mazes_are_solved_and_followed(tmp_path):
    rows = seed002(runs=1, plot_dir=str(tmp_path))
    assert [r["maze"] for r in rows] == ["10x10", "10x10", "15x15", "15x15"]
    assert all(r["status"] == "REACHED" for r in rows)
    assert all(r["max_tracking_error_m"] < 0.09 for r in rows)  # corridors leave 0.14 m each side
    assert all((tmp_path / r["plot"].split("/")[-1]).stat().st_size > 5000 for r in rows)


def test_cli_experiment_json_and_bad_input(tmp_path):
    runner = CliRunner()
    res = runner.invoke(main, ["sim", "--experiment", "seed004", "--runs", "1", "--json"])
    assert res.exit_code == 0, res.output
    rows = [json.loads(line) for line in res.output.splitlines()]
    assert len(rows) == 8 and {"target_mm", "obstacle", "status", "final_true_mm", "final_odom_mm", "error_true_mm",
                               "error_odom_mm", "time_s"} <= set(rows[0])
    # every length in mm says so in its key: "final_true" is metres in navlab sim --json (newcomer, session 29)
    assert not {"target", "final_true", "final_odom"} & set(rows[0])
    assert rows[0]["error_true_mm"] == pytest.approx(math.dist(rows[0]["final_true_mm"], rows[0]["target_mm"]))
    # a goal the robot cannot stand on is an answer about the world, as navlab plan's INVALID_GOAL (exit 1)
    res = runner.invoke(main, ["sim", "squarefield", "--goal", "50.0", "5.0"])
    # a point's own description, not "the goal is in collision: ... is outside the bounds" (newcomer, session 29)
    assert res.exit_code == 1 and res.output.startswith("INVALID_GOAL (the goal (50, 5) is outside the bounds ")
    res = runner.invoke(main, ["sim", "trap", "--goal", "7.8", "6.0"])  # inside the trap's wall
    assert res.exit_code == 1 and res.output.startswith("INVALID_GOAL (") and "inside obstacle" in res.output
    res = runner.invoke(main, ["sim", "clutter", "--goal", "4.75", "10.45"])  # 0.04 m from circle 0 (r 0.3 at y 10.11)
    assert res.exit_code == 1 and "of obstacle 0 (circle; clearance 0.04 m)" in res.output
    for controller in ("rpp", "dwa", "mppi"):  # the costmap controllers answer as the others do
        res = runner.invoke(main, ["sim", "clutter", "--controller", controller, "--goal", "4.75", "10.11"])
        assert res.exit_code == 1 and res.output.startswith("INVALID_GOAL (") and "inside obstacle 0" in res.output
    res = runner.invoke(main, ["sim", "clutter", "--controller", "rpp", "--start", "4.75", "10.11", "0"])
    assert res.exit_code == 1 and res.output.startswith("INVALID_START (")
    res = runner.invoke(main, ["sim", "squarefield", "--controller", "potential_feild"])
    assert res.exit_code == 2 and "Did you mean" in res.output
    res = runner.invoke(main, ["sim", "squarefield", "--robot-param", "wheel_radius=-0.1"])
    assert res.exit_code == 2 and "wheel_radius" in res.output
    res = runner.invoke(main, ["sim", "squarefield", "--dt", "0"])
    assert res.exit_code == 2 and "dt" in res.output
    gif = tmp_path / "run.gif"
    res = runner.invoke(main, ["sim", "squarefield", "--robot", "diff", "--gif", str(gif), "--plot",
                               str(tmp_path / "run.png"), "--max-time", "3"])
    assert res.exit_code == 1 and "TIMEOUT" in res.output
    assert gif.read_bytes()[:3] == b"GIF" and (tmp_path / "run.png").exists()


def test_logs_grow_with_the_run_not_with_max_time(monkeypatch):
    """A max_time of 10⁶ s would be 2·10⁷ rows up front; the logs double as the run goes on."""
    import tracemalloc

    from navlab.sim import simulation

    short = simulate("one_obstacle", max_time=60.0)
    monkeypatch.setattr(simulation, "INITIAL_LOG_ROWS", 16)  # so that this run grows them several times
    tracemalloc.start()
    try:
        long = simulate("one_obstacle", max_time=1e6)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 64 * 2**20
    assert long[0].steps == short[0].steps > 4 * simulation.INITIAL_LOG_ROWS  # the logs did grow, and lost nothing
    for name in ("true_poses", "odom_poses", "commands", "t"):
        assert np.array_equal(getattr(long[0], name), getattr(short[0], name)), name


@pytest.mark.parametrize("kwargs, message", [
    ({"dt": 1e-300}, "below the smallest supported step"),
    ({"max_time": float("inf")}, "max_time must be a positive, finite number"),
    ({"max_time": 1e300}, r"steps, more than the 1e\+08 a run supports"),
])
def test_runs_that_could_not_end_are_refused(kwargs, message):
    """--dt 1e-300 ran for ever and --max-time inf was an internal OverflowError."""
    with pytest.raises(ValueError, match=message):
        simulate("one_obstacle", **kwargs)


def test_lidar_beams_are_bounded():
    """10⁹ beams took 16 GB in the ROS sim node before this."""
    from navlab.sensors.lidar import MAX_BEAMS

    with pytest.raises(ValueError, match=f"from 1 to {MAX_BEAMS}"):
        Lidar(beams=10**9)
    assert Lidar(beams=MAX_BEAMS).angles.shape == (MAX_BEAMS,)


def test_an_experiment_records_a_world_without_a_path_and_goes_on(monkeypatch):
    """random-clutter --runs 200 stopped at world 195 (no path for the hybrid's plan) as if it were bad input."""
    from navlab.sim import experiments, runner

    real = runner.simulate

    def simulate_or_no_path(world, controller=None, **kwargs):
        if controller == "hybrid" and world.name.endswith("_1"):
            raise runner.NoPathError("no path for the robot from (1.0, 1.0) to (9.0, 9.0): APPROXIMATE")
        return real(world, controller=controller, **kwargs)

    monkeypatch.setattr(runner, "simulate", simulate_or_no_path)
    rows = experiments.hybrid_vs_field(runs=2)
    assert [r["status"] for r in rows][2:] == [rows[2]["status"], "NO_PATH"] and len(rows) == 4
    assert "APPROXIMATE" in rows[3]["reason"]
    table = experiments.hybrid_table(rows).splitlines()
    hybrid = next(line for line in table if line.split()[0] == "hybrid")
    assert int(hybrid.split()[3]) == 1  # counted under "other"
    # a line says what ran (the bare table did not: newcomer, session 29)
    assert table[0].startswith("The omni3 robot from (1, 1) to (9, 9) in 2 seeded random cluttered worlds ")


def test_reached_is_judged_on_the_true_pose_not_the_controllers_estimate():
    """A controller that says REACHED where the robot is not (its estimate is
    wrong) ends OFF_GOAL with the distance; `navlab sim clutter --dt 2.0`
    printed REACHED with the true pose 12.13 m from the goal."""
    from navlab.control.base import REACHED, Command, Controller
    from navlab.sim.simulation import GOAL_TOLERANCE, SimStatus

    class Deluded(Controller):
        def reset(self, goal, path=None):
            pass

        def command(self, t, pose, points=None):
            return Command(status=REACHED)

    world = load_world("squarefield")
    far = Simulation(world, make_robot("diff"), Deluded(), (*world.start, 0.0), world.goal).run()
    assert far.status is SimStatus.OFF_GOAL and "m from it" in far.reason
    near_goal = (world.goal[0] - GOAL_TOLERANCE / 2, world.goal[1], 0.0)
    near = Simulation(world, make_robot("diff"), Deluded(), near_goal, world.goal).run()
    assert near.status is SimStatus.REACHED


@pytest.mark.parametrize("dt", [0.2000001, 2.0, 1e308])
def test_a_time_step_past_the_largest_is_refused(dt):
    from navlab.sim.simulation import MAX_DT

    world = load_world("squarefield")
    with pytest.raises(ValueError, match=f"above the largest supported step, {MAX_DT:g} s"):
        Simulation(world, make_robot("diff"), make_controller("pure_pursuit"), (*world.start, 0.0), world.goal,
                   dt=dt)


def test_a_planner_that_finds_no_path_is_an_answer_exit_1_not_bad_input():
    res = CliRunner().invoke(main, ["sim", "trap", "--robot", "diff", "--planner", "rrt", "--sampler", "boundary"])
    assert res.exit_code == 1 and res.output.startswith("NO_PATH (") and "Error" not in res.output
    res = CliRunner().invoke(main, ["sim", "trap", "--robot", "diff", "--planner", "rrt", "--sampler", "boundary",
                                    "--json"])
    assert res.exit_code == 1 and json.loads(res.output)["status"] == "NO_PATH"


@pytest.mark.parametrize("planner", ["astar", "rrt_star"])
def test_a_start_the_robot_fits_at_is_valid_for_a_star_and_rrt_star_alike(tmp_path, planner):
    """The 10 x 10 maze's corner (0.35, 0.35): the diff robot (0.105 m) fits with 0.045 m to spare,
    less than the 0.07 m planning margin. RRT* refused it (INVALID_START) while A* accepted it."""
    from navlab.grid.maze import make_maze
    from navlab.grid.mapio import save_map
    from navlab.sim.replan import margin_room, plan_path

    grid = make_maze(10, 10, seed=1, cell_size=0.5, wall=0.1, resolution=0.05)
    assert 0 < margin_room(grid, 0.105, [(0.35, 0.35)]) < 0.07
    path = plan_path(grid, 0.105, (0.35, 0.35, 0.0), (4.8, 4.8), planner)
    assert isinstance(path, np.ndarray) and np.allclose(path[0], (0.35, 0.35)) and np.allclose(path[-1], (4.8, 4.8))


def test_a_world_radius_the_simulated_robot_lacks_is_noted(tmp_path):
    """A world's robot_radius is navlab plan's; the simulator moves the robot's own footprint, and says so
    when the two differ (a start 0.2 m from a wall, refused by plan for 0.5 m, ran to REACHED without a
    word: newcomer, session 29)."""
    (tmp_path / "near.yaml").write_text("bounds: {x: [0, 10], y: [0, 10]}\nstart: [1, 1]\ngoal: [9, 9]\n"
                                        "robot_radius: 0.5\nobstacles:\n"
                                        "  - {type: rectangle, min: [0.5, 1.2], max: [1.5, 2]}\n")
    runner = CliRunner()
    res = runner.invoke(main, ["sim", str(tmp_path / "near.yaml"), "--robot", "diff"])
    assert res.exit_code == 0 and res.stdout.startswith("REACHED"), res.output
    assert res.stderr == ("note: the world's robot_radius 0.5 m is navlab plan's; the simulated robot is its own "
                          "footprint, a disc of radius 0.105 m (--robot-param radius=0.5 gives it that size)\n")
    res = runner.invoke(main, ["sim", str(tmp_path / "near.yaml"), "--robot", "diff", "--robot-param", "radius=0.5"])
    assert res.exit_code == 1 and res.stdout.startswith("INVALID_START (") and "note:" not in res.output
    # a polygon footprint is changed with footprint=, not radius= (which sizes a disc: review, session 29)
    (tmp_path / "open.yaml").write_text("bounds: {x: [0, 10], y: [0, 10]}\nstart: [2, 2]\ngoal: [8, 8]\n"
                                        "robot_radius: 0.5\nobstacles: []\n")
    res = runner.invoke(main, ["sim", str(tmp_path / "open.yaml"), "--robot", "jackal", "--controller", "rpp"])
    assert res.exit_code == 0 and res.stderr.startswith("note: the world's robot_radius 0.5 m is navlab plan's; the "
                                                        "simulated robot is its own footprint, a 4-gon of "), res.output
    assert res.stderr.endswith("(--robot-param footprint=[[x, y], ...] gives it another shape)\n")
    # the robot at least as large as the world's radius (omni3's 0.16 m, trap's 0.15 m): no note
    res = runner.invoke(main, ["sim", str(tmp_path / "near.yaml"), "--robot-param", "radius=0.6"])
    assert res.exit_code == 1 and res.stdout.startswith("INVALID_START (") and res.stderr == ""
    res = runner.invoke(main, ["sim", "trap"])
    assert res.exit_code == 0 and res.stderr == "", res.output


def test_the_runs_help_gives_each_experiments_own_default():
    """--runs said no default (newcomer, session 29): the help lists each experiment's, which must be the
    experiment function's own."""
    import inspect

    import navlab.sim.latency  # noqa: F401 - registers sensor-latency
    from navlab.sim.experiments import EXPERIMENTS

    # (the help's words run on, whatever the wrapping: click may break a line after a name's hyphen)
    text = "".join(CliRunner().invoke(main, ["sim", "--help"]).output.split()).replace("-", "")
    for name in ("omni-potential-field", "maze-astar", "sensor-latency", "hybrid-vs-field"):
        default = inspect.signature(EXPERIMENTS.get(name)).parameters["runs"].default
        assert re.search(rf"[ ,]{default}(for)?{name.replace('-', '')}[,)]", text.replace(",", ", ")), name


@pytest.mark.parametrize("path, said", [
    ([[6, 6], [np.nan, 6], [16, 6]], "path: waypoints must be finite"),  # ran to COLLIDED with NaN poses
    ([[1e308, 6], [16, 6]], "path: waypoints must be finite and within"),  # numpy's overflow warnings
    ([], "path: expected (N, 2) waypoints"),  # an IndexError
    (np.zeros((3, 2, 2)), "path: expected (N, 2) waypoints"),  # a TypeError
    ("ab", "path: expected (N, 2) waypoints"),
])
def test_a_path_the_simulation_cannot_follow_is_refused_naming_it(path, said):
    """(API attack, session 29)"""
    from navlab.errors import ParameterError
    from navlab.world import load_world

    with pytest.raises(ParameterError, match=re.escape(said)):
        Simulation(load_world("trap"), Omni3(), make_controller("pure_pursuit"), (6, 6, 0), (16, 6), path=path)


@pytest.mark.parametrize("robot, controller, start, goal, field", [
    ("omni3", "ok", (6, 6, 0), (16, 6), "robot"), (None, "potential_field", (6, 6, 0), (16, 6), "controller"),
    (None, "ok", None, (16, 6), "start"), (None, "ok", "ab", (16, 6), "start"),
    (None, "ok", (6, 6, 0, 0), (16, 6), "start"), (None, "ok", (6, 6, 0), "ab", "goal"),
    (None, "ok", (6, 6, 0), (np.nan, 6), "goal"),
])
def test_the_simulation_names_a_part_it_cannot_take(robot, controller, start, goal, field):
    """A robot or a controller given by name, a start of None or text: AttributeError, TypeError or
    numpy's ValueError inside (API attack, session 29)."""
    from navlab.errors import ParameterError
    from navlab.world import load_world

    robot = Omni3() if robot is None else robot
    controller = PotentialField() if controller == "ok" else controller
    with pytest.raises(ParameterError, match=f"^{field}: expected"):
        Simulation(load_world("trap"), robot, controller, start, goal, lidar=Lidar())
