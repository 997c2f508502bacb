"""Run an experiment into an output folder and write its report.

Output folder::

    experiment.json   the experiment and its fingerprint
    results.jsonl     one row per finished trial (appended as trials end),
                      and the repeated trials that measure timing noise
    summary.json      per-cell statistics, comparisons and claim verdicts
    report.md         the report; report.html is the same, self-contained
    plots/            box plots, convergence curves, example trees

Trials run interleaved across cells (trial 0 of every cell, then trial 1,
...), so a machine whose load changes during the run slows every cell alike;
the noise-measuring repeats run last.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, Optional, Sequence, Set

from ..atomic import write_text_atomic
from ..errors import interrupted_by_ctrl_c
from ..limits import MAX_JOBS, check_count, check_flag, shown
from ..wording import counted
from .analysis import by_world, compared_rows, judge_claims, scope_text, summarize, timed
from .errors import ExperimentError
from .executors import EXECUTORS, check_executor
from .export import write_store_csv
from .experiment import OMPL_PREFIX, Experiment
from .report import build, to_html, to_markdown
from .store import OutputError, ResultStore, read_rows, write_error
from .trial import execute, machine


class Interrupted(Exception):
    """Ctrl-C during a run: the rows written so far are kept."""

    def __init__(self, folder: Path, kept: int, total: int, repeats_kept: int = 0, repeats: int = 0,
                 unit: str = "trials") -> None:
        # the progress bar counted the noise repeats too: say them, so the two counts add up
        self.counts = f"{kept} of {total} {unit}" + (f" and {repeats_kept} of {repeats} noise repeats" if repeats
                                                     else "")
        super().__init__(f"interrupted: {self.counts} kept in {folder}")
        self.folder, self.kept, self.total = folder, kept, total
        #: every trial and noise repeat on disk: only the summary and the report are missing
        self.complete = kept == total and repeats_kept == repeats


@dataclass
class BenchRun:
    """What :func:`run_experiment` did."""

    folder: Path
    rows: List[Dict[str, Any]]
    summary: Dict[str, Any]
    ran: int  #: trials run now (the others were already finished), repeats included
    elapsed_s: float
    #: seconds per phase of the run (see :func:`breakdown_lines`)
    breakdown: Dict[str, Any] = field(default_factory=dict)

    @property
    def errors(self) -> int:
        return sum(r.get("status") == "ERROR" for r in self.rows)


#: the clocks a run's times can be summarised in (``time_kind``)
TIME_KINDS = ("cpu", "wall")


def _check_run_arguments(experiment, out, jobs, time_kind) -> None:
    """ExperimentError naming the argument of :func:`run_experiment` it cannot take, before anything runs (a
    plain mapping, an output folder of None, jobs=-1 or 'a': raw errors; time_kind='foo' a KeyError after
    every trial had run: API attack, session 29)."""
    if not isinstance(experiment, Experiment):
        raise ExperimentError(f"experiment: expected what load_experiment returns, got {type(experiment).__name__}")
    if not isinstance(out, (str, os.PathLike)) or not os.fspath(out):
        raise ExperimentError(f"out: expected an output folder's path, got {shown(out)}")
    if jobs is not None:
        check_count("jobs", jobs, 1, MAX_JOBS)
    if time_kind not in TIME_KINDS:
        raise ExperimentError(f"time_kind: expected one of {', '.join(TIME_KINDS)}, got {shown(time_kind)}")


def interleave(specs: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """Trial 0 of every cell, then trial 1 of every cell, ...; cells in their
    order of first appearance."""
    order: Dict[str, int] = {}
    for s in specs:
        order.setdefault(s["cell_id"], len(order))
    return sorted(specs, key=lambda s: (s["trial"], order[s["cell_id"]]))


def run_experiment(experiment: Experiment, out, executor: str = "process", jobs: Optional[int] = None,
                   scheduler: Optional[str] = None, resume: bool = False, overwrite: bool = False,
                   progress: bool = True, plots: bool = True, time_kind: str = "cpu") -> BenchRun:
    """Run every unfinished trial of ``experiment``, store the rows, write
    summary and report. See :class:`~navlab.bench.store.ResultStore` for
    ``resume`` and ``overwrite``; ``time_kind`` is ``"cpu"`` or ``"wall"``.

    Raises
    ------
    ExperimentError
        Before any trial: the executor cannot run (Dask missing or its
        scheduler unreachable), the folder is in use or holds other results.
        During the run: a file cannot be written (one line naming it).
    Interrupted
        Ctrl-C; the rows written so far are kept (``--resume`` runs the rest).
    """
    _check_run_arguments(experiment, out, jobs, time_kind)
    resume, overwrite = check_flag("resume", resume), check_flag("overwrite", overwrite)
    progress, plots = check_flag("progress", progress), check_flag("plots", plots)
    check_executor(executor, scheduler)
    run_trials = EXECUTORS.get(executor)
    phases: Dict[str, Any] = {}
    with ResultStore(out, experiment, resume=resume, overwrite=overwrite) as store:
        if store.taken_over_from:
            print(f"{store.folder}: took over the lock of run pid {store.taken_over_from}, which is gone "
                  "(killed before it could release it)", file=sys.stderr)
        if store.rejected:
            print(f"{store.results_path}: {store.rejected} line(s) that are not trial rows were set aside in "
                  f"{store.folder / 'results.rejected.jsonl'} (with the reason); their trials run again",
                  file=sys.stderr)
        specs = experiment.trial_specs()
        cells = {s["cell_id"] for s in specs}
        _note_rows_of_no_cell(store, cells)
        _note_trials_past_the_count(store, specs, cells, experiment.trials)
        done = store.finished()
        todo = interleave([s for s in specs if s["trial_id"] not in done])
        trials_todo = len(todo)
        repeats_todo = interleave([s for s in experiment.noise_specs() if s["trial_id"] not in done])
        todo += repeats_todo
        trees: Dict[str, Dict[str, Any]] = {}
        t0 = time.perf_counter()
        new_rows: List[Dict[str, Any]] = []

        def stop() -> Interrupted:  # what a Ctrl-C raises, in the trials and in the report alike
            return stopped(store, specs, experiment.noise_specs())

        if todo:
            bar = _progress(len(todo), _bar_label(experiment.name, len(specs), trials_todo, len(repeats_todo)),
                            progress)
            with stops_at_ctrl_c(stop, bar) as trials:
                for row in trials.track(run_trials(todo, jobs=jobs, scheduler=scheduler)):
                    tree = row.pop("tree", None)
                    if tree is not None:
                        trees[row["cell_id"]] = tree
                    store.append(row)
                    new_rows.append(row)
                    bar.update(1)
        elapsed = time.perf_counter() - t0
        phases["trials"] = elapsed
        phases["workers"] = 1 if executor == "serial" else (jobs or os.cpu_count() or 1)
        phases["warmup_s"] = sum(r.get("warmup_s") or 0.0 for r in new_rows)
        phases["trial_cpu_s"] = sum(r.get("cpu_s") or 0.0 for r in new_rows)
        phases["repeats"] = sum(bool(r.get("repeat")) for r in new_rows)
        rows = store.current_rows(specs)
        repeats = [store.rows[s["trial_id"]] for s in experiment.noise_specs() if s["trial_id"] in store.rows]
        # every trial is on disk: a Ctrl-C here says so (it said "run the rest with", as if trials were missing,
        # through the report's seconds of plotting: review, session 29)
        with stops_at_ctrl_c(stop):
            summary = write_report(experiment, rows + repeats, store.folder, elapsed if todo else None, plots=plots,
                                   time_kind=time_kind, trees=trees, torn=store.torn, phases=phases,
                                   plot_jobs=1 if executor == "serial" else min(phases["workers"],
                                                                                os.cpu_count() or 1))
            write_store_csv(store)
    return BenchRun(store.folder, rows, summary, len(todo), elapsed, phases)


class _Trials:
    """What :func:`stops_at_ctrl_c` yields: :meth:`track` hands it the executor's row iterator to close."""

    def __init__(self) -> None:
        self.rows: Optional[Iterator[Dict[str, Any]]] = None

    def track(self, rows: Iterator[Dict[str, Any]]) -> Iterator[Dict[str, Any]]:
        self.rows = rows
        return rows


@contextlib.contextmanager
def stops_at_ctrl_c(stop: Callable[[], Interrupted], bar=None) -> Iterator[_Trials]:
    """A Ctrl-C within the block raises ``stop()`` (an :class:`Interrupted`) instead; a Ctrl-C handed back as a
    SystemError (:func:`~navlab.errors.interrupted_by_ctrl_c`) is one too. The executor's row iterator given to
    the yielded :meth:`_Trials.track` is closed when the block ends early, stopping its workers; ``bar`` is
    closed however the block ends.

    The iterator is closed here, not left to be freed: a Ctrl-C that reached this process between two rows
    left it to be closed as it was freed, and a second Ctrl-C while its workers stopped printed "Exception
    ignored in: <generator object process>" and a traceback above the resume line (CI, session 29). A second
    Ctrl-C then asks for what the first did, and a clean-up that fails is a line on stderr, not what ends the
    run.
    """
    trials = _Trials()
    try:
        yield trials
    except BaseException as exc:
        if trials.rows is not None:
            _close_quietly(trials.rows)
        if bar is not None:
            bar.close()
        if interrupted_by_ctrl_c(exc):
            raise stop() from None
        raise
    if bar is not None:
        bar.close()


def _close_quietly(rows: Iterator[Dict[str, Any]]) -> None:
    """Close ``rows`` (a generator: an executor may return a plain iterator) after the run ended early; a Ctrl-C
    meanwhile asks for the same end, and a failed clean-up (the pool's temporary folder, a Dask cluster) is one
    line on stderr (review, session 30: its traceback replaced the resume line)."""
    close = getattr(rows, "close", None)
    try:
        if close is not None:
            close()
    except (KeyboardInterrupt, Exception) as exc:
        if not interrupted_by_ctrl_c(exc):
            print(f"note: stopping the trials did not end cleanly: {type(exc).__name__}: {exc}", file=sys.stderr)


def _note_rows_of_no_cell(store: ResultStore, cells: Set[str]) -> None:
    """Say on stderr how many resumed rows belong to no cell of the experiment as it is routed now (a setting
    that came to split a planner's cells or to merge them, after an upgrade: a run sweeping ``weight`` before
    Hybrid A* took it ran hybrid_astar as one cell): they stay in results.jsonl and results.csv, left out of
    the report (attack, session 24: they were left without a word). ``cells``: the experiment's cell ids (a
    cell's trials past ``--trials`` are not of another cell: :func:`_note_trials_past_the_count`)."""
    stale = [row for row in store.rows.values() if row.get("cell_id") not in cells]
    if stale:
        labels = sorted({str(row.get("label") or row.get("planner") or "?") for row in stale})
        one = len(stale) == 1
        print(f"{store.folder}: {counted(len(stale), 'kept row')} ({', '.join(labels)}) "
              f"{'belongs' if one else 'belong'} to no cell of this experiment as navlab now runs it (its cells are "
              f"split or merged differently since {'it' if one else 'they'} ran): kept in results.jsonl and "
              "results.csv, left out of the report", file=sys.stderr)


def _note_trials_past_the_count(store: ResultStore, specs: List[Dict[str, Any]], cells: Set[str],
                                trials: int) -> None:
    """Say on stderr how many resumed trials of this experiment's cells lie past its trial count (an earlier
    run with more ``--trials``): they stay in results.jsonl and results.csv, left out of the report, which
    otherwise shrank without a word (newcomer, session 26). ``cells``: the cell ids of ``specs``."""
    wanted = {s["trial_id"] for s in specs}
    past = [row for row in store.rows.values() if row.get("cell_id") in cells and not row.get("repeat")
            and row.get("trial_id") not in wanted and isinstance(row.get("trial"), int)]
    if past:
        most = max(row["trial"] for row in past) + 1
        one = len(past) == 1
        print(f"{store.folder}: {counted(len(past), 'kept trial')} {'lies' if one else 'lie'} past this run's "
              f"{trials} per cell: kept in results.jsonl and results.csv, left out of the report (--trials {most} "
              f"includes {'it' if one else 'them'})", file=sys.stderr)


def stopped(store: ResultStore, specs: List[Dict[str, Any]], repeats: Sequence[Dict[str, Any]] = (),
            unit: str = "trials") -> Interrupted:
    """After Ctrl-C: close the store (releasing its lock) and say how many of ``specs`` (and of the
    noise ``repeats``) are on disk, counted in ``unit``."""
    store.close()
    kept = {r["trial_id"] for r in read_rows(store.results_path)} if store.results_path.exists() else set()
    return Interrupted(store.folder, len(kept & {s["trial_id"] for s in specs}), len(specs),
                       len(kept & {s["trial_id"] for s in repeats}), len(repeats), unit)


def _bar_label(name: str, trials: int, trials_todo: int, repeats_todo: int) -> str:
    """The progress bar's title: the bar counts trials and noise repeats alike, so say both (one trial
    showed a bar of 2), and how many trials an earlier run already kept."""
    label = name + (f": {trials - trials_todo} of {trials} trials done before" if trials_todo < trials else "")
    if repeats_todo:
        label += f" ({counted(trials_todo, 'trial')} + {counted(repeats_todo, 'noise repeat')})"
    return label


def _progress(total: int, desc: str, enabled: bool):
    """The run's bar on stderr; off when not ``enabled`` or when stderr is not a terminal (a log
    file would fill with carriage-return redraws; the run's summary lines say what it did)."""
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="trial", disable=None if enabled else True, dynamic_ncols=True)


def write_report(experiment: Experiment, rows: List[Dict[str, Any]], folder: Path,
                 elapsed_s: Optional[float] = None, plots: bool = True, time_kind: str = "cpu",
                 trees: Optional[Dict[str, Dict[str, Any]]] = None, torn: int = 0,
                 phases: Optional[Dict[str, Any]] = None, plot_jobs: int = 1) -> Dict[str, Any]:
    """summary.json, report.md, report.html and (with ``plots``) the figures,
    drawn by ``plot_jobs`` processes. ``rows`` may include the noise repeats;
    ``phases`` gets the seconds spent here."""
    phases = phases if phases is not None else {}
    t0 = time.perf_counter()
    summary = summarize(rows, time_kind)
    summary["claims"] = judge_claims(rows, experiment.claims, time_kind)
    summary["torn_lines"] = torn
    summary["warmup_s"] = sum(r.get("warmup_s") or 0.0 for r in rows)
    _write(folder / "summary.json", json.dumps(summary, indent=1))
    t1 = time.perf_counter()
    trials = [r for r in timed(rows, time_kind) if not r.get("repeat")]
    images = make_plots(experiment, trials, folder, trees or {}, jobs=plot_jobs,
                        time_label=summary["time_label"]) if plots else {}
    t2 = time.perf_counter()
    from .. import __version__

    meta = {"version": __version__, **machine()}
    blocks = build(experiment.to_dict(), trials, summary, images, elapsed_s, meta)
    _write(folder / "report.md", to_markdown(blocks))
    _write(folder / "report.html", to_html(blocks, folder))
    phases["plots"] = t2 - t1
    phases["report"] = (t1 - t0) + (time.perf_counter() - t2)
    return summary


def _write(path: Path, text: str) -> None:
    try:
        write_text_atomic(path, text)
    except OSError as exc:
        raise write_error(path, exc) from None


def make_plots(experiment: Experiment, rows: List[Dict[str, Any]], folder: Path,
               trees: Dict[str, Dict[str, Any]], jobs: int = 1, time_label: str = "time") -> Dict[str, List[str]]:
    """Figures per world, drawn by up to ``jobs`` processes (one world each).
    The example tree of each cell is trial 0's, kept by the worker that ran
    it; when trial 0 ran in an earlier (resumed) run, it is rerun with its
    recorded seed (same seed, same tree)."""
    plot_dir = folder / "plots"
    try:
        plot_dir.mkdir(exist_ok=True)
    except OSError as exc:
        raise write_error(plot_dir, exc) from None
    specs = {s["trial_id"]: s for s in experiment.trial_specs() if s["trial"] == 0}
    tasks = []
    for world, groups in by_world(rows).items():
        firsts = {g: min(m, key=lambda r: r["trial"]) for g, m in groups.items()}
        group_specs = {g: specs.get(r["trial_id"]) for g, r in firsts.items()}
        tasks.append((world, {g: [_plot_fields(r) for r in m] for g, m in groups.items()},
                      {g: trees.get(r["cell_id"]) if r["trial"] == 0 else None for g, r in firsts.items()},
                      group_specs, str(folder), time_label))
    if jobs > 1 and len(tasks) > 1:
        from .executors import stoppable_pool

        with stoppable_pool(min(jobs, len(tasks))) as pool:
            done = list(pool.map(_plot_world, tasks))
    else:
        done = [_plot_world(t) for t in tasks]
    for error in (d for d in done if isinstance(d, str)):
        raise OutputError(error)
    return {world: names for world, names in done}


#: what the figures read from a row
_PLOT_FIELDS = ("cell_id", "trial", "status", "success", "cost", "time", "time_s", "trace", "query")


def _plot_fields(row: Dict[str, Any]) -> Dict[str, Any]:
    return {k: row.get(k) for k in _PLOT_FIELDS}


def _plot_world(task):
    """One world's figures: box plots, convergence, example trees. Returns
    (world, image names), or the one-line message of a failed write."""
    from ..viz.bench_plot import box_plots, convergence_plot, example_trees
    from .trial import trial_world

    world, groups, trees, specs, folder, time_label = task
    folder = Path(folder)
    slug = _slug(world)
    names = [f"plots/box_{slug}.png"]
    try:
        compared, scope = compared_rows(groups)  # the rows the summary and the verdicts describe
        box_plots(world, groups, str(folder / names[0]), time_label=f"{time_label} [s]", compared=compared,
                  scope=scope_text(scope))
        if convergence_plot(world, groups, str(folder / f"plots/convergence_{slug}.png")):
            names.append(f"plots/convergence_{slug}.png")
        examples = []
        for group, members in groups.items():
            first = min(members, key=lambda r: r["trial"])
            tree = trees.get(group) or _rerun_tree(specs.get(group))
            if tree is None:
                continue
            label = f"{first['cost']:.2f} m" if first.get("success") and first.get("cost") is not None \
                else first.get("status", "?")
            examples.append((f"{group} (trial {first['trial']})\n{label}", tree))
        if examples:
            names.append(f"plots/trees_{slug}.png")
            drawn = trial_world(next(sp for sp in specs.values() if sp is not None))  # trial 0's query on a map
            example_trees(drawn, examples, str(folder / names[-1]))
    except OSError as exc:
        return str(write_error(folder / "plots", exc))
    return world, names


def _rerun_tree(spec: Optional[Dict[str, Any]]) -> Optional[Dict[str, Any]]:
    if spec is None or spec["cell"]["planner"]["name"].startswith(OMPL_PREFIX):
        return None
    try:
        result = execute(spec, keep_tree=True)
    except Exception:  # noqa: BLE001 - an errored trial has no tree to draw
        return None
    if result.tree is None or "nodes" not in result.tree:
        return None
    return {"nodes": result.tree["nodes"], "parent": result.tree["parent"], "path": result.path}


def breakdown_lines(run: BenchRun, total_s: Optional[float] = None) -> List[str]:
    """Where the run's time went, for the end of ``navlab bench``."""
    p = run.breakdown
    if not p:
        return []
    parts = []
    if total_s is not None:
        parts.append(f"total {total_s:.1f} s since navlab started")
        known = p.get("trials", 0) + p.get("plots", 0) + p.get("report", 0)
        parts.append(f"start-up and checks {max(0.0, total_s - known):.1f} s")
    workers = p.get("workers", 1)
    parts.append(f"trials {p.get('trials', 0):.1f} s on {counted(workers, 'worker')} "
                 f"(trial CPU {p.get('trial_cpu_s', 0):.1f} s, warm-up {p.get('warmup_s', 0):.1f} s summed over "
                 f"workers, {counted(p.get('repeats', 0), 'noise repeat')})")
    parts.append(f"plots {p.get('plots', 0):.1f} s")
    parts.append(f"summary and report {p.get('report', 0):.1f} s")
    return ["time: " + "; ".join(parts)]


def _slug(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in Path(name).stem)
