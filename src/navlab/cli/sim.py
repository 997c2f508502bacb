"""``navlab sim``: run the simulator on a world or map, or a seed's experiment."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import click

from ..wording import counted
from .common import (Count, PointOrPoseOption, PositiveNumber, SuggestingChoice, before_first_kernel, check_figure_file,
                     check_output_file, parse_params, status_if_output_is_cut)

#: runs per setting an experiment takes (each is a whole simulation: 10 000 of the shortest take minutes)
MAX_EXPERIMENT_RUNS = 10_000

#: experiment names the CLI offers (the registry is filled when sim.experiments is imported; listed here so
#: that `navlab --help` does not import the simulator)
EXPERIMENT_NAMES = ["omni-potential-field", "seed004", "maze-astar", "seed002", "sensor-latency", "seed004-latency",
                    "hybrid-vs-field", "random-clutter"]


@click.command("sim")
@click.argument("world", required=False)
@click.option("--robot", type=SuggestingChoice(["omni3", "diff", "jackal", "car"]), default="omni3", show_default=True,
              help="omni3 (seed 004's), diff (a TurtleBot3 Burger), jackal (the BARN robot: a 0.42 × 0.33 m "
                   "rectangle; default controller rpp) or car (a kinematic bicycle, 4.4 × 1.8 m, turning radius "
                   "4.5 m: plans between poses and reverses at cusps).")
@click.option("--controller", default=None,
              help="hybrid (omni3 default: a global plan, the potential field as local avoider), "
                   "potential_field (seed 004's field alone), goto_waypoint (diff default), pure_pursuit, "
                   "rear_wheel_feedback (car default; any robot on a path of poses), or the "
                   "costmap planners dwa, dwa_barn (the BARN challenge's settings), mppi, rpp (jackal default).")
@click.option("--start", cls=PointOrPoseOption, default=None,
              help="Start [m] and heading THETA [rad] (default: the world's start and heading, else 0).")
@click.option("--goal", cls=PointOrPoseOption, default=None,
              help="Goal [m] (default: the world's); with THETA [rad] the run plans between poses and must end "
                   "facing THETA (within 0.25 rad).")
@click.option("--planner", default=None,
              help="Global path for hybrid and the followers: any planner (`navlab list`; worlds default "
                   "rrt_star, maps astar, smoothed; between poses hybrid_astar).")
@click.option("--plan-param", "plan_params", multiple=True, metavar="KEY=VALUE",
              help="Global planner setting, e.g. motion=dubins, turning_radius=1.2, max_iter=20000.")
@click.option("--sampler", default="uniform", show_default=True,
              help="Sampler of a tree planner (rrt_star etc.), on worlds and maps.")
@click.option("--lidar", type=SuggestingChoice(["rplidar_a1", "exact", "none"]), default=None,
              help="LiDAR noise (default: exact when the controller needs a scan).")
@click.option("--robot-param", "robot_params", multiple=True, metavar="KEY=VALUE",
              help="Robot setting, e.g. wheel_radius=0.04 (see the docs).")
@click.option("--controller-param", "controller_params", multiple=True, metavar="KEY=VALUE",
              help="Controller setting, e.g. alpha=0.8 max_speed=0.25.")
@click.option("--dt", type=PositiveNumber(), default=0.05, show_default=True, help="Time step [s].")
@click.option("--max-time", type=PositiveNumber(), default=None,
              help="Simulated time limit [s] (default: 60 s + 4× the path's length at the robot's speed).")
@click.option("--lidar-timing", "lidar_timing", multiple=True, metavar="KEY=VALUE[,...]",
              help="LiDAR rate [Hz], latency [s] and jitter [s], e.g. rate=10,latency=0.5,jitter=0.12 (default: "
                   "every step, no delay).")
@click.option("--odom-timing", "odom_timing", multiple=True, metavar="KEY=VALUE[,...]",
              help="Odometry rate [Hz], latency [s] and jitter [s], e.g. rate=50,latency=0.08.")
@click.option("--seed", type=Count(low=0), default=0, show_default=True,
              help="Random seed of the run's noise (sensors, wheels; MPPI's samples) and of a tree planner, or an "
                   "experiment's base seed: same seed, same run.")
@click.option("--experiment", type=SuggestingChoice(EXPERIMENT_NAMES), default=None,
              help="Run an experiment instead (no WORLD): omni-potential-field (alias seed004), maze-astar "
                   "(seed002), sensor-latency (seed004-latency: seed 004 with its measured topic delays and a "
                   "crossing obstacle), hybrid-vs-field (random-clutter).")
@click.option("--runs", type=Count(high=MAX_EXPERIMENT_RUNS), default=None,
              help=f"Runs per setting (with --experiment; at most {MAX_EXPERIMENT_RUNS}; default: the "
                   "experiment's own, 5 for omni-potential-field, 1 maze-astar, 3 sensor-latency, 20 "
                   "hybrid-vs-field).")
@click.option("--plot-dir", type=click.Path(file_okay=False), default=None,
              help="Experiments: write a PNG per run here (seed002 default: sim-results/seed002).")
@click.option("--json", "as_json", is_flag=True, help="JSON output (one object per run for experiments).")
@click.option("--plot", type=click.Path(dir_okay=False), default=None,
              help="Figure of the run: PNG, or the format its suffix names (.svg, .pdf, ...).")
@click.option("--gif", type=click.Path(dir_okay=False), default=None, help="GIF animation of the run.")
@click.option("--trajectory", type=click.Path(dir_okay=False), default=None,
              help="CSV of the true pose at every step (header t,x,y,theta; s, m, m, rad).")
def sim_cmd(world, robot, controller, start, goal, planner, plan_params, sampler, lidar, robot_params, controller_params, dt,
            max_time, lidar_timing, odom_timing, seed, experiment, runs, plot_dir, as_json, plot, gif,
            trajectory) -> None:
    """Simulate a robot in WORLD (a world YAML, a scene name, a map_server
    YAML / Moving AI map, or a Gazebo SDF .world such as a BARN world)
    driving to --goal, or run an --experiment. The
    omni robot's default controller is the hybrid navigator (a global plan
    with the potential field as local avoider); obstacles with a `motion`
    move, and the robot can replan around them
    (--controller-param replan=true for the followers). Exit status 1 when
    the robot does not reach the goal, or when no path leads there
    (NO_PATH, INVALID_START, INVALID_GOAL: answers, as navlab plan gives them).

    \b
    Examples:
      navlab sim trap
      navlab sim --experiment omni-potential-field
      navlab sim clutter --robot diff --planner rrt_star --controller-param replan=true --plot run.png
      navlab sim maze.yaml --robot diff --start 0.35 0.35 0 --goal 4.8 4.8 --gif run.gif
      navlab sim maze.yaml --robot diff --start 0.35 0.35 0 --goal 4.8 4.8 --planner rrt_star --sampler integration
      navlab sim one_obstacle --controller potential_field --lidar-timing rate=10,latency=0.5
      navlab sim ../shared/data/barn/world_0.world --robot jackal --controller rpp --start -2 3 1.57 --trajectory t.csv
      navlab sim parking --robot car --plot parking.png
      navlab sim trap --robot diff --goal 16 6 3.14159 --plan-param turning_radius=0.5
    """
    if experiment:
        if world:
            raise click.UsageError("--experiment takes no WORLD")
        _refuse_flags_experiments_do_not_take()
        _experiment(experiment, runs, seed, plot_dir, as_json)
        return
    if runs is not None:
        raise click.UsageError("--runs applies to --experiment (a single simulation runs once)")
    if plot_dir is not None:
        raise click.UsageError("--plot-dir applies to --experiment (a single simulation's figure: --plot FILE)")
    if not world:
        raise click.UsageError("give a WORLD or --experiment")
    for flag, name, suffix in (("--trajectory", trajectory, ""), ("--gif", gif, ".gif")):
        if name:
            check_output_file(name, flag, suffix)
    if plot:
        check_figure_file(plot, "--plot")
    from ..sim.runner import NoPathError, simulate

    before_first_kernel()  # numba is imported by now (the simulator's kernels)
    began = time.perf_counter()
    bar = SimulatedTimeBar()
    try:
        result, scene_world, sim = simulate(world, robot=robot, controller=controller, start=start, goal=goal,
                                            planner=planner, sampler=sampler, lidar=lidar,
                                            robot_params=parse_params(robot_params, "--robot-param"),
                                            controller_params=parse_params(controller_params, "--controller-param"),
                                            dt=dt, max_time=max_time, seed=seed,
                                            lidar_timing=_timing(lidar_timing, "--lidar-timing"),
                                            odometry_timing=_timing(odom_timing, "--odom-timing"),
                                            plan_params=parse_params(plan_params, "--plan-param"),
                                            progress=bar)
    except NoPathError as exc:
        # the planner's answer about this world, as `navlab plan` gives it: not bad input
        status_if_output_is_cut(1)
        click.echo(json.dumps({"status": exc.status, "reason": str(exc)}) if as_json else f"{exc.status} ({exc})")
        sys.exit(1)
    finally:
        bar.close()
    _note_the_robots_own_size(scene_world, sim.robot)
    status = 0 if result.status.name == "REACHED" else 1  # (the exit status, also if the output is cut short)
    status_if_output_is_cut(status)
    if trajectory:
        from ..sim.trajectory import write_trajectory_csv

        write_trajectory_csv(result, trajectory)
    if plot:
        from ..viz.sim_plot import plot_run

        plot_run(scene_world, result, plot, footprint=sim.robot.shape)
    if gif:
        from ..viz.sim_plot import animate_run

        animate_run(scene_world, result, gif, sim.robot.radius, footprint=sim.robot.shape)
    if as_json:
        click.echo(json.dumps(result.to_dict(trajectory=True)))
    else:
        click.echo(f"{result.status.name}" + (f" ({result.reason})" if result.reason else "")
                   + f" after {result.time_s:.2f} s simulated in {result.wall_time_s * 1000:.0f} ms "
                   f"(real-time factor {result.real_time_factor:.0f}x, {counted(result.steps, 'step')})")
        setup_s = time.perf_counter() - began - result.wall_time_s
        if setup_s > 3.0:  # a first use compiles for up to minutes (loading them takes about a second): say so
            click.echo(f"  set-up before the run {setup_s:.1f} s (the world, the plan, compiling or loading kernels: "
                       "a first use compiles them once)")
        click.echo(f"  final true pose ({result.final_true[0]:.3f}, {result.final_true[1]:.3f}) m, "
                   f"{_distance(result.error_true)} from the goal; odometry says "
                   f"({result.final_odom[0]:.3f}, {result.final_odom[1]:.3f}), travelled {result.distance:.2f} m")
        if "goal_heading" in result.meta:
            click.echo(f"  final heading {result.final_true[2]:.3f} rad, {result.meta['heading_error_rad']:.3f} rad "
                       f"from the goal's {result.meta['goal_heading']:.3f}")
        if result.path is not None and result.replans:
            # the error is the distance from the first path, which the robot stopped following at a replan
            # (DWA on clutter: "max tracking error 3.116 m" from a path it dropped at once; newcomer, session 29)
            click.echo(f"  planned a {len(result.path)}-waypoint path and replanned "
                       f"{counted(result.replan_count, 'time')} (the last plan {len(result.replans[-1])} waypoints); "
                       f"the farthest from the first path: {result.tracking_error():.3f} m")
        elif result.path is not None:
            click.echo(f"  followed a {len(result.path)}-waypoint path, max tracking error "
                       f"{result.tracking_error():.3f} m")
        if sim.scene.dynamic:
            # the follower's replanner counts its tries, found or not; others (DWA's move_base) their paths
            replans = getattr(getattr(sim.controller, "replanner", None), "count", result.replan_count)
            click.echo(f"  {len(sim.scene.moving)} moving obstacle(s); closest approach "
                       f"{1000 * sim.min_clearance(result):.0f} mm; {replans} replan(s)")
        for what, name in (("trajectory", trajectory), ("plot", plot), ("animation", gif)):
            if name:
                click.echo(f"  {what} written to {name}")
    if status:
        sys.exit(status)


class SimulatedTimeBar:
    """A run's progress in simulated seconds, as a tqdm bar on standard error when that is a terminal,
    shown only once the run has taken :data:`BAR_DELAY` s of wall time (a jackal's MPPI run in a BARN world
    takes 10 s, a DWA run that times out 20 s; most runs end well under a second)."""

    def __init__(self) -> None:
        self.bar = None

    def __call__(self, t: float, max_time: float) -> None:
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=max_time, unit=" s simulated", file=sys.stderr, disable=None, leave=False,
                            dynamic_ncols=True, delay=BAR_DELAY, bar_format=BAR_FORMAT)
        self.bar.update(t - self.bar.n)  # tqdm redraws at most every 0.1 s

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


#: [s] of wall time before the bar shows
BAR_DELAY = 2.0
#: simulated seconds of the limit, wall time, and the real-time factor
BAR_FORMAT = "{l_bar}{bar}| {n:.1f}/{total:g} s simulated [{elapsed}, {rate_noinv_fmt}]"  # (not "1.83s/ s simulated")


def _note_the_robots_own_size(world, robot) -> None:
    """One ``note:`` line when the world gives a ``robot_radius`` larger than the simulated robot's (its
    footprint's inscribed radius): the simulator moves and checks the robot's own footprint, so a start 0.2 m
    from a wall that navlab plan refused for the world's 0.5 m ran to REACHED without a word (newcomer,
    session 29). A robot larger than the world's radius keeps more room than it asks: nothing to say."""
    size = getattr(world, "robot_radius", 0.0)
    if size > robot.planning_radius + 1e-9:
        # radius= sizes a disc; a polygon footprint (jackal, car) is changed with footprint= (review, s. 29)
        remedy = f"--robot-param radius={size:g} gives it that size" if getattr(robot, "footprint", None) is None \
            else "--robot-param footprint=[[x, y], ...] gives it another shape"
        click.echo(f"note: the world's robot_radius {size:g} m is navlab plan's; the simulated robot is its own "
                   f"footprint, {robot.shape.describe()} ({remedy})", err=True)


def _timing(items, flag: str):
    """``rate=10,latency=0.5`` (or the flag repeated) as a mapping; None when not given."""
    if not items:
        return None
    return parse_params(tuple(part for item in items for part in item.split(",") if part.strip()), flag)


#: the flags an --experiment takes: its runs are set by the experiment itself (robot, controller, time step...)
EXPERIMENT_FLAGS = ("experiment", "runs", "seed", "plot_dir", "as_json")


def _refuse_flags_experiments_do_not_take() -> None:
    """A usage error naming every flag given with --experiment that it does not take (--dt, --max-time,
    --robot, --plot, --gif... ran the experiment's own settings and wrote nothing, unsaid: newcomer,
    session 32)."""
    from click.core import ParameterSource

    ctx = click.get_current_context()
    given = [max(p.opts, key=len) for p in ctx.command.params
             if p.name not in EXPERIMENT_FLAGS and p.param_type_name == "option"
             and ctx.get_parameter_source(p.name) not in (None, ParameterSource.DEFAULT)]
    if given:
        raise click.UsageError(f"--experiment runs with its own settings: {', '.join(given)} "
                               f"{'does' if len(given) == 1 else 'do'} not apply to it (it takes --runs, --seed, "
                               "--plot-dir and --json)")


def _experiment(name: str, runs, seed: int, plot_dir, as_json: bool) -> None:
    from ..sim import latency
    from ..sim.experiments import EXPERIMENTS, hybrid_table, seed002_table, seed004_table

    study = EXPERIMENTS.get(name).registered_name  # the descriptive name behind an alias
    if study == "maze-astar" and plot_dir is None:
        plot_dir = "sim-results/seed002"
    if plot_dir:
        Path(plot_dir).mkdir(parents=True, exist_ok=True)
    kwargs = {"seed": seed, "plot_dir": plot_dir}
    if runs:
        kwargs["runs"] = runs
    rows = EXPERIMENTS.get(name)(**kwargs)
    if as_json:
        for row in rows:
            click.echo(json.dumps(row))
        return
    tables = {"omni-potential-field": seed004_table, "maze-astar": seed002_table,
              "sensor-latency": latency.latency_table, "hybrid-vs-field": hybrid_table}
    click.echo(tables[study](rows))
    if study == "sensor-latency":
        click.echo(f"with the measured delays the field stays clear of the cylinder up to "
                   f"{latency.safe_speed(rows)} m/s (without delays: {latency.safe_speed(rows, 'none')} m/s)")
    wall = sum(r.get("wall_time_s", 0.0) for r in rows)
    simulated = sum(r.get("time_s", 0.0) for r in rows)
    click.echo(f"{len(rows)} runs, {simulated:.0f} s simulated in {wall:.2f} s of compute "
               f"(real-time factor {simulated / max(wall, 1e-9):.0f}x)" + (f"; pictures in {plot_dir}" if plot_dir else ""))


def _distance(metres: float) -> str:
    """A distance to the goal as a reader takes it in: mm near the goal, m beyond a metre ("8733.4 mm")."""
    return f"{1000 * metres:.1f} mm" if metres < 1.0 else f"{metres:.3f} m"
