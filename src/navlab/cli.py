"""The ``navlab`` command."""

from __future__ import annotations

import json
import sys
from typing import Any, Dict, Tuple

import click
import yaml

from .registry import UnknownNameError, parameters_of


class NavlabGroup(click.Group):
    """Turns navlab's input errors into one clean line and exit status 2."""

    def invoke(self, ctx):
        from .world.io import WorldFormatError

        try:
            return super().invoke(ctx)
        except (UnknownNameError, WorldFormatError, ValueError, FileNotFoundError) as exc:  # MapFormatError too
            click.echo(f"Error: {exc}", err=True)
            sys.exit(2)


@click.group(cls=NavlabGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="navlab")
def main() -> None:
    """navlab: 2D mobile-robot path planning and navigation.

    Worlds are YAML world files or built-in scene names (see `navlab list`).
    Units are metres and radians unless a flag says otherwise.
    """


def parse_params(items: Tuple[str, ...]) -> Dict[str, Any]:
    """``key=value`` pairs; values are read as YAML (numbers, lists, mappings)."""
    out: Dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise click.BadParameter(f"expected key=value, got '{item}'", param_hint="--param")
        try:
            out[key.strip()] = yaml.safe_load(value)
        except yaml.YAMLError as exc:
            raise click.BadParameter(f"cannot read the value of '{key}': {exc}", param_hint="--param") from None
    return out


@main.command("plan")
@click.argument("world")
@click.option("--planner", default="rrt_star", show_default=True, help="Registered planner (navlab list).")
@click.option("--sampler", default="uniform", show_default=True, help="Registered sampler (navlab list).")
@click.option("--max-iter", type=click.IntRange(min=1), default=None, help="Iterations (default: the planner's).")
@click.option("--max-time", type=click.FloatRange(min=0, min_open=True), default=None, help="Time limit in seconds.")
@click.option("--seed", type=int, default=0, show_default=True, help="Random seed (same seed, same result).")
@click.option("--param", "params", multiple=True, metavar="KEY=VALUE",
              help="Planner or sampler setting, e.g. expand_dis=1.0 goal_sample_rate=0.05 "
                   "'weights={goal: 0.1, uniform: 0.3, gaussian: 0.3, boundary: 0.3}'. Repeatable.")
@click.option("--json", "as_json", is_flag=True, help="Print status, cost, path, stats and all parameters as JSON.")
@click.option("--plot", type=click.Path(dir_okay=False, writable=True), default=None,
              help="Write a PNG of obstacles, tree, path, start and goal.")
def plan_cmd(world, planner, sampler, max_iter, max_time, seed, params, as_json, plot) -> None:
    """Plan a path in WORLD (a YAML world file or a scene name)."""
    from . import load_world, plan

    w = load_world(world)
    settings = parse_params(params)
    if max_iter is not None:
        settings["max_iter"] = max_iter
    if max_time is not None:
        settings["max_time"] = max_time
    if plot:
        settings.setdefault("keep_tree", True)
    result = plan(w, planner=planner, sampler=sampler, seed=seed, **settings)
    if plot:
        from .viz import plot_plan

        plot_plan(w, result, plot)
    if as_json:
        click.echo(json.dumps(result.to_dict()))
    else:
        s = result.stats
        click.echo(f"{w.name}: {planner} + {sampler}, seed {seed}: {result.status.name}"
                   + (f" ({result.reason})" if result.reason else ""))
        if len(result.path):
            click.echo(f"  cost {result.cost:.4f} m, {len(result.path)} waypoints")
        if s:
            first = s.get("first_solution_iteration")
            click.echo(f"  {s['iterations']} iterations, {s['nodes']} nodes, {s['collision_checks']} collision checks, "
                       f"{s['time_s'] * 1000:.1f} ms" + (f", first solution at iteration {first}" if first is not None else ""))
        if plot:
            click.echo(f"  plot written to {plot}")
    if not result.success:
        sys.exit(1)


def _describe(factory) -> str:
    doc = (factory.__doc__ or "").strip().splitlines()
    return doc[0] if doc else ""


@main.command("list")
def list_cmd() -> None:
    """Planners, samplers and scenes, with their parameters and defaults."""
    from .sampling import PLANNERS, SAMPLERS
    from .world import SCENES

    for title, registry in (("planners", PLANNERS), ("samplers", SAMPLERS)):
        click.echo(f"{title}:")
        for name in registry:
            cls = registry.get(name)
            click.echo(f"  {name:<20} {_describe(cls)}")
            params = ", ".join(f"{k}={v!r}" for k, v in parameters_of(cls).items())
            click.echo(f"  {'':<20} {params or '(no parameters)'}")
        click.echo("  (None: derived from the world, see the docs)" if title == "planners" else "")
    click.echo("scenes:")
    for name in SCENES:
        w = SCENES.get(name)()
        click.echo(f"  {name:<20} {_describe(SCENES.get(name))}")
        click.echo(f"  {'':<20} start {w.start}, goal {w.goal}, robot radius {w.robot_radius} m, "
                   f"{len(w.obstacles)} obstacles")


from .bench_cli import bench_cmd  # noqa: E402
from .grid_cli import grid_group  # noqa: E402
from .ros_cli import ros_group  # noqa: E402
from .sim_cli import sim_cmd  # noqa: E402

main.add_command(grid_group)
main.add_command(bench_cmd)
main.add_command(sim_cmd)
main.add_command(ros_group)

if __name__ == "__main__":  # pragma: no cover
    main()
