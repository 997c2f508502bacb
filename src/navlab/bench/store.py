"""A result set on disk: ``experiment.json`` (what was asked) and
``results.jsonl`` (one row per finished trial, appended and flushed as each
trial ends, so a killed run loses only the trials in flight)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, Iterator, List

from .experiment import Experiment, ExperimentError

EXPERIMENT_FILE = "experiment.json"
RESULTS_FILE = "results.jsonl"


class ResultStore:
    """The output folder of one experiment.

    Parameters
    ----------
    folder : path
    experiment : Experiment
    resume : bool
        Keep the finished trials of an earlier run of the same experiment.
    overwrite : bool
        Discard whatever results the folder holds.

    Raises
    ------
    ExperimentError
        The folder holds results of a different experiment, or results of
        this one while neither ``resume`` nor ``overwrite`` was given.
    """

    def __init__(self, folder, experiment: Experiment, resume: bool = False, overwrite: bool = False) -> None:
        self.folder = Path(folder)
        self.experiment = experiment
        self.results_path = self.folder / RESULTS_FILE
        if self.folder.exists() and not self.folder.is_dir():
            raise ExperimentError(f"output '{folder}' exists and is not a folder")
        if overwrite:
            self.results_path.unlink(missing_ok=True)
            old_rows = []
        else:
            old_rows = list(read_rows(self.results_path)) if self.results_path.exists() else []
            _check_reuse(self.folder, experiment, old_rows, resume)
        self.folder.mkdir(parents=True, exist_ok=True)
        meta = {"fingerprint": experiment.fingerprint(), "experiment": experiment.to_dict()}
        (self.folder / EXPERIMENT_FILE).write_text(json.dumps(meta, indent=2))
        # Errors are retried on resume; the newest row of a trial wins.
        self.rows: Dict[str, Dict[str, Any]] = {row["trial_id"]: row for row in old_rows}
        self._file = None

    def finished(self) -> set:
        """Trial ids that need not run again (errored trials do)."""
        return {tid for tid, row in self.rows.items() if row.get("status") != "ERROR"}

    def append(self, row: Dict[str, Any]) -> None:
        if self._file is None:
            self._file = open(self.results_path, "a", encoding="utf-8")
        self._file.write(json.dumps(row, separators=(",", ":")) + "\n")
        self._file.flush()
        os.fsync(self._file.fileno())
        self.rows[row["trial_id"]] = row

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def current_rows(self, specs: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
        """Rows of the given trials, in the experiment's order."""
        return [self.rows[s["trial_id"]] for s in specs if s["trial_id"] in self.rows]


def _check_reuse(folder: Path, experiment: Experiment, old_rows: List[Dict[str, Any]], resume: bool) -> None:
    """Refuse to mix results: another experiment's folder, or this one's
    without ``resume``."""
    meta_path = folder / EXPERIMENT_FILE
    if meta_path.exists():
        old = json.loads(meta_path.read_text())
        if old.get("fingerprint") != experiment.fingerprint():
            raise ExperimentError(
                f"'{folder}' holds results of a different experiment ('{old.get('experiment', {}).get('name')}'; "
                f"differs in: {', '.join(_differences(old.get('experiment', {}), experiment.to_dict())) or '?'}). "
                "Use another --out, or --overwrite to discard them.")
        if old_rows and not resume:
            raise ExperimentError(f"'{folder}' already holds {len(old_rows)} finished trials of this experiment; "
                                  "pass --resume to continue it or --overwrite to start again")
    elif old_rows:
        raise ExperimentError(f"'{folder}' holds results without {EXPERIMENT_FILE}; use another --out")


def read_rows(path) -> Iterator[Dict[str, Any]]:
    """Rows of a results file; a last line cut short by a kill is skipped."""
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            try:
                yield json.loads(line)
            except json.JSONDecodeError:
                continue


def _differences(a: Dict[str, Any], b: Dict[str, Any]) -> List[str]:
    ignored = {"trials", "description", "name", "claims"}
    return [k for k in sorted(set(a) | set(b)) if k not in ignored and a.get(k) != b.get(k)]
