"""``navlab plan``: plan a path in any source with any planner."""

from __future__ import annotations

import json
import math
import sys

import click

from ..errors import ParameterError
from ..wording import counted, duration
from .common import (Count, NonNegativeNumber, PointOrPoseOption, PositiveNumber, before_first_kernel,
                     before_numba_import, check_figure_file, note_unused_grid_settings, parse_params,
                     status_if_output_is_cut)

_FLAGS = {"start": "--start X Y", "goal": "--goal X Y"}


@click.command("plan")
@click.argument("source", metavar="SOURCE")
@click.option("--planner", default="rrt_star", show_default=True,
              help="Tree planner or grid algorithm (navlab list): rrt, rrt_star, informed_rrt_star, "
                   "growth_ratio_rrt, astar, dijkstra, jps, theta_star (astar with --param costmap=true plans on a "
                   "Nav2-style costmap); hybrid_astar plans between poses for a car-like robot (--param "
                   "motion=reeds_shepp|dubins --param turning_radius=R --param 'footprint=[[x, y], ...]').")
@click.option("--sampler", default=None, help="Registered sampler for tree planners (navlab list). [default: uniform]")
@click.option("--start", cls=PointOrPoseOption, default=None,
              help="Start in metres (overrides the world's; required for maps); THETA, the heading in radians, "
                   "matters to hybrid_astar.")
@click.option("--goal", cls=PointOrPoseOption, default=None,
              help="Goal in metres (overrides the world's; required for maps); THETA as for --start.")
@click.option("--robot-radius", type=NonNegativeNumber(), default=None,
              help="Robot radius in metres (overrides the world's; maps: 0).")
@click.option("--max-iter", type=Count(), default=None,
              help="Iterations (default: 5000 for rrt_star and informed_rrt_star, 10 000 for rrt and "
                   "growth_ratio_rrt).")
@click.option("--max-time", type=PositiveNumber(), default=None,
              help="Time limit in seconds (starts after warm-up).")
@click.option("--seed", type=Count(low=0), default=0, show_default=True,
              help="Random seed (same seed, same result; the grid planners and hybrid_astar draw no random "
                   "numbers).")
@click.option("--param", "params", multiple=True, metavar="KEY=VALUE",
              help="One planner, sampler or grid setting per --param (repeat it for more), e.g. "
                   "--param expand_dis=1.0 --param goal_sample_rate=0.05 (navlab list shows each part's); "
                   "the integration sampler: --param 'weights={goal: 0.1, uniform: 0.3, gaussian: 0.3, "
                   "boundary: 0.3}'; grid: resolution=0.05 heuristic=octile connectivity=8 smooth=true "
                   "allow_unknown=true weight=1.5 (resolution: a geometric world's cell size, default 1/200 "
                   "of its longer side; a map keeps its own; weight: astar's, default 1; above 1, weighted A*: "
                   "usually fewer expansions, for a path at most weight times the shortest under an "
                   "admissible heuristic such as octile; hybrid_astar takes it too, without that bound); "
                   "astar on a costmap: "
                   "costmap=true inflation_radius=0.55 "
                   "cost_scaling_factor=3.0 cost_travel_multiplier=2.0 allow_unknown=true (its cells 0.05 m on a "
                   "geometric world unless resolution= says).")
@click.option("--json", "as_json", is_flag=True,
              help="Print status, cost, path, stats and all parameters as JSON (without the cost trace).")
@click.option("--trace", is_flag=True, help="With --json: include the per-iteration cost trace.")
@click.option("--plot", type=click.Path(dir_okay=False), default=None,
              help="Write a figure of the world or map, tree, path, start and goal: PNG, or the format its "
                   "suffix names (.svg, .pdf, ...).")
def plan_cmd(source, planner, sampler, start, goal, robot_radius, max_iter, max_time, seed, params, as_json,
             trace, plot) -> None:
    """Plan a path in SOURCE: a built-in scene name (navlab list), a world
    YAML, a ROS map_server YAML (PGM/PNG) or a Moving AI .map. Maps have no start or goal: give
    --start and --goal (metres, map frame).

    Exit status: 0 for an EXACT path; 1 when the planner answered without one
    (APPROXIMATE, FAILED, INVALID_START, INVALID_GOAL: the first line says
    why); 2 for bad input (one line, Error: ...).
    """
    from ..numba_start import collections_paused

    if trace and not as_json:  # (it did nothing on its own, silently: newcomer check, session 26)
        raise click.UsageError("--trace adds the cost trace to the --json output: give it with --json")
    # One query in a process of its own: what loads on the way (numba, its registries, the kernels) lives until
    # the exit, and the query's own objects are freed by reference counting, so collections would only walk
    # the ~110 000 long-lived objects again and again (~0.1 s of CPU); reference cycles wait for the exit.
    before_numba_import()
    if plot:  # (after numba's lean import: matplotlib's own imports would take what it defers)
        check_figure_file(plot, "--plot")
    with collections_paused():
        from ..planning import is_grid_planner, plan
        from ..pose_queries import POSE_PLANNERS, check_radius_not_dropped, is_pose_query
        from ..world.sources import MissingQueryError, load_source

        before_first_kernel()  # numba is imported by now (the planners' kernels)
        settings = parse_params(params)
        for key in ("planner", "sampler", "seed"):  # the flags' own (a TypeError, "multiple values", until session 17)
            if key in settings:
                raise click.UsageError(f"--param {key}=... : give --{key} {settings[key]} instead")
        for flag, value in (("max_iter", max_iter), ("max_time", max_time)):
            if value is not None:
                if flag in settings and settings[flag] != value:
                    raise click.UsageError(f"--{flag.replace('_', '-')} {value:g} and --param {flag}="
                                           f"{settings[flag]} disagree: give one")
                settings[flag] = value
        grid = planner in POSE_PLANNERS or is_grid_planner(planner)
        if trace and grid:  # (an empty answer without a word: newcomer, session 27)
            raise click.UsageError(f"--trace: {planner} keeps no per-iteration cost trace (the tree planners do)")
        if sampler is None:
            sampler = None if grid else "uniform"
        if plot and not grid:
            settings.setdefault("keep_tree", True)
        try:
            world = load_source(source, start=start, goal=goal, robot_radius=robot_radius,
                                allow_unknown=settings.get("allow_unknown"))
        except MissingQueryError as exc:
            # one line through the CLI's error handler (exit 2), naming the flag
            raise ParameterError(f"{_FLAGS[exc.field].split()[0]} is required: {source} is a map and has no "
                                 f"{exc.field} (give {_FLAGS[exc.field]} in metres)") from None
        pose_query = is_pose_query(planner, settings)
        if pose_query:
            check_radius_not_dropped(world, robot_radius, settings, planner)
        result = plan(world, planner=planner, sampler=sampler, seed=seed, **settings)
        if not pose_query and is_grid_planner(planner):  # (once they passed the planner's checks)
            note_unused_grid_settings(planner, settings, lambda key, value: f"--param {key}={value}")
    status = 0 if result.success else 1  # (the exit status, also if the output is cut short)
    status_if_output_is_cut(status)
    if plot:
        from ..viz import plot_plan

        plot_plan(world, result, plot)
    if as_json:
        out = result.to_dict()
        if not trace:
            out["stats"].pop("cost_trace", None)
        click.echo(json.dumps(out))
    else:
        _print_summary(world, result, planner, sampler, seed, plot)
    _note_ignored_shape(world, result)
    if status:
        sys.exit(status)


#: the command may end the process at once after this verb (navlab.cli._exit_now): it writes with click.echo
#: only and closes what it opens
plan_cmd.exits_quickly = True


def _note_ignored_shape(world, result) -> None:
    """Say so when a point planner ran in a world that names a footprint: its path is for a disc of
    ``robot_radius`` and ignores the outline and the headings (navlab sim switches to poses there)."""
    footprint = getattr(world, "footprint", None)
    if footprint is None or len(result.path) == 0 or result.path.ndim != 2 or result.path.shape[1] != 2:
        return
    click.echo(f"note: {world.name} names a robot outline and headings; this path is for a disc of radius "
               f"{result.params.get('robot_radius', 0):g} m and ignores both: plan with --planner hybrid_astar "
               "(or a tree with --param motion=reeds_shepp) for the outline", err=True)


def _print_summary(world, result, planner, sampler, seed, plot) -> None:
    s = result.stats
    what = planner if sampler is None else f"{planner} + {sampler}, seed {seed}"
    rate = result.params.get("goal_sample_rate")
    if sampler not in (None, "goal_bias") and rate:  # wrapped in goal bias (docs/sampling.md; newcomer run, session 21)
        what = f"{planner} + {sampler} with goal bias {rate:g}, seed {seed}"
    if result.params.get("costmap"):  # the header said "astar" alone whether or not it planned on a costmap
        what += " (costmap)"
    click.echo(f"{world.name}: {what}: {result.status.name}" + (f" ({result.reason})" if result.reason else ""))
    if len(result.path):
        click.echo(f"  cost {result.cost:.4f} m, {counted(len(result.path), 'waypoint')}")
        if "heuristic" in result.params:  # a grid search's (not imported for a tree's)
            from ..grid.planner import path_bound_note

            bound = path_bound_note(result.params)
            if bound:
                click.echo(f"  {bound}")
    if "iterations" in s:
        first = s.get("first_solution_iteration")
        click.echo(f"  {counted(s['iterations'], 'iteration')}, {counted(s['nodes'], 'node')}, "
                   f"{counted(s['collision_checks'], 'collision check')}, "
                   f"planning {s['time_s'] * 1000:.1f} ms"
                   + (f", first solution at iteration {first}" if first is not None else ""))
    elif "expansions" in s:  # a heading-aware planner
        p, n = result.params, s["expansions"]
        cusps = s.get("cusps", 0)  # of a path found: a failed search has none to count
        cusps_said = f"{counted(cusps, 'cusp')}, " if len(result.path) else ""
        # (a weighted search said nothing of its weight but in --json: newcomer, session 24)
        weighted = f"heuristic weight {p['weight']:g}, " if p.get("weight", 1.0) != 1.0 else ""
        click.echo(f"  {p.get('motion')}, turning radius {p.get('turning_radius', 0):g} m, {weighted}"
                   f"{counted(n, 'expansion')}, {cusps_said}planning {s['time_s'] * 1000:.1f} ms")
        off, turn = s.get("goal_offset_m", 0.0), s.get("goal_heading_offset_rad", 0.0)
        if len(result.path) and (off > 1e-6 or turn > 1e-6):  # analytic_expansion=false: near the goal, not at it
            click.echo(f"  ends {off:.3f} m and {math.degrees(turn):.1f}° from the goal pose (without the analytic "
                       "expansion the search ends in the goal's cell, its heading within one arc's turn)")
    elif "time_s" in s and s.get("grid"):  # a grid planner that searched (not one refused at its start)
        line = f"  grid {s['grid']} at {result.params.get('resolution', 0):g} m"
        if "expanded" in s:
            line += f", {counted(s['expanded'], 'cell')} expanded"
        rasterising_ms = s.get("rasterize_s", 0) * 1000
        click.echo(line + f", planning {s['time_s'] * 1000:.1f} ms (rasterising {rasterising_ms:.1f} ms)")
    if s.get("warmup_s", 0) > 0.0005:
        click.echo(f"  warm-up (compiling / loading kernels, not planning) {duration(s['warmup_s'])}")
    if plot:
        click.echo(f"  plot written to {plot}")
