"""``navlab bench``: run an experiment file or a built-in suite."""

from __future__ import annotations

import contextlib
import difflib
import os
import shlex
import sys
from pathlib import Path
from typing import Any, Dict, List

import click
import yaml

from ..bench.suites import suite_help
from ..errors import interrupted_by_ctrl_c
from ..limits import MAX_JOBS
from ..wording import counted, listed
from .common import EXIT_INTERRUPTED, Count, FiniteNumber, PositiveNumber, SuggestingChoice, end_at_ctrl_c, parse_params


class BenchCommand(click.Command):
    """``navlab bench`` with one sub-verb: ``navlab bench export DIR`` converts
    a results folder (an experiment file named ``export`` is ``./export``)."""

    def parse_args(self, ctx, args):
        if args[:1] == ["export"]:
            ctx.meta["navlab.bench.export"] = args[1:]
            return []
        first = args[0] if args else ""
        if first and not first.startswith("-") and not os.path.exists(first) and \
                difflib.get_close_matches(first, ["export"], n=1, cutoff=0.7):
            from ..bench.suites import find_suite

            if find_suite(first) is None:  # a near miss of the sub-verb, not a suite or a file
                raise click.UsageError(f"no experiment file or suite named '{first}'. "
                                       f"Did you mean 'navlab bench export DIR'?", ctx)
        return super().parse_args(ctx, args)

    def invoke(self, ctx):
        if "navlab.bench.export" in ctx.meta:
            return export_cmd.main(ctx.meta["navlab.bench.export"], prog_name="navlab bench export",
                                   standalone_mode=False)
        return super().invoke(ctx)


@click.command("export", context_settings={"help_option_names": ["-h", "--help"]})
@click.argument("folder", type=click.Path(file_okay=False))
@click.option("--format", "fmt", type=SuggestingChoice(["csv", "parquet"]), default="csv", show_default=True,
              help="csv, or parquet (needs pyarrow, navlab's parquet extra).")
@click.option("--out", type=click.Path(dir_okay=False), default=None,
              help="Output file (default: FOLDER/results.csv or results.parquet).")
def export_cmd(folder, fmt, out) -> None:
    """Convert a results folder's results.jsonl into one flat table: a row per
    trial, the parameters asked for (params.*) and used (params_used.*) as
    columns. navlab bench writes results.csv by itself; this converts any
    results folder, older ones included, and writes Parquet.

    \b
    Examples:
      navlab bench export bench-results/samplers
      navlab bench export bench-results/samplers --format parquet
    """
    from ..bench.export import export

    target = export(folder, fmt, out)
    click.echo(f"wrote {target}")


@click.command("bench", cls=BenchCommand)
@click.argument("experiment", required=False)
@click.option("--suite", default=None, help="A built-in suite. " + suite_help() + ".")
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="Output folder (default: bench-results/NAME).")
@click.option("--world", "worlds", multiple=True,
              help="World, scene or map file (repeatable; replaces the file's). A map needs --start and --goal.")
@click.option("--start", type=FiniteNumber(), nargs=2, default=None, metavar="X Y",
              help="Start [m] for the --world maps (map_server YAML or Moving AI .map), which have none.")
@click.option("--goal", type=FiniteNumber(), nargs=2, default=None, metavar="X Y",
              help="Goal [m] for the --world maps.")
@click.option("--planner", "planners", multiple=True, help="Planner, e.g. rrt_star or ompl:RRTstar (repeatable).")
@click.option("--sampler", "samplers", multiple=True, help="Sampler (repeatable).")
@click.option("--param", "params", multiple=True, metavar="KEY=VALUE", help="Setting for every cell (repeatable).")
@click.option("--grid", "grid", multiple=True, metavar="KEY=[V1,V2]", help="Parameter grid axis (repeatable).")
@click.option("--trials", type=Count(), default=None, help="Trials per cell.")
@click.option("--max-iter", type=Count(), default=None, help="Iteration budget per trial.")
@click.option("--max-time", type=PositiveNumber(), default=None, help="Time budget per trial [s].")
@click.option("--seed", type=Count(low=0), default=None, help="Base seed of the per-trial seeds.")
@click.option("--executor", type=SuggestingChoice(["process", "serial", "dask"]), default="process", show_default=True,
              help="process: all local cores; dask: a Dask cluster (--scheduler, or a local one).")
@click.option("--jobs", "-j", type=Count(1, MAX_JOBS), default=None,
              help=f"Worker processes, 1 to {MAX_JOBS} (default: all cores), of the process executor or a local "
                   "Dask cluster.")
@click.option("--scheduler", default=None, metavar="ADDRESS", help="Dask scheduler, e.g. tcp://10.0.0.5:8786.")
@click.option("--resume", is_flag=True, help="Keep the finished trials in --out and run the rest.")
@click.option("--overwrite", is_flag=True, help="Discard the results in --out and start again.")
@click.option("--time", "time_kind", type=SuggestingChoice(["cpu", "wall"]), default="cpu", show_default=True,
              help="Time the statistics, plots and claims use: the trial thread's CPU time, or wall-clock time.")
@click.option("--no-plots", is_flag=True, help="Skip the figures (faster).")
@click.option("--show", is_flag=True, help="Print the experiment as YAML and exit (a template for your own).")
@click.option("--quiet", "-q", is_flag=True, help="No progress bar.")
@click.option("--data", type=click.Path(), default=None,
              help="--suite barn: the BARN worlds (a checkout's jackal_helper/worlds/BARN, or any folder of "
                   "world_N.world with path_files/ beside them; ../shared/data/barn has eight).")
@click.option("--worlds", "barn_worlds", default=None, metavar="LIST",
              help="--suite barn: which worlds, e.g. 0,6,12 or 0-49 or 0-299:6 or test (default: every one found).")
@click.option("--controller", "controllers", multiple=True, metavar="NAME[:KEY=VALUE,...]",
              help="--suite barn: a navigator (repeatable), e.g. dwa_barn or rpp:desired_linear_vel=1.5 "
                   "(default: dwa_barn).")
@click.option("--straight-line", is_flag=True,
              help="--suite barn: score worlds without a path file against the 10 m straight line (OT 5 s).")
@click.option("--lidar", "barn_lidar", type=SuggestingChoice(["exact", "rplidar_a1"]), default="exact",
              show_default=True,
              help="--suite barn: the Jackal's sensors. rplidar_a1: a noisy laser (RPLIDAR A1 datasheet), 2 % "
                   "wheel-speed noise, 1 % slip and a compass, so the runs of one world differ by seed as Gazebo's "
                   "do (give --trials N runs per world; the challenge ran 10).")
def bench_cmd(experiment, suite, out, worlds, start, goal, planners, samplers, params, grid, trials, max_iter, max_time,
              seed, executor, jobs, scheduler, resume, overwrite, time_kind, no_plots, show, quiet, data, barn_worlds,
              controllers, straight_line, barn_lidar) -> None:
    """Run a benchmark: EXPERIMENT (a YAML file) or --suite NAME, optionally
    changed by flags, or an experiment made of flags alone (--world, --planner).

    Rows go to OUT/results.jsonl as trials finish; OUT/report.md (and, but
    for --suite barn, OUT/report.html) summarise them, and OUT/results.csv holds the same trials
    as one flat table (navlab bench export DIR --format csv|parquet converts
    any results folder). Exit status 1 when a trial errored,
    2 for bad input (nothing runs), 130 when stopped by Ctrl-C (the finished
    trials are kept: rerun with --resume).

    \b
    Examples:
      navlab bench --suite samplers
      navlab bench --suite samplers --trials 40 --out runs/s0 --resume
      navlab bench --world trap --planner rrt_star --sampler uniform --sampler gaussian --trials 10
      navlab bench my_study.yaml --executor dask --scheduler tcp://10.0.0.5:8786
      navlab bench --suite barn --data ../shared/data/barn --controller dwa_barn --controller rpp
    """
    from ..bench import load_experiment, run_experiment
    from ..bench.experiment import (check_max_iter, check_max_time, check_plain, check_seed,
                                    check_trials, experiment_data)
    from ..bench.executors import check_executor
    from ..bench.runner import breakdown_lines

    if resume and overwrite:
        raise click.UsageError("--resume keeps the finished trials and --overwrite discards them: give one")
    if out is not None and not str(out).strip():  # '' wrote the run into the current folder
        raise click.UsageError("--out must name a folder, got ''")
    if jobs is not None and (executor == "serial" or executor == "dask" and scheduler):
        # (it was ignored, unsaid, where --scheduler with serial is refused: newcomer, session 32)
        raise click.UsageError("--jobs sets the process executor's workers, or a local Dask cluster's: "
                               + ("serial runs one trial at a time" if executor == "serial"
                                  else "a --scheduler's cluster has its own workers"))
    if suite == "barn":
        _barn(data, barn_worlds, controllers, planners, params, trials, seed, out, executor, jobs, scheduler, resume,
              overwrite, no_plots, quiet, straight_line, barn_lidar, experiment or worlds or samplers or grid or show)
        return
    if data or barn_worlds or controllers or straight_line or barn_lidar != "exact":
        raise click.UsageError("--data, --worlds, --controller, --straight-line and --lidar go with --suite barn")
    if experiment and suite:
        raise click.UsageError("give an experiment file or --suite, not both")
    if experiment or suite:
        data, where = experiment_data(experiment or suite)
    elif worlds and planners:
        data, where = {}, "the command line"
    else:
        raise click.UsageError("give an experiment file, --suite NAME, or at least --world and --planner")
    if not isinstance(data, dict):
        raise click.UsageError(f"{where}: expected a mapping of experiment fields")
    if (start is None) != (goal is None):
        raise click.UsageError("give --start and --goal together")
    if start is not None and not worlds:
        raise click.UsageError("--start and --goal go with --world (a map, which has no start or goal)")
    if worlds:
        data["worlds"] = [_as_world(w, start, goal) for w in worlds]
    if planners:
        data["planners"] = list(planners)
    if samplers:
        data["samplers"] = list(samplers)
    if params:
        data["params"] = {**(data.get("params") or {}), **parse_params(params)}
    if grid:
        data["grid"] = {**(data.get("grid") or {}), **_grid_axes(grid)}
    budget = data.get("budget") or {}
    if not isinstance(budget, dict):
        raise click.UsageError(f"{where}: 'budget' must be a mapping (max_iter, max_time), got {budget!r}")
    budget = dict(budget)
    for holder, field, flag, value, check in ((budget, "max_iter", "--max-iter", max_iter, check_max_iter),
                                              (budget, "max_time", "--max-time", max_time, check_max_time),
                                              (data, "trials", "--trials", trials, check_trials),
                                              (data, "seed", "--seed", seed, check_seed)):
        if value is not None:
            _check_replaced(where, holder.get(field), flag, check)
            holder[field] = value
    data["budget"] = budget
    if not (experiment or suite):
        # an experiment made of flags: named by what it runs, so two different ones never share a folder
        # (its values checked first: the name hashes them, and a date was an internal TypeError there)
        check_plain(data)
        data["name"] = "adhoc"  # (named below by what it runs)
        # its errors said as any command's are ("the command line: unknown scene 'x'" opened each: newcomer, s30)
        exp = load_experiment(data, None)
    else:
        exp = load_experiment(data, where)
    if not (experiment or suite):
        exp.name = data["name"] = _adhoc_name(data, exp.fingerprint())
    if show:
        # (an edited copy that kept the suite's name ran into the suite's own folder, "holds results of a
        # different experiment": newcomer, session 25)
        where = f"(bench-results/{exp.name}) without --out" if not out else "without --out"
        click.echo(f"# 'name' names the results folder {where}: give your own study its own name\n"
                   + yaml.safe_dump(data, sort_keys=False))
        return
    note_unused_settings(exp)
    # what cannot run here is said before where results would go (--executor dask without Dask printed "results
    # go to ..." first: newcomer, session 31); reaching a --scheduler is left to the run, which connects once
    check_executor(executor, None if executor == "dask" else scheduler)
    folder = out or f"bench-results/{exp.name}"
    if not (experiment or suite) and not out and not resume:
        click.echo(f"results go to {folder} (--out DIR to choose; the same flags again with --resume continue it)",
                   err=True)
    from ..bench.store import RESULTS_FILE

    if resume and not (Path(folder) / RESULTS_FILE).is_file():  # (it began afresh without a word: newcomer,
        click.echo(f"note: nothing to resume in {folder} (no results there): a new run", err=True)  # session 23)
    with _ends_at_ctrl_c(folder, "trials"):
        run = run_experiment(exp, folder, executor=executor, jobs=jobs, scheduler=scheduler, resume=resume,
                             overwrite=overwrite, progress=not quiet, plots=not no_plots, time_kind=time_kind)
    summary = run.summary
    repeats = run.breakdown.get("repeats", 0)
    ran = f"{run.ran - repeats} run now, {counted(run.errors, 'error')}" + (
        # what a noise repeat is, where it is counted ("36 noise repeats besides" was unexplained: newcomer, s. 29)
        f"; {counted(repeats, 'noise repeat')} besides, each timing a trial again to measure the noise and in no "
        "statistic" if repeats else "")
    # (the elapsed time is the run's wall time, warm-up included; the times per cell below are each trial's own:
    # "in 74.7 s; times are thread CPU time" read as 74.7 s of CPU for trials that took 25.9, newcomer run)
    click.echo(f"{counted(len(run.rows), 'trial')} ({ran}) in {run.elapsed_s:.1f} s of wall time; each trial's time "
               f"below is its {summary['time_label']}")
    if run.ran:  # this run's workers' warm-up: a resumed run's earlier rows hold an earlier run's
        click.echo(f"warm-up (compiling and loading kernels, before the first timed trial of each worker): "
                   f"{run.breakdown.get('warmup_s', 0.0):.1f} s in all, not counted in any trial")
    if summary.get("torn_lines"):
        click.echo(f"{summary['torn_lines']} torn line(s) cut from results.jsonl (kept in results.torn.jsonl)")
    width = max([len(c["group"]) for c in summary["cells"]] + [20]) + 2
    compared = summary.get("compared") or {}  # map experiments: costs and times over the queries all cells solved
    if compared:
        click.echo("cost and time below are over the queries all cells of a map solved: "
                   + ", ".join(f"{world} {scope['common']} of {scope['queries']}" for world, scope in compared.items()))
    for cell in summary["cells"]:
        cost = cell["cost"]
        ran = cell["trials"] - cell["errors"]
        line = (f"  {cell['world']:<14} {cell['group']:<{width}} success {cell['successes']}/{ran}"
                f"  cost mean {_f(cost['mean'])} min {_f(cost['min'])}  time median {_f(cell['time']['median'], 4)}"
                + (" s" if cell["time"]["median"] is not None else ""))  # (a cell that solved nothing: "-", not "- s")
        if cell["successes"] < cell["trials"] and cell["reasons"]:
            reason, count = cell["reasons"][0]
            failed = cell["trials"] - cell["successes"]
            # (the first reason alone read as every failure's: 2 failures, 2.1 and 11.5 m short; newcomer run)
            # ("[...; 1 of 2 failed trials]" read as one trial of two failing: newcomer run, session 21)
            line += f"  [{reason}]" if count == failed else \
                f"  [{reason}: {count} of the {failed} failures; report.md lists the others' reasons]"
        click.echo(line)
    for verdict in _overall(summary):
        click.echo(verdict)
    click.echo(f"report: {run.folder / 'report.html'} (and report.md, results.jsonl, results.csv)")
    for line in breakdown_lines(run, _since_navlab_start()):
        click.echo(line)
    if run.errors:
        sys.exit(1)


def _check_replaced(where: str, written: Any, flag: str, check) -> None:
    """A file's value that ``flag`` replaces must still be valid: a typo in the file (``trials: 2.5``)
    would otherwise pass unseen this time and stop the next run, without the flag."""
    from ..bench.experiment import ExperimentError

    if written is None:
        return
    try:
        check(written)
    except ExperimentError as exc:
        raise ExperimentError(f"{where}: {exc} ({flag} replaces it this time; correct it in the file)") from None


def _barn(data, worlds, controllers, planners, params, runs, seed, out, executor, jobs, scheduler, resume,
          overwrite, no_plots, quiet, straight_line, lidar, other) -> None:
    """``navlab bench --suite barn``: see :mod:`navlab.bench.barn_run`."""
    from ..bench.barn_run import Navigator, make_study, run_barn

    if other:
        raise click.UsageError("--suite barn takes --data, --worlds, --controller, --planner, --param, --trials "
                               "(runs per world), --seed and the run options; not an experiment file, --world, "
                               "--sampler, --grid or --show")
    if not data:
        raise click.UsageError("--suite barn needs --data DIR: a checkout's jackal_helper/worlds/BARN (git clone "
                               "https://github.com/Daffan/the-barn-challenge), or ../shared/data/barn for eight")
    if len(planners) > 1:
        raise click.UsageError("--suite barn: give at most one --planner (the global planner of every navigator)")
    shared = parse_params(params) if params else {}
    navigators = []
    for text in controllers or ("dwa_barn",):
        name, _, rest = text.partition(":")
        own = parse_params(tuple(p for p in rest.split(",") if p.strip()), "--controller") if rest else {}
        navigators.append(Navigator(name.strip(), {**shared, **own}, planners[0] if planners else None))
    study = make_study(data, worlds, navigators, runs=runs or 1, seed=seed or 0, straight_line=straight_line,
                       lidar=lidar)
    folder = out or "bench-results/barn"
    with _ends_at_ctrl_c(folder, "runs"):
        folder, rows, summary = run_barn(study, folder, executor=executor, jobs=jobs, scheduler=scheduler,
                                         resume=resume, overwrite=overwrite, progress=not quiet, plots=not no_plots)
    from ..bench.barn_report import disclaimer, means_table

    # ("1 runs (1 run now) in 5.6 s", read against 12.3 s of wall time: the report's plots come after; newcomer run)
    click.echo(f"{counted(len(rows), 'run')} ({summary['ran']} run now) in {summary['elapsed_s']:.1f} s of wall time, "
               "before the report")
    for line in means_table(summary):
        click.echo(line)
    click.echo(disclaimer(study.lidar))
    # (the report's line, then the time's, as navlab bench's experiments end: newcomer, session 30)
    click.echo(f"report: {folder / 'report.md'} (and summary.json, results.jsonl, results.csv)")
    # where the rest of the command's time went ("1 run in 4.4 s" of a 23.9 s command, the rest unsaid: newcomer,
    # session 30)
    total = _since_navlab_start()
    click.echo(f"time: total {total:.1f} s since navlab started; runs {summary['elapsed_s']:.1f} s; start-up, "
               f"compiling kernels on a first use, and the report {max(0.0, total - summary['elapsed_s']):.1f} s")
    if any(r["status"] == "ERROR" for r in rows):
        sys.exit(1)


def _as_world(world: str, start, goal):
    """A --world as the experiment names it: a map with --start/--goal becomes a map world with that query."""
    from ..errors import NavlabError
    from ..limits import short_name
    from ..world.sources import source_kind

    if start is None:
        try:
            kind = source_kind(world)
        except NavlabError:  # (not a world at all: the experiment's check says so, naming it)
            return world
        if kind in ("ros_map", "movingai_map"):  # (the experiment's line gave the file form: newcomer, session 22)
            raise click.UsageError(f"--world {short_name(world)} is a map, which has no start or goal: give "
                                   "--start X Y and --goal X Y in metres (or, in an experiment file, "
                                   "{map: FILE, scen: FILE.scen, queries: N} for a Moving AI scenario)")
        return world
    if source_kind(world) not in ("ros_map", "movingai_map"):
        raise click.UsageError(f"--start and --goal are for maps (map_server YAML, Moving AI .map); {world!r} "
                               "has its own start and goal")
    return {"map": world, "queries": [[*start, *goal]]}


def note_unused_settings(exp) -> None:
    """A note on stderr for each grid planner given a ``heuristic`` or ``weight`` it does not use
    (:func:`~navlab.grid.planner.unused_settings`), each line once: its trials labelled with the value
    given run the search without it (the rows' ``params_used`` say what ran)."""
    from ..bench.experiment import routed_params
    from ..grid.planner import GRID_ALGORITHMS, unused_settings

    lines: Dict[str, None] = {}  # (ordered, each once)
    for cell in exp.cells():
        if cell.planner.name not in GRID_ALGORITHMS:  # (tree, OMPL and pose planners)
            continue
        own = routed_params(cell.planner.name, cell.params, cell.planner.params)
        lines.update(dict.fromkeys(unused_settings(cell.planner.name, own, lambda k, value: f"{k}={value}")))
    lines.update(dict.fromkeys(_untaken(exp)))
    for label, keys in exp.unswept().items():  # (its cells were run once per value, as if it took them)
        lines[f"note: {label} does not use the swept {listed(keys)}: its cells are not split by "
              f"{_once(keys)}"] = None
    for label, parts in exp.partly_unswept().items():
        lines[f"note: {label} does not use the swept {'; nor '.join(parts)}: those cells are not split by "
              f"{_once(parts)}"] = None
    for label, keys in exp.own_over_sweep().items():
        lines[f"note: {label} sets its own {listed(keys)}: the swept values do not split its cells"] = None
    for line in lines:
        click.echo(line, err=True)


def _once(settings: List[str]) -> str:
    """How a note on swept settings that do not split cells ends."""
    return f"{'them' if len(settings) > 1 else 'it'} (each runs once, not once per value)"


def _untaken(exp) -> List[str]:
    """Notes for samplers or a budget that none of the experiment's planners takes (:meth:`Experiment.unused
    <navlab.bench.experiment.Experiment.unused>`): navlab plan refuses them, and bench ran hybrid_astar with
    --sampler gaussian --max-iter 200 as if neither were given (newcomer, session 22). Notes, not refusals: a
    suite's own samplers and budget stay when --planner picks planners that take none, and a run made so must
    still resume (review, session 22)."""
    from ..bench.experiment import OMPL_PREFIX
    from ..bench.ompl_planners import COUNTING

    unused = exp.unused()
    names = ", ".join(sorted({p.name for p in exp.planners}))
    ompl = sorted({p.name for p in exp.planners if p.name.startswith(OMPL_PREFIX)})
    out = []
    if exp.samplers_given and unused["samplers"]:
        own = " (OMPL's planners draw their own)" if ompl else ""
        out.append(f"note: the samplers ({', '.join(s.title for s in exp.samplers)}) are for navlab's tree planners; "
                   f"none of this experiment's ({names}) draws them{own}, so they are not used")
    if exp.budget and unused["budget"] and not ompl:
        given = ", ".join(f"{k} {v}" for k, v in exp.budget.items())
        hybrid = "; hybrid_astar's budget is max_expansions" if any(p.name == "hybrid_astar" for p in exp.planners) \
            else ""
        out.append(f"note: the budget ({given}) is for tree and OMPL planners; none of this experiment's ({names}) "
                   f"takes one (grid planners search to the end{hybrid}), so it is not used")
    # (per planner: a max_iter beside RRTstar too is used by it, and not by RRTConnect)
    uncounted = [name for name in ompl if name[len(OMPL_PREFIX):] not in COUNTING]
    if exp.budget.get("max_iter") is not None and uncounted:  # (recorded, and never read: attack, session 23)
        one = len(uncounted) == 1
        out.append(f"note: {', '.join(uncounted)} count{'s' if one else ''} no iterations and stop{'s' if one else ''} "
                   f"on max_time alone: max_iter {exp.budget['max_iter']} is not used by {'it' if one else 'them'}")
    return out


def _adhoc_name(data, fingerprint: str) -> str:
    """``adhoc-<worlds>-<planners>-<hash>``: readable, and different for different experiments; the hash is
    the run's identity (:meth:`~navlab.bench.experiment.Experiment.fingerprint`), so the same run with more
    trials, or with samplers, a budget or a seed none of its planners uses, finds its folder to resume."""
    import re

    def short(value) -> str:
        text = value.get("map", "map") if isinstance(value, dict) else str(value)
        return re.sub(r"[^A-Za-z0-9_.]+", "_", text.rsplit("/", 1)[-1].rsplit(".", 1)[0])[:16]

    parts = [short(w) for w in data.get("worlds", [])[:2]] + [short(p) for p in data.get("planners", [])[:2]]
    return "-".join(["adhoc", *parts, fingerprint[:8]])


def _grid_axes(items) -> Dict[str, Any]:
    """``--grid KEY=[V1,V2]`` flags as an experiment's grid; values with commas and no brackets are refused
    with the bracketed form ("expand_dis must be a number, got '1,2'" came from the planner: newcomer,
    session 30)."""
    axes = parse_params(items, "--grid")
    for key, value in axes.items():
        if isinstance(value, str) and "," in value:
            raise click.BadParameter(f"'{key}={value}': a grid axis's values go in brackets: {key}=[{value}]",
                                     param_hint="--grid")
    return axes


@contextlib.contextmanager
def _ends_at_ctrl_c(folder, unit: str):
    """A Ctrl-C within the block ends the command with exit 130 and a line saying what is kept and the command
    that resumes; from then on a second Ctrl-C ends it the same way. ``unit``: what the run counts (trials, or
    BARN's runs, whose suite said nothing of a Ctrl-C outside its trials and no "every one" after the last:
    review, session 30)."""
    from ..bench.runner import Interrupted

    try:
        yield
    except Interrupted as stop:
        end_at_ctrl_c(EXIT_INTERRUPTED, click.get_current_context())
        if stop.complete:  # ("50 of 50 trials ... run the rest with" after the last one: attack, session 29)
            # ("the summary and report were not written" beside a summary.json written before the plots: newcomer,
            # session 30)
            click.echo(f"\ninterrupted: {stop.counts} are kept in {stop.folder}, every one; the report is not "
                       f"complete: {_resume_command()} writes it", err=True)
        else:
            click.echo(f"\ninterrupted: {stop.counts} are kept in {stop.folder}; "
                       f"run the rest with: {_resume_command()}", err=True)
        sys.exit(EXIT_INTERRUPTED)
    except (KeyboardInterrupt, SystemError) as exc:  # before or after the trials: every finished one is on disk
        if not interrupted_by_ctrl_c(exc):
            raise
        end_at_ctrl_c(EXIT_INTERRUPTED, click.get_current_context())
        click.echo(f"\ninterrupted: the finished {unit} are kept in {folder}; run the rest with: {_resume_command()}",
                   err=True)
        sys.exit(EXIT_INTERRUPTED)


def _resume_command() -> str:
    """The command line that was run, with --resume (and without --overwrite)."""
    args = sys.argv[1:]
    if "bench" in args:
        args = args[args.index("bench") + 1:]
    args = [a for a in args if a != "--overwrite"]
    if "--resume" not in args:
        args.append("--resume")
    return "navlab bench " + " ".join(shlex.quote(a) for a in args)


def _since_navlab_start() -> float:
    """Seconds since the navlab command started (its first import; see ``navlab.cli.STARTED``)."""
    import time

    from . import STARTED

    return time.perf_counter() - STARTED


def _overall(summary) -> List[str]:
    from ..bench.analysis import overall_verdicts

    return [f"  claim: {k}: {v}" for k, v in overall_verdicts(summary.get("claims", [])).items()]


def _f(value, digits: int = 3) -> str:
    return "-" if value is None else f"{value:.{digits}f}"
