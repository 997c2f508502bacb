"""``navlab grid``: plan on maps, run Moving AI scenarios, generate mazes."""

from __future__ import annotations

import json
import math
import os
import shlex
import sys

import click
import numpy as np

from ..errors import ParameterError
from ..wording import counted, decimal, duration
from .common import (Count, ExactNumber, FiniteNumber, NonNegativeNumber, PositiveNumber, SuggestingChoice,
                     SuggestingGroup, before_first_kernel, before_numba_import, check_figure_file, check_output_file,
                     note_unused_grid_settings)


@click.group("grid", cls=SuggestingGroup)
def grid_group() -> None:
    """Grid planning on ROS map_server maps (.yaml) and Moving AI maps (.map)."""


ALGORITHMS = ["astar", "dijkstra", "jps", "theta_star"]
HEURISTICS = ["octile", "euclidean", "chebyshev", "manhattan", "none"]
HEURISTIC_HELP = ("A*'s heuristic (none: uniform-cost search, as dijkstra; manhattan is not admissible with "
                  "8-connectivity: its paths can be longer than the optimum).")


@grid_group.command("plan")
@click.argument("map_path", metavar="MAP", type=click.Path(dir_okay=False))
@click.option("--start", nargs=2, type=ExactNumber(), required=True, metavar="X Y",
              help="Start cell (or metres with --world).")
@click.option("--goal", nargs=2, type=ExactNumber(), required=True, metavar="X Y",
              help="Goal cell (or metres with --world).")
@click.option("--world", "in_world", is_flag=True, help="Start and goal are world coordinates in metres.")
@click.option("--algorithm", type=SuggestingChoice(ALGORITHMS), default="astar", show_default=True)
@click.option("--heuristic", type=SuggestingChoice(HEURISTICS), default="octile", show_default=True,
              help=HEURISTIC_HELP)
@click.option("--connectivity", type=SuggestingChoice(["4", "8"]), default="8", show_default=True)
@click.option("--weight", type=FiniteNumber(), default=1.0, show_default=True,
              help="Weighted A*: the heuristic times this (>= 1; 1 finds shortest paths). Only astar with a "
                   "heuristic takes one (a note says so otherwise).")
@click.option("--smooth", is_flag=True, help="Shortcut the path along Bresenham lines of sight.")
@click.option("--robot-radius", "--inflate", "inflate", type=NonNegativeNumber(), default=0.0, show_default=True,
              help="The robot's radius [m]: a cell is blocked when its centre is within it of a blocked cell's "
                   "centre (OccupancyGrid.inflate; --inflate is the old name). navlab plan's --robot-radius is "
                   "stricter: it blocks a cell when any part of its square is within the radius of a blocked "
                   "cell's square, so the same radius can give it a longer path.")
@click.option("--allow-unknown", is_flag=True, help="Let the path cross cells of unknown occupancy.")
@click.option("--map-rule", type=SuggestingChoice(["nav2", "ros1"]), default="nav2", show_default=True,
              help="How a map_server image is read: Nav2's map_io (inclusive thresholds) or ROS 1's map_server.")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@click.option("--plot", type=click.Path(dir_okay=False), default=None,
              help="Write a figure of grid and path: PNG, or the format its suffix names (.svg, .pdf, ...).")
def grid_plan(map_path, start, goal, in_world, algorithm, heuristic, connectivity, weight, smooth, inflate,
              allow_unknown, map_rule, as_json, plot) -> None:
    """Plan a path on MAP between two cells (x = column, y = row)."""
    before_numba_import()
    if plot:  # (after numba's lean import, as navlab plan's)
        check_figure_file(plot, "--plot")
    from ..grid import load_map, plan, plan_world
    from ..grid.planner import path_bound_note
    from ..limits import check_length, shown

    for label, v in (("--start", start), ("--goal", goal)):
        got = " ".join(shown(c) if isinstance(c, int) else f"{c:g}" for c in v)
        if not all(isinstance(c, int) or math.isfinite(c) for c in v):
            raise ParameterError(f"{label} must be finite numbers, got {got}")
        if not in_world and any(isinstance(c, float) and c != int(c) for c in v):
            raise ParameterError(f"{label}: cells are integers; use --world for metres, got {got}")
    from ..world.sources import source_kind

    # (a missing file is load_map's "no such file": source_kind takes a name it cannot find for a scene's,
    # and a scene is no map: "unknown scene 'nofile.txt'; valid: ...": newcomer, session 32)
    if os.path.exists(map_path) and source_kind(map_path) == "world_file":
        raise ParameterError(f"{map_path}: this is a world file (shapes, start and goal), not a map: use "
                             f"navlab plan {map_path} --planner {algorithm}")
    grid = load_map(map_path, rule=map_rule)
    if inflate:  # checked under the flag's name (OccupancyGrid.inflate calls it "inflation radius")
        grid = grid.inflate(check_length("--robot-radius", inflate))
    kwargs = dict(algorithm=algorithm, heuristic=heuristic, connectivity=int(connectivity), smooth=smooth,
                  weight=weight, allow_unknown=allow_unknown)
    before_first_kernel()  # numba loads for the search below anyway
    if in_world:
        result = plan_world(grid, start, goal, **kwargs)
        ends = np.array([start, goal], dtype=float)
    else:
        cells = ((int(start[0]), int(start[1])), (int(goal[0]), int(goal[1])))
        result = plan(grid, *cells, **kwargs)
        ends = grid.cell_to_world(np.array(cells, dtype=float))
    note_unused_settings(algorithm, heuristic=heuristic, weight=weight)  # (once they passed the planner's checks)
    if plot:
        from ..viz.grid_plot import plot_grid_plan

        try:
            plot_grid_plan(grid, result, plot, start=ends[0], goal=ends[1])
        except OSError as exc:
            fail(f"cannot write {plot}: {exc.strerror or exc}")
    if as_json:
        click.echo(json.dumps(result.to_dict()))
    else:
        click.echo(f"{grid.name}: {algorithm}: {result.status.name}" + (f" ({result.reason})" if result.reason else ""))
        if result.success:
            click.echo(f"  {counted(len(result.cells), 'waypoint')}, length {result.stats['cost_cells']:.6f} cells = {result.cost:.4f} m, "
                       f"{result.stats['expanded']} expanded, {result.stats['time_s'] * 1000:.2f} ms")
            bound = path_bound_note(result.params)
            if bound:
                click.echo(f"  {bound}")
        if result.stats.get("warmup_s"):  # a failed first use compiled as long as a successful one
            click.echo(f"  warm-up (compiling / loading kernels, not planning) {duration(result.stats['warmup_s'])}")
        if plot:
            click.echo(f"  plot written to {plot}")
    if not result.success:
        sys.exit(1)


def note_unused_settings(algorithm: str, **values) -> None:
    """:func:`~navlab.cli.common.note_unused_grid_settings` for those of ``values`` (``heuristic``,
    ``weight``) given on the command line, not left at their defaults."""
    source = click.get_current_context().get_parameter_source
    given = {k: v for k, v in values.items() if source(k) == click.core.ParameterSource.COMMANDLINE}
    note_unused_grid_settings(algorithm, given, lambda key, value: f"--{key} {value:g}" if key == "weight"
                              else f"--{key} {value}")


def fail(message: str) -> None:
    """One line on stderr and exit status 2 (an input or file error, not a traceback)."""
    click.echo(f"Error: {message}", err=True)
    sys.exit(2)


@grid_group.command("scen", short_help="Run a Moving AI scenario file against its stored optima.")
@click.argument("scen_path", metavar="FILE.scen", type=click.Path(dir_okay=False))
@click.option("--map", "map_path", type=click.Path(dir_okay=False), default=None,
              help="The .map file (default: the scenario's map name next to FILE.scen).")
@click.option("--algorithm", type=SuggestingChoice(ALGORITHMS), default="astar", show_default=True)
@click.option("--heuristic", type=SuggestingChoice(HEURISTICS), default="octile", show_default=True,
              help=HEURISTIC_HELP)
@click.option("--limit", type=Count(), default=None, help="Only the first N scenarios.")
@click.option("--every", type=Count(), default=1, show_default=True, help="Only every k-th scenario.")
@click.option("--json", "as_json", is_flag=True, help="Print the summary and every scenario as JSON.")
@click.option("--quiet", is_flag=True, help="No progress bar.")
def grid_scen(scen_path, map_path, algorithm, heuristic, limit, every, as_json, quiet) -> None:
    """Run a Moving AI scenario file; compare lengths with the stored optima.

    Lengths are compared as the benchmark computes them (a diagonal costs
    1.414213562) to one unit in the last printed digit; exact lengths are in
    the JSON rows as exact_length. theta_star (any-angle) matches when its
    path is at most the stored octile optimum. Prints a summary with the five
    worst scenarios; exit status 1 when any scenario mismatches or is invalid
    (start or goal blocked or outside the map).
    """
    from ..grid.scen import read_scen
    from ..grid.scen_runner import run_scenarios
    from ..limits import short_name

    for path in (scen_path, map_path):
        if path is not None and not os.path.exists(path):
            fail(f"{short_name(os.fsdecode(path))}: no such file. Moving AI scenarios and maps come from "
                 "movingai.com/benchmarks "
                 "(a .map and its .map.scen side by side; the README's examples use the five in "
                 "../shared/data/movingai beside a navlab checkout)")
    total = len(read_scen(scen_path)[::every][:limit])
    with progress_bar(total, "scenarios", quiet) as bar:
        out = run_scenarios(scen_path, map_path, algorithm, heuristic, limit, every,
                            progress=lambda done: bar.update(done - bar.n))
    note_unused_settings(algorithm, heuristic=heuristic)
    s = out["summary"]
    if as_json:
        click.echo(json.dumps(out))
    else:
        click.echo(scen_report(s))
    if s["mismatches"] or s["invalid"]:
        sys.exit(1)


def scen_report(s) -> str:
    """The summary of ``navlab grid scen`` as text: counts, times, the worst five."""
    from ..grid.scen import printed_decimals

    fmt = lambda v: "-" if v is None else f"{v:.8g}"  # noqa: E731
    # Dijkstra uses no heuristic, so none is named beside it (A* given none says so: newcomer run, session 20)
    searched = s["algorithm"] if s["algorithm"] == "dijkstra" else f"{s['algorithm']} ({s['heuristic']})"
    lines = [f"{s['map']}: {s['scenarios']} scenarios, {searched}, "
             f"length {s['comparison']}: {s['matches']} match, {s['mismatches']} do not"
             + (f", {s['invalid']} invalid (start or goal blocked or outside the map)" if s["invalid"] else "")]
    lines.append("  statuses: " + ", ".join(f"{k} {v}" for k, v in sorted(s["statuses"].items())))
    if s.get("length_over_optimal_median") is not None:
        lines.append(f"  any-angle length / octile optimum: median {s['length_over_optimal_median']:.4f}")
    total = s["time_total_s"]  # (in ms below a second: three queries read "total 0.000 s", newcomer check)
    lines.append(f"  time per query: median {s['time_median_ms']:.3f} ms, p95 {s['time_p95_ms']:.3f} ms, "
                 + (f"total {total:.3f} s" if total >= 1.0 else f"total {1000 * total:.3f} ms"))
    if s["worst"]:
        # what the rows rank by, and that a match's excess is the stored value's rounding ("match, excess
        # 4.9182e-05" read as an error; the cells were not said to be (x, y): newcomer run, session 29)
        lines.append(f"  worst {len(s['worst'])}: failed first, then by |length - stored optimum| (cells (x, y); a "
                     "match is within the stored value's rounding):")
        for w in s["worst"]:
            # the length at the stored optimum's own printed digits, which it is compared at
            digits = printed_decimals(w["optimal_text"])
            got = "-" if w["length"] is None else f"{w['length']:.{digits}f}"
            (sx, sy), (gx, gy) = w["start"], w["goal"]
            lines.append(f"    #{w['index']}: ({sx}, {sy}) -> ({gx}, {gy}): stored {w['optimal_text']}, "
                         f"got {got} ({w['status']}, {'match' if w['match'] else 'MISMATCH'}, "
                         f"length - optimum {fmt(w['excess'])})")
    return "\n".join(lines)


def progress_bar(total: int, unit: str, quiet: bool = False, threshold: int = 0):
    """A tqdm bar on stderr, off with ``quiet``, when stderr is not a terminal, or for
    fewer than ``threshold`` items."""
    from tqdm import tqdm

    disable = True if quiet or total < threshold else None  # None: off when not a TTY
    return tqdm(total=total, unit=f" {unit}", file=sys.stderr, disable=disable, leave=False, dynamic_ncols=True)


@grid_group.command("maze")
@click.option("--cells", nargs=2, type=Count(), default=(10, 10), show_default=True, metavar="W H",
              help="Maze size in cells.")
@click.option("--seed", type=Count(low=0), default=0, show_default=True,
              help="Seed of the maze's layout: same seed and size, same maze.")
@click.option("--cell-size", type=PositiveNumber(), default=0.5, show_default=True,
              help="Distance between cell centres, m.")
@click.option("--wall", type=PositiveNumber(), default=0.1, show_default=True,
              help="Wall thickness, m.")
@click.option("--resolution", type=PositiveNumber(), default=0.05, show_default=True,
              help="Map resolution, m per pixel.")
@click.option("--out", type=click.Path(dir_okay=False), required=True, help="Output map_server YAML (PGM beside it).")
@click.option("--quiet", is_flag=True, help="No progress bar.")
def grid_maze(cells, seed, cell_size, wall, resolution, out, quiet) -> None:
    """Generate a perfect maze as a ROS map_server map (YAML + PGM).

    The resolution must be at most the wall thickness and the corridor width
    (cell size - wall), so neither vanishes; mazes whose map would exceed
    navlab's 1e8-cell limit or the memory available are refused before
    anything is built. Mazes of more than 1000 cells show a progress bar.
    """
    from ..grid import make_maze, save_map
    from ..grid.mapio import check_map_yaml_path
    from ..grid.maze import maze_size

    maze_size(cells[0], cells[1], cell_size, wall, resolution)  # refuse before the bar and the carving
    check_map_yaml_path(out)
    check_output_file(out, "--out")  # (a missing folder was named as the .pgm's after the carving: newcomer, s30)
    with progress_bar(cells[0] * cells[1], "cells", quiet, threshold=1000) as bar:
        grid = make_maze(cells[0], cells[1], seed=seed, cell_size=cell_size, wall=wall, resolution=resolution,
                         progress=lambda done: bar.update(done - bar.n))
    try:
        image = save_map(grid, out)
    except OSError as exc:
        fail(str(exc.strerror or exc))
    click.echo(f"wrote {out} and {image}: {cells[0]}x{cells[1]} cells, {grid.width}x{grid.height} pixels "
               f"at {resolution} m")
    click.echo(_where_to_plan(out, cells, cell_size, wall, resolution))


def _where_to_plan(out: str, cells, cell_size: float, wall: float, resolution: float) -> str:
    """The maze's first and last cells' centres and the command that plans between them (the map gave
    no free coordinates to plan between: newcomer, session 30): to a hundredth of a pixel, and the map's
    path as the shell reads it back (quoted; one starting with '-' read as an option: review, session 31)."""
    from ..grid.maze import maze_cell_center

    places = max(6, math.ceil(-math.log10(resolution)) + 2)  # (0.000001 rounded a 1e-7 m pixel's centre off)
    corners = [maze_cell_center(i, j, cell_size, wall) for i, j in ((0, 0), (cells[0] - 1, cells[1] - 1))]
    (x0, y0), (x1, y1) = ((decimal(x, places), decimal(y, places)) for x, y in corners)
    path = out if not out.startswith("-") else os.path.join(".", out)
    return (f"corner cells' centres: ({x0}, {y0}) and ({x1}, {y1}) m: "
            f"navlab grid plan {shlex.quote(path)} --world --start {x0} {y0} --goal {x1} {y1}")
