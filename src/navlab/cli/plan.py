"""``navlab plan``: plan a path in a world."""

from __future__ import annotations

import json
import sys

import click

from .common import parse_params


@click.command("plan")
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
    from .. import load_world, plan

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
        from ..viz import plot_plan

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
