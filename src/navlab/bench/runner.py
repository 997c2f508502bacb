"""Run an experiment into an output folder and write its report.

Output folder::

    experiment.json   the experiment and its fingerprint
    results.jsonl     one row per finished trial (appended as trials end)
    summary.json      per-cell statistics, comparisons and claim verdicts
    report.md         the report; report.html is the same, self-contained
    plots/            box plots, convergence curves, example trees
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Optional

from .analysis import by_world, judge_claims, summarize
from .executors import EXECUTORS
from .experiment import OMPL_PREFIX, Experiment
from .report import build, to_html, to_markdown
from .store import ResultStore
from .trial import execute, machine


@dataclass
class BenchRun:
    """What :func:`run_experiment` did."""

    folder: Path
    rows: List[Dict[str, Any]]
    summary: Dict[str, Any]
    ran: int  #: trials run now (the others were already finished)
    elapsed_s: float

    @property
    def errors(self) -> int:
        return sum(r.get("status") == "ERROR" for r in self.rows)


def run_experiment(experiment: Experiment, out, executor: str = "process", jobs: Optional[int] = None,
                   scheduler: Optional[str] = None, resume: bool = False, overwrite: bool = False,
                   progress: bool = True, plots: bool = True) -> BenchRun:
    """Run every unfinished trial of ``experiment``, store the rows, write
    summary and report. See :class:`~navlab.bench.store.ResultStore` for
    ``resume`` and ``overwrite``."""
    run_trials = EXECUTORS.get(executor)
    store = ResultStore(out, experiment, resume=resume, overwrite=overwrite)
    specs = experiment.trial_specs()
    done = store.finished()
    todo = [s for s in specs if s["trial_id"] not in done]
    t0 = time.perf_counter()
    try:
        if todo:
            bar = _progress(len(todo), f"{experiment.name}: {len(specs) - len(todo)} of {len(specs)} done before"
                            if len(todo) < len(specs) else experiment.name, progress)
            for row in run_trials(todo, jobs=jobs, scheduler=scheduler):
                store.append(row)
                bar.update(1)
            bar.close()
    finally:
        store.close()
    elapsed = time.perf_counter() - t0
    rows = store.current_rows(specs)
    summary = write_report(experiment, rows, store.folder, elapsed if todo else None, plots=plots)
    return BenchRun(store.folder, rows, summary, len(todo), elapsed)


def _progress(total: int, desc: str, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="trial", disable=not enabled, dynamic_ncols=True)


def write_report(experiment: Experiment, rows: List[Dict[str, Any]], folder: Path,
                 elapsed_s: Optional[float] = None, plots: bool = True) -> Dict[str, Any]:
    """summary.json, report.md, report.html and (with ``plots``) the figures."""
    summary = summarize(rows)
    summary["claims"] = judge_claims(rows, experiment.claims)
    (folder / "summary.json").write_text(json.dumps(summary, indent=1))
    images = make_plots(experiment, rows, folder) if plots else {}
    from .. import __version__

    meta = {"version": __version__, **machine()}
    blocks = build(experiment.to_dict(), rows, summary, images, elapsed_s, meta)
    (folder / "report.md").write_text(to_markdown(blocks))
    (folder / "report.html").write_text(to_html(blocks, folder))
    return summary


def make_plots(experiment: Experiment, rows: List[Dict[str, Any]], folder: Path) -> Dict[str, List[str]]:
    """Figures per world; the example trees rerun trial 0 of each navlab cell
    with its recorded seed (same seed, same tree) in this process."""
    from ..viz.bench_plot import box_plots, convergence_plot, example_trees
    from .trial import _world

    plot_dir = folder / "plots"
    plot_dir.mkdir(exist_ok=True)
    images: Dict[str, List[str]] = {}
    specs = {s["trial_id"]: s for s in experiment.trial_specs()}
    for world, groups in by_world(rows).items():
        slug = _slug(world)
        names = [f"plots/box_{slug}.png"]
        box_plots(world, groups, str(folder / names[0]))
        if convergence_plot(world, groups, str(folder / f"plots/convergence_{slug}.png")):
            names.append(f"plots/convergence_{slug}.png")
        examples = []
        for group, members in groups.items():
            first = min(members, key=lambda r: r["trial"])
            spec = specs.get(first["trial_id"])
            if spec is None or spec["cell"]["planner"]["name"].startswith(OMPL_PREFIX):
                continue
            try:
                examples.append((f"{group} (trial {first['trial']})", execute(spec, keep_tree=True)))
            except Exception:  # noqa: BLE001 - an errored trial has no tree to draw
                continue
        if examples:
            names.append(f"plots/trees_{slug}.png")
            example_trees(_world(world), examples, str(folder / names[-1]))
        images[world] = names
    return images


def _slug(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in Path(name).stem)
