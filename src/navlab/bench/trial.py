"""One trial: run a cell's planner with the trial's seed and turn the Result
into a flat, JSON-ready row. Runs in worker processes, so it takes and
returns plain data only.

Timing: before a process's first trial of each kind (world, planner,
sampler, settings), the query is warmed (:func:`warm_trial`) and that time is recorded apart
(``warmup_s``), so neither the trial's time nor its ``max_time`` budget pays
for compilation. Each trial records its wall time (``wall_s``) and the CPU
time of the thread that ran it (``cpu_s``), which a busy machine disturbs far
less (time spent waiting for a core is not counted)."""

from __future__ import annotations

import functools
import os
import platform
import socket
import time
import traceback
import warnings
from typing import Any, Callable, Dict, Optional

import numpy as np

from ..angles import HeadingWarning
from ..errors import interrupted_by_ctrl_c
from ..result import Result, _jsonable
from .experiment import OMPL_PREFIX

#: points kept of each cost-vs-iteration trace (log-spaced in iterations)
TRACE_POINTS = 120


@functools.lru_cache(maxsize=None)
def _world(name: str):
    from ..world.sources import load_source

    return load_source(name)


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
    """The planner and sampler settings of a cell, budget included (a grid
    algorithm has no budget: it searches to the end)."""
    from .experiment import routed_params

    name = cell["planner"]["name"]
    sampler = cell["sampler"] or {"params": {}}
    own = routed_params(name, cell["params"], cell["planner"]["params"], sampler.get("name"))
    if _is_grid(name):
        return own
    return {**own, **sampler["params"], **budget}


def trial_world(spec: Dict[str, Any]):
    """The World a trial plans in: a scene or world file, or one query of a map."""
    if spec.get("query"):
        from .maps import map_world

        return map_world(spec["map"], spec["query"])
    return _world(spec["cell"]["world"])


def execute(spec: Dict[str, Any], keep_tree: Optional[bool] = None) -> Result:
    """Run the trial described by ``spec`` and return navlab's Result (with
    its tree when ``keep_tree``, by default ``spec["keep_tree"]``)."""
    from ..planning import plan
    from .ompl_planners import plan_ompl

    cell = spec["cell"]
    world = trial_world(spec)
    kwargs = cell_kwargs(cell, spec["budget"])
    name = cell["planner"]["name"]
    if name.startswith(OMPL_PREFIX):
        return plan_ompl(world, name[len(OMPL_PREFIX):], spec["seed"], **kwargs)
    if _is_grid(name):
        return plan(world, planner=name, sampler=None, seed=spec["seed"], **kwargs)
    if spec.get("keep_tree") if keep_tree is None else keep_tree:
        kwargs["keep_tree"] = True
    return plan(world, planner=name, sampler=cell["sampler"]["name"], seed=spec["seed"], **kwargs)


def warm_trial(spec: Dict[str, Any]) -> float:
    """Warm this process for the trial's kind of query before it is timed; the
    seconds spent (about 0 once this process has run the same kind).

    Tree planners: the cell's own query with a tiny iteration budget, so
    ``navlab.plan`` warms its kernels (:func:`navlab.warmup.warm_up`, a map's
    too) and the world is loaded. Grid planners: the cell's query once, whole
    (there is no budget to shrink), which warms the algorithm's variant. OMPL:
    :func:`navlab.warmup.warm_up`. One kind is a world (all queries of a map
    together), a planner, a sampler and their settings.
    """
    import json

    cell = spec["cell"]
    key = json.dumps({"world": cell["world"], "planner": cell["planner"], "sampler": cell["sampler"],
                      "params": cell["params"]}, sort_keys=True, default=str)
    if key in _WARMED:
        return 0.0
    t0 = time.perf_counter()
    _warm_kind(key, spec)
    return time.perf_counter() - t0


#: kinds of query this process has warmed (a process-lifetime cache, like an lru_cache)
_WARMED: set = set()


def _warm_kind(key: str, spec: Dict[str, Any]) -> None:
    from ..warmup import WARM_ITERATIONS, warm_up

    if key in _WARMED:
        return
    cell = spec["cell"]
    name = cell["planner"]["name"]
    if name.startswith(OMPL_PREFIX):
        warm_up(name)
        trial_world(spec)
    else:
        budget = {} if _is_grid(name) else {"max_iter": WARM_ITERATIONS}
        execute({**spec, "budget": budget, "keep_tree": False})
    _WARMED.add(key)


def _is_grid(planner: str) -> bool:
    from ..grid.planner import GRID_ALGORITHMS
    from ..pose_queries import POSE_PLANNERS

    return planner in GRID_ALGORITHMS or planner in POSE_PLANNERS  # no sampler, no iteration budget


def identity_fields(spec: Dict[str, Any]) -> Dict[str, Any]:
    """What every row says about its trial, whatever became of it."""
    from .. import __version__

    cell = spec["cell"]
    row = {key: spec[key] for key in ("trial_id", "cell_id", "label", "trial", "seed")}
    row.update(world=cell["world"], planner=cell["planner"]["label"], planner_name=cell["planner"]["name"],
               sampler=cell["sampler"]["label"] if cell["sampler"] else "-",
               params=_jsonable(cell_kwargs(cell, spec["budget"])), swept=dict(spec.get("swept") or {}),
               version=__version__, machine=machine())
    if spec.get("repeat"):
        row["repeat"] = spec["repeat"]
    if spec.get("query"):
        q = spec["query"]
        row.update(query=q["index"], start=q["start"], goal=q["goal"], optimum=q.get("optimum"))
    return row


#: what each row's times were measured with, in the row itself (results.jsonl and results.csv)
CLOCKS = ("cpu_s: the trial's thread CPU time (time.thread_time); wall_s: its wall time (time.perf_counter); "
          "time_s: the planner's own wall time (time.perf_counter), inside wall_s; warmup_s: wall time, apart")


def run_trial(spec: Dict[str, Any], runner: Callable[[Dict[str, Any]], Result] = execute,
              warm: Callable[[Dict[str, Any]], float] = warm_trial) -> Dict[str, Any]:
    """Warm up (timed apart), then run one trial with ``runner`` and time it
    (wall and thread CPU time); an exception becomes an ``ERROR`` row with
    its traceback. With ``spec["keep_tree"]`` the row carries the tree under
    ``"tree"`` (numpy arrays: for the example plot, not for results.jsonl)."""
    row = identity_fields(spec)
    try:
        with warnings.catch_warnings():
            # a heading beyond ±2π was noted once when the experiment was read; a trial (in a worker, where a
            # Dask worker printed it raw and PYTHONWARNINGS=error made every trial an ERROR) does not repeat it
            warnings.simplefilter("ignore", HeadingWarning)
            row["warmup_s"] = warm(spec)
            wall0, cpu0 = time.perf_counter(), time.thread_time()
            result = runner(spec)
        row["cpu_s"], row["wall_s"] = time.thread_time() - cpu0, time.perf_counter() - wall0
        row["clocks"] = CLOCKS
        row.update(result_fields(result))
        if row.get("optimum") and row["success"] and row.get("cost") is not None:
            row["vs_optimum"] = row["cost"] / row["optimum"]
        if spec.get("keep_tree") and result.tree is not None and "nodes" in result.tree:
            row["tree"] = {"nodes": np.asarray(result.tree["nodes"]), "parent": np.asarray(result.tree["parent"]),
                           "path": np.asarray(result.path, dtype=float)}
    except Exception as exc:  # noqa: BLE001 - any failure of one trial is data, not the end of the run
        if interrupted_by_ctrl_c(exc):  # a Ctrl-C handed back as a SystemError ends the run, as any Ctrl-C does
            raise KeyboardInterrupt from exc
        row.update(error_fields(traceback.format_exc()))
    return row


def error_fields(message: str) -> Dict[str, Any]:
    """The fields of a trial that raised; ``reason`` is the exception's last line."""
    lines = [line for line in message.strip().splitlines() if line.strip()]
    return {"status": "ERROR", "success": False, "cost": None, "time_s": None, "error": message,
            "reason": lines[-1].strip() if lines else "unknown error"}


def result_fields(result: Result) -> Dict[str, Any]:
    stats = result.stats
    out = {"status": result.status.name, "success": result.success, "cost": _jsonable(result.cost)
           if result.success else None, "reason": result.reason,
           # what the planner actually ran with, derived values included (expand_dis, sigma, ...),
           # as `navlab plan --json` shows them; ``params`` above is what the experiment asked for
           "params_used": {k: _jsonable(v) for k, v in result.params.items() if k not in ("seed", "world")}}
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
