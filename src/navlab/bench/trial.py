"""One trial: run a cell's planner with the trial's seed and turn the Result
into a flat, JSON-ready row. Runs in worker processes, so it takes and
returns plain data only."""

from __future__ import annotations

import functools
import os
import platform
import socket
import traceback
from typing import Any, Callable, Dict

import numpy as np

from ..result import Result, _jsonable
from .experiment import OMPL_PREFIX

#: points kept of each cost-vs-iteration trace (log-spaced in iterations)
TRACE_POINTS = 120


@functools.lru_cache(maxsize=None)
def _world(name: str):
    from ..world import load_world

    return load_world(name)


@functools.lru_cache(maxsize=1)
def machine() -> Dict[str, Any]:
    """Where a row was computed."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), cpu)
    except OSError:
        pass
    return {"host": socket.gethostname(), "cpu": cpu, "cores": os.cpu_count(),
            "python": platform.python_version(), "system": platform.platform(terse=True)}


def cell_kwargs(cell: Dict[str, Any], budget: Dict[str, Any]) -> Dict[str, Any]:
    """The planner and sampler settings of a cell, budget included."""
    sampler = cell["sampler"] or {"params": {}}
    return {**cell["params"], **cell["planner"]["params"], **sampler["params"], **budget}


def execute(spec: Dict[str, Any], keep_tree: bool = False) -> Result:
    """Run the trial described by ``spec`` and return navlab's Result."""
    from ..planning import plan
    from .ompl_planners import plan_ompl

    cell = spec["cell"]
    world = _world(cell["world"])
    kwargs = cell_kwargs(cell, spec["budget"])
    name = cell["planner"]["name"]
    if name.startswith(OMPL_PREFIX):
        return plan_ompl(world, name[len(OMPL_PREFIX):], spec["seed"], **kwargs)
    if keep_tree:
        kwargs["keep_tree"] = True
    return plan(world, planner=name, sampler=cell["sampler"]["name"], seed=spec["seed"], **kwargs)


def identity_fields(spec: Dict[str, Any]) -> Dict[str, Any]:
    """What every row says about its trial, whatever became of it."""
    from .. import __version__

    cell = spec["cell"]
    row = {key: spec[key] for key in ("trial_id", "cell_id", "label", "trial", "seed")}
    row.update(world=cell["world"], planner=cell["planner"]["label"],
               sampler=cell["sampler"]["label"] if cell["sampler"] else "-",
               params=_jsonable(cell_kwargs(cell, spec["budget"])), version=__version__, machine=machine())
    return row


def run_trial(spec: Dict[str, Any], runner: Callable[[Dict[str, Any]], Result] = execute) -> Dict[str, Any]:
    """Run one trial with ``runner``; an exception becomes an ``ERROR`` row
    with its traceback."""
    row = identity_fields(spec)
    try:
        row.update(result_fields(runner(spec)))
    except Exception:  # noqa: BLE001 - any failure of one trial is data, not the end of the run
        row.update(error_fields(traceback.format_exc()))
    return row


def error_fields(message: str) -> Dict[str, Any]:
    return {"status": "ERROR", "success": False, "cost": None, "time_s": None, "error": message}


def result_fields(result: Result) -> Dict[str, Any]:
    stats = result.stats
    out = {"status": result.status.name, "success": result.success, "cost": _jsonable(result.cost)
           if result.success else None, "reason": result.reason}
    for key in ("time_s", "iterations", "nodes", "collision_checks", "first_solution_iteration",
                "first_solution_time_s"):
        out[key] = _jsonable(stats.get(key))
    trace = stats.get("cost_trace")
    out["trace"] = compress_trace(np.asarray(trace)) if trace is not None and len(trace) else None
    return out


def compress_trace(trace: np.ndarray, points: int = TRACE_POINTS) -> Dict[str, list]:
    """Best cost after iteration k for log-spaced k (1-based); ``None`` before
    the first solution. Same iterations for every trial of the same budget."""
    n = len(trace)
    its = np.unique(np.round(np.geomspace(1, n, min(points, n))).astype(int))
    costs = trace[its - 1]
    return {"iteration": its.tolist(), "cost": [float(c) if np.isfinite(c) else None for c in costs]}
