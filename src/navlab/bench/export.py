"""Results as flat tables: one row per trial, parameters as columns.

``results.jsonl`` keeps each trial as a nested object (the parameters asked
for, the parameters used, the machine, a convergence trace). Analysis tools
(pandas, R, a spreadsheet) want one flat row per trial; :func:`flatten` gives
it: nested mappings become dotted columns (``params.expand_dis``,
``params_used.connect_circle_dist``, ``swept.sigma``, ``machine.cpu``), lists
(a query's start and goal) become JSON text, and the bulky fields a table has
no use for (the convergence ``trace``, an error's full ``error`` traceback:
its last line stays in ``reason``) are left out.

The CSV is written in two streaming passes over the JSON Lines (columns, then
rows), so a results file of any length is converted in bounded memory.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any, Dict, Iterable, List

from ..atomic import atomic_path
from .experiment import ExperimentError
from .store import read_rows, write_error

#: identity columns first, in this order; every other column follows alphabetically
LEADING = ("trial_id", "cell_id", "label", "world", "planner", "planner_name", "sampler", "trial", "seed", "repeat",
           "query", "status", "success", "cost", "time_s", "cpu_s", "wall_s", "warmup_s", "iterations", "nodes",
           "collision_checks", "first_solution_iteration", "first_solution_time_s", "reason")
#: left out of the flat table (kept in results.jsonl)
DROPPED = ("trace", "error", "tree")
FORMATS = ("csv", "parquet")


def flatten(row: Dict[str, Any], prefix: str = "") -> Dict[str, Any]:
    """One trial as a flat mapping of scalar columns (see the module docstring)."""
    out: Dict[str, Any] = {}
    for key, value in row.items():
        if not prefix and key in DROPPED:
            continue
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(flatten(value, f"{name}."))
        elif isinstance(value, (list, tuple)):
            out[name] = json.dumps(value)
        else:
            out[name] = value
    return out


def columns(rows: Iterable[Dict[str, Any]]) -> List[str]:
    """Every column any row has: identity columns first, then the rest sorted."""
    seen = set()
    for row in rows:
        seen.update(flatten(row))
    return [c for c in LEADING if c in seen] + sorted(seen - set(LEADING))


def write_store_csv(store) -> int:
    """A run folder's trials (its ``ResultStore``'s results.jsonl) as results.csv, the one flat table every
    navlab bench folder has, for pandas, R or a spreadsheet; a file that cannot be written is an
    ExperimentError naming it (:func:`navlab.bench.store.write_error`)."""
    try:
        return write_csv(store.results_path, store.folder / "results.csv")
    except OSError as exc:
        raise write_error(store.folder / "results.csv", exc) from None


def write_csv(results: Path, target: Path) -> int:
    """results.jsonl → CSV (whole or not at all); returns the number of rows written."""
    names = columns(read_rows(results))
    count = 0
    with atomic_path(target) as tmp, open(tmp, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=names, restval="", extrasaction="raise")
        writer.writeheader()
        for row in read_rows(results):
            writer.writerow({k: "" if v is None else v for k, v in flatten(row).items()})
            count += 1
    return count


def write_parquet(results: Path, target: Path) -> int:
    """results.jsonl → Parquet (needs pyarrow, the parquet extra: :func:`navlab.extras.install_command`)."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        from ..extras import install_command

        raise ExperimentError(f"--format parquet needs pyarrow: {install_command('parquet')} (or use --format csv)") \
            from None
    names = columns(read_rows(results))
    table: Dict[str, list] = {n: [] for n in names}
    count = 0
    for row in read_rows(results):
        flat = flatten(row)
        for n in names:
            table[n].append(flat.get(n))
        count += 1
    # mixed-type columns (a number in one row, text in another) become text rather than fail
    arrays = {}
    for n, values in table.items():
        try:
            arrays[n] = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):
            arrays[n] = pa.array([None if v is None else str(v) for v in values])
    with atomic_path(target) as tmp:
        pq.write_table(pa.table(arrays), tmp)
    return count


def export(folder, fmt: str = "csv", out=None) -> Path:
    """Convert a results folder's ``results.jsonl`` to ``results.<fmt>`` (or ``out``)."""
    folder = Path(folder)
    if fmt not in FORMATS:
        raise ExperimentError(f"--format must be one of {', '.join(FORMATS)}, got {fmt!r}")
    results = folder / "results.jsonl"
    if not results.is_file():
        raise ExperimentError(f"{folder}: no results.jsonl there (give the --out folder of a navlab bench run)")
    target = Path(out) if out is not None else folder / f"results.{fmt}"
    (write_csv if fmt == "csv" else write_parquet)(results, target)
    return target

