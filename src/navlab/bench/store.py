"""A result set on disk: ``experiment.json`` (what was asked) and
``results.jsonl`` (one row per finished trial, appended and flushed as each
trial ends, so a killed run loses only the trials in flight).

One run at a time: the folder is locked (a POSIX record lock on ``.lock``,
held by the run's main process until it ends; the kernel drops it when that
process dies, pool workers never hold it, so a killed run never leaves a stale
lock) and a second run is refused with the holder's pid. A run whose ``.lock``
is deleted under it stops before its next row, so two runs never write the
same trials. Lines of ``results.jsonl`` that are not trial rows (not UTF-8, not
an object, no ``trial_id``, text where a number belongs) are moved to
``results.rejected.jsonl`` with the reason, and counted. ``experiment.json`` is replaced atomically. A last line cut short (a
kill, a full disk) is moved to ``results.torn.jsonl`` before anything is
appended, so the next row starts on a line of its own.
"""

from __future__ import annotations

import errno
import fcntl
import json
import os
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Tuple

from ..atomic import write_text_atomic
from ..errors import ParameterError
from ..limits import short_name
from ..wording import counted
from .experiment import Experiment, ExperimentError, differences

EXPERIMENT_FILE = "experiment.json"
RESULTS_FILE = "results.jsonl"
TORN_FILE = "results.torn.jsonl"
REJECTED_FILE = "results.rejected.jsonl"
LOCK_FILE = ".lock"


class OutputError(ExperimentError):
    """A file of the output folder cannot be written (disk full, permissions)."""


def write_error(path, exc: OSError) -> OutputError:
    """The one-line error for a failed write of ``path``."""
    return OutputError(f"cannot write '{path}': {exc.strerror or exc}")


class FolderLock:
    """An exclusive, non-blocking POSIX record lock (``lockf``) on ``folder/.lock``
    that records the holder's pid.

    A record lock belongs to the process that took it: pool workers forked
    from it do not hold it (with ``flock`` they inherited it, so a killed run's
    orphaned workers kept the folder locked), and the kernel drops it when the
    holder dies. A lock file naming a pid that is gone is taken over with a
    line saying so (:attr:`taken_over_from`). :meth:`release` empties the file.
    """

    def __init__(self, folder: Path) -> None:
        self.path = folder / LOCK_FILE
        self.taken_over_from: Optional[str] = None
        try:
            self._fd: Optional[int] = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise write_error(self.path, exc) from None
        holder = os.pread(self._fd, 32, 0).decode(errors="replace").strip()
        try:
            fcntl.lockf(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(self._fd)
            self._fd = None
            if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                raise ExperimentError(f"'{folder}' is in use by another navlab bench run (pid {holder or 'unknown'}); "
                                      "wait for it to end or use another --out") from None
            raise
        if holder and holder != str(os.getpid()):
            self.taken_over_from = holder  # its run was killed: the kernel dropped the lock with it
        os.ftruncate(self._fd, 0)
        os.pwrite(self._fd, f"{os.getpid()}\n".encode(), 0)
        self._inode = os.fstat(self._fd).st_ino

    def check(self) -> None:
        """Raise OutputError if the lock file was removed or replaced during the run:
        another run may then hold a new lock on the folder, and both would write rows."""
        try:
            same = os.stat(self.path).st_ino == self._inode
        except OSError:
            same = False
        if not same:
            raise OutputError(f"'{self.path}' was removed during the run, so another run could start in the same "
                              "folder: stopping here (the finished trials are kept; --resume continues)")

    def release(self) -> None:
        if self._fd is not None:
            try:
                if os.fstat(self._fd).st_ino == self._inode:
                    os.ftruncate(self._fd, 0)  # a clean end leaves no holder behind
            except OSError:
                pass
            os.close(self._fd)  # closing the descriptor drops the lock
            self._fd = None


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
        if resume and overwrite:
            raise ExperimentError("--resume keeps the finished trials and --overwrite discards them: give one")
        self.folder = Path(folder)
        self.experiment = experiment
        self.results_path = self.folder / RESULTS_FILE
        if self.folder.exists() and not self.folder.is_dir():
            raise ExperimentError(f"output '{folder}' exists and is not a folder")
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:  # (said as a file's write, "cannot write '/proc/nope'": newcomer, session 31)
            raise OutputError(f"cannot make the results folder '{folder}': {exc.strerror or exc}") from None
        self._lock: Optional[FolderLock] = FolderLock(self.folder)
        #: pid of a killed run whose lock this run took over (None when the folder was free)
        self.taken_over_from = self._lock.taken_over_from
        self._file = None
        #: lines of results.jsonl set aside (into results.rejected.jsonl) as not being trial rows
        self.rejected = 0
        try:
            contents = experiment.world_contents()
            _cut_torn_tail(self.results_path)
            if overwrite:
                self.results_path.unlink(missing_ok=True)
                (self.folder / TORN_FILE).unlink(missing_ok=True)
                old_rows = []
            else:
                old_rows, self.rejected = _set_aside_bad_rows(self.results_path) if self.results_path.exists() \
                    else ([], 0)
                _check_reuse(self.folder, experiment, old_rows, resume, contents)
            #: torn last lines cut from results.jsonl over the folder's life (kept in results.torn.jsonl)
            self.torn = _count_lines(self.folder / TORN_FILE)
            meta = {"fingerprint": experiment.fingerprint(), "experiment": experiment.to_dict(),
                    "world_contents": contents}
            try:
                write_text_atomic(self.folder / EXPERIMENT_FILE, json.dumps(meta, indent=2))
            except OSError as exc:
                raise write_error(self.folder / EXPERIMENT_FILE, exc) from None
        except BaseException:
            self.close()
            raise
        # Errors are retried on resume; the newest row of a trial wins.
        self.rows: Dict[str, Dict[str, Any]] = {row["trial_id"]: row for row in old_rows}

    def finished(self) -> set:
        """Trial ids that need not run again (errored trials do)."""
        return {tid for tid, row in self.rows.items() if row.get("status") != "ERROR"}

    def append(self, row: Dict[str, Any]) -> None:
        """Write one row and flush it to disk (one line, whole or torn: never
        two rows on one line)."""
        line = json.dumps(row, separators=(",", ":")) + "\n"
        if self._lock is not None:
            self._lock.check()
        try:
            if self._file is None:
                self._file = open(self.results_path, "a", encoding="utf-8")
            self._file.write(line)
            self._file.flush()
            os.fsync(self._file.fileno())
        except OSError as exc:
            self._abandon_file()
            raise write_error(self.results_path, exc) from None
        self.rows[row["trial_id"]] = row

    def _abandon_file(self) -> None:
        """After a failed write the buffer may hold part of a line: drop it
        (the next run cuts the torn tail)."""
        if self._file is not None:
            try:
                self._file.close()
            except OSError:
                pass
            self._file = None

    def close(self) -> None:
        """Close the results file and release the folder's lock."""
        try:
            if self._file is not None:
                try:
                    self._file.close()
                except OSError as exc:
                    raise write_error(self.results_path, exc) from None
                finally:
                    self._file = None
        finally:
            if self._lock is not None:
                self._lock.release()
                self._lock = None

    def __enter__(self) -> "ResultStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def current_rows(self, specs: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
        """Rows of the given trials, in the experiment's order."""
        return [self.rows[s["trial_id"]] for s in specs if s["trial_id"] in self.rows]


def _check_reuse(folder: Path, experiment: Experiment, old_rows: List[Dict[str, Any]], resume: bool,
                 contents: Dict[str, str]) -> None:
    """Refuse to mix results: another experiment's folder, one computed on world files that have changed
    since (``contents``: :meth:`~navlab.bench.experiment.Experiment.world_contents`), or this one's without
    ``resume``."""
    meta_path = folder / EXPERIMENT_FILE
    if meta_path.exists():
        try:
            old = json.loads(meta_path.read_text(encoding="utf-8"))
            if not isinstance(old, dict) or not isinstance(old.get("experiment", {}), dict):
                raise ParameterError("not an object with 'fingerprint' and 'experiment'")
        except (ValueError, UnicodeDecodeError, OSError) as exc:
            raise ExperimentError(f"'{meta_path}' is damaged ({str(exc).splitlines()[0][:120]}), so the results "
                                  "beside it cannot be matched to this experiment: restore it, use another --out, "
                                  "or --overwrite to start again") from None
        if old.get("fingerprint") not in experiment.fingerprints():
            changed = ", ".join(differences(old.get("experiment", {}), experiment.to_dict())) or \
                "no setting its experiment.json shows; its results were identified another way"
            raise ExperimentError(
                f"'{folder}' holds results of a different experiment ('{old.get('experiment', {}).get('name')}'; "
                f"differs in: {changed}). Use another --out, or --overwrite to discard them.")
        changed = [world for world, digest in (old.get("world_contents") or {}).items()
                   if contents.get(world, digest) != digest]
        if changed and old_rows:  # (a run from before the digests were kept has none to compare)
            raise ExperimentError(f"'{folder}' holds results computed on another version of "
                                  f"{', '.join(map(short_name, changed))} (the file changed since): use another "
                                  "--out, or --overwrite to discard them")
        if old_rows and not resume:
            # (a BARN study has no noise repeats to count: newcomer, session 30)
            counts = " (trials and noise repeats)" if hasattr(experiment, "noise_specs") else ""
            raise ExperimentError(f"'{folder}' already holds {counted(len(old_rows), 'finished run')} of this "
                                  f"experiment{counts}; pass --resume to continue it or --overwrite to start again")
    elif old_rows:
        raise ExperimentError(f"'{folder}' holds results without {EXPERIMENT_FILE}; use another --out")


def _cut_torn_tail(path: Path) -> int:
    """Move an unterminated last line of ``path`` to the torn file beside it
    and truncate ``path`` after its last complete line; 1 if it did, else 0."""
    try:
        with open(path, "rb+") as f:
            size = f.seek(0, os.SEEK_END)
            if size == 0:
                return 0
            f.seek(size - 1)
            if f.read(1) == b"\n":
                return 0
            f.seek(max(0, size - (1 << 20)))
            tail = f.read()
            cut = size - len(tail) + tail.rfind(b"\n") + 1 if b"\n" in tail else 0
            f.seek(cut)
            fragment = f.read()
            torn = path.parent / TORN_FILE
            with open(torn, "ab") as side:
                side.write(fragment + b"\n")
                side.flush()
                os.fsync(side.fileno())
            f.truncate(cut)
            f.flush()
            os.fsync(f.fileno())
            return 1
    except FileNotFoundError:
        return 0
    except OSError as exc:
        raise write_error(path, exc) from None


def _count_lines(path: Path) -> int:
    try:
        with open(path, "rb") as f:
            return sum(1 for line in f if line.strip())
    except FileNotFoundError:
        return 0


#: row fields that hold a number (or null) in every trial row
NUMERIC_FIELDS = ("cost", "time_s", "cpu_s", "wall_s", "warmup_s", "iterations", "nodes", "collision_checks",
                  "trial", "seed")


def row_problem(row: Any) -> Optional[str]:
    """Why a parsed line is not a trial row (None when it is one)."""
    if not isinstance(row, dict):
        return f"not a JSON object but {type(row).__name__}"
    if not isinstance(row.get("trial_id"), str) or not row["trial_id"]:
        return "no trial_id"
    if not isinstance(row.get("status", ""), str):
        return "status is not text"
    for key in NUMERIC_FIELDS:
        value = row.get(key)
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))):
            return f"{key} is {type(value).__name__}, not a number"
    return None


def read_rows(path, rejected: Optional[List[Tuple[bytes, str]]] = None) -> Iterator[Dict[str, Any]]:
    """Trial rows of a results file. A line that is not one (cut short by a
    kill, not UTF-8, not a JSON object, no trial_id, text where a number
    belongs) is skipped, and appended to ``rejected`` with why when given."""
    with open(path, "rb") as f:
        for raw in f:
            line = raw.strip()
            if not line:
                continue
            try:
                row = json.loads(line.decode("utf-8"))
                problem = row_problem(row)
            except UnicodeDecodeError:
                problem = "not UTF-8 text"
            except json.JSONDecodeError:
                problem = "not JSON"
            if problem is None:
                yield row
            elif rejected is not None:
                rejected.append((line, problem))


def _set_aside_bad_rows(path: Path) -> Tuple[List[Dict[str, Any]], int]:
    """The trial rows of ``path``; lines that are not trial rows are moved to
    results.rejected.jsonl (each with why) and ``path`` rewritten without them."""
    rejected: List[Tuple[bytes, str]] = []
    rows = list(read_rows(path, rejected))
    if rejected:
        side = path.parent / REJECTED_FILE
        try:
            with open(side, "ab") as f:
                for line, why in rejected:
                    f.write(json.dumps({"why": why, "line": line.decode("utf-8", errors="replace")}).encode()
                            + b"\n")
            write_text_atomic(path, "".join(json.dumps(r, separators=(",", ":")) + "\n" for r in rows))
        except OSError as exc:
            raise write_error(side, exc) from None
    return rows, len(rejected)
