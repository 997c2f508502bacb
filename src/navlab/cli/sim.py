"""``navlab sim``: run the simulator on a world or map, or a seed's experiment."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from .common import parse_params


@click.command("sim")
@click.argument("world", required=False)
@click.option("--robot", type=click.Choice(["omni3", "diff"]), default="omni3", show_default=True)
@click.option("--controller", default=None,
              help="potential_field (omni3 default), goto_waypoint (diff default) or pure_pursuit.")
@click.option("--start", nargs=3, type=float, default=None, metavar="X Y THETA",
              help="Start pose [m, m, rad] (default: the world's start, heading 0).")
@click.option("--goal", nargs=2, type=float, default=None, metavar="X Y", help="Goal [m] (default: the world's).")
@click.option("--planner", default=None,
              help="Path for the followers: a sampling planner (worlds, default rrt_star) or a grid "
                   "algorithm (maps, default astar, smoothed).")
@click.option("--lidar", type=click.Choice(["rplidar_a1", "exact", "none"]), default=None,
              help="LiDAR noise (default: exact when the controller needs a scan).")
@click.option("--robot-param", "robot_params", multiple=True, metavar="KEY=VALUE",
              help="Robot setting, e.g. wheel_radius=0.04 (see the docs).")
@click.option("--controller-param", "controller_params", multiple=True, metavar="KEY=VALUE",
              help="Controller setting, e.g. alpha=0.8 max_speed=0.25.")
@click.option("--dt", type=float, default=0.05, show_default=True, help="Time step [s].")
@click.option("--max-time", type=float, default=120.0, show_default=True, help="Simulated time limit [s].")
@click.option("--seed", type=int, default=0, show_default=True)
@click.option("--experiment", type=click.Choice(["seed004", "seed002"]), default=None,
              help="Run a seed's experiment instead (no WORLD).")
@click.option("--runs", type=click.IntRange(min=1), default=None, help="Runs per setting (experiments).")
@click.option("--plot-dir", type=click.Path(file_okay=False), default=None,
              help="Experiments: write a PNG per run here (seed002 default: sim-results/seed002).")
@click.option("--json", "as_json", is_flag=True, help="JSON output (one object per run for experiments).")
@click.option("--plot", type=click.Path(dir_okay=False), default=None, help="PNG of the run.")
@click.option("--gif", type=click.Path(dir_okay=False), default=None, help="GIF animation of the run.")
def sim_cmd(world, robot, controller, start, goal, planner, lidar, robot_params, controller_params, dt, max_time,
            seed, experiment, runs, plot_dir, as_json, plot, gif) -> None:
    """Simulate a robot in WORLD (a world YAML, a scene name, or a map_server
    YAML / Moving AI map) driving to --goal, or run --experiment seed004 or
    seed002. Exit status 1 when the robot does not reach the goal.

    \b
    Examples:
      navlab sim --experiment seed004
      navlab sim clutter --robot diff --controller goto_waypoint --planner rrt_star --plot run.png
      navlab sim maze.yaml --robot diff --start 0.35 0.35 0 --goal 4.8 4.8 --gif run.gif
      navlab sim trap --robot omni3 --controller potential_field --lidar rplidar_a1
    """
    if experiment:
        if world:
            raise click.UsageError("--experiment takes no WORLD")
        _experiment(experiment, runs, seed, plot_dir, as_json)
        return
    if not world:
        raise click.UsageError("give a WORLD or --experiment")
    from ..sim.runner import simulate

    result, scene_world, sim = simulate(world, robot=robot, controller=controller, start=start, goal=goal,
                                        planner=planner, lidar=lidar, robot_params=parse_params(robot_params),
                                        controller_params=parse_params(controller_params), dt=dt,
                                        max_time=max_time, seed=seed)
    if plot:
        from ..viz.sim_plot import plot_run

        plot_run(scene_world, result, plot)
    if gif:
        from ..viz.sim_plot import animate_run

        animate_run(scene_world, result, gif, sim.robot.radius)
    if as_json:
        click.echo(json.dumps(result.to_dict(trajectory=True)))
    else:
        click.echo(f"{result.status.name}" + (f" ({result.reason})" if result.reason else "")
                   + f" after {result.time_s:.2f} s simulated in {result.wall_time_s * 1000:.0f} ms "
                   f"(real-time factor {result.real_time_factor:.0f}x, {result.steps} steps)")
        click.echo(f"  final true pose ({result.final_true[0]:.3f}, {result.final_true[1]:.3f}) m, "
                   f"{1000 * result.error_true:.1f} mm from the goal; odometry says "
                   f"({result.final_odom[0]:.3f}, {result.final_odom[1]:.3f}), travelled {result.distance:.2f} m")
        if result.path is not None:
            click.echo(f"  followed a {len(result.path)}-waypoint path, max tracking error "
                       f"{result.tracking_error():.3f} m")
        for what, name in (("plot", plot), ("animation", gif)):
            if name:
                click.echo(f"  {what} written to {name}")
    if result.status.name != "REACHED":
        sys.exit(1)


def _experiment(name: str, runs, seed: int, plot_dir, as_json: bool) -> None:
    from ..sim.experiments import EXPERIMENTS, seed002_table, seed004_table

    if name == "seed002" and plot_dir is None:
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
    click.echo(seed004_table(rows) if name == "seed004" else seed002_table(rows))
    wall = sum(r.get("wall_time_s", 0.0) for r in rows)
    simulated = sum(r.get("time_s", 0.0) for r in rows)
    click.echo(f"{len(rows)} runs, {simulated:.0f} s simulated in {wall:.2f} s of compute "
               f"(real-time factor {simulated / max(wall, 1e-9):.0f}x)" + (f"; pictures in {plot_dir}" if plot_dir else ""))
