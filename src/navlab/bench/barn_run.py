"""The BARN suite: every navigator on every BARN world, N runs each, judged by the protocol.

A *navigator* is a controller (``dwa_barn``, ``dwa``, ``mppi``, ``rpp``, any
registered one) with its settings, driving the ``jackal`` robot behind a
global planner (default: cost-weighted A* on the navigator's costmap). Each
run is one simulation from :data:`~navlab.bench.barn.START` to
:data:`~navlab.bench.barn.GOAL`, judged by :func:`~navlab.bench.barn.judge`;
its row gives the world, status (succeeded / collided / timeout), AT, OT and
the score. Runs go through the bench's executors (process pool, Dask) and
:class:`~navlab.bench.store.ResultStore` (resumable; a killed run leaves no
stale lock). Runs of the same navigator on the same world differ only by
their seed (sensor noise, MPPI's samples).

This is a 2D kinematic simulation of a Jackal's footprint in the worlds'
cylinders, not Gazebo's physics: no wheel slip, no laser at 0.065 m off
centre, no move_base timing; see docs/navigation.md.
"""

from __future__ import annotations

import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Tuple

from ..wording import counted
from . import barn
from .experiment import ExperimentError, content_digest, stable_hash, trial_seed

#: [s] simulated beyond the time limit, so the clock (which starts after the first 0.1 m) can run its 100 s
SLACK_S = 20.0
#: [s] the simulator's step (the challenge's move_base runs its controller at 20 Hz)
DT = 0.05


@dataclass(frozen=True)
class Navigator:
    """A controller with its settings (and optionally a navlab global planner)."""

    controller: str
    params: Dict[str, Any] = field(default_factory=dict)
    planner: Optional[str] = None

    @property
    def label(self) -> str:
        extra = ",".join(f"{k}={v}" for k, v in sorted(self.params.items()))
        return self.controller + (f"({extra})" if extra else "") + (f"+{self.planner}" if self.planner else "")

    def to_dict(self) -> Dict[str, Any]:
        return {"controller": self.controller, "params": dict(self.params), "planner": self.planner}


@dataclass
class BarnStudy:
    """What one ``navlab bench --suite barn`` run measures."""

    data: Path
    worlds: List[int]
    navigators: List[Navigator]
    runs: int = 1
    seed: int = 0
    name: str = "barn"
    optimal_times: Dict[int, float] = field(default_factory=dict)
    straight_line: bool = False
    #: the Jackal's sensors: "exact", or "rplidar_a1" (noisy laser, wheels and compass: runs differ by seed)
    lidar: str = "exact"

    def to_dict(self) -> Dict[str, Any]:
        out = {"name": self.name, "suite": "barn", "data": str(self.data), "worlds": list(self.worlds),
               "navigators": [n.to_dict() for n in self.navigators], "runs": self.runs, "seed": self.seed,
               "straight_line": self.straight_line}
        if self.lidar != "exact":  # named only when not the default, so folders made before it still resume
            out["lidar"] = self.lidar
        return out

    def fingerprint(self) -> str:
        """Identity of the results: the runs count and world list are left out (they extend a result set)."""
        core = {k: v for k, v in self.to_dict().items() if k not in ("runs", "worlds", "data")}
        return stable_hash(core)

    def fingerprints(self) -> Tuple[str, str]:
        """The identities a folder of this study may hold (one: a BARN study's has not changed)."""
        return self.fingerprint(), self.fingerprint()

    def world_contents(self) -> Dict[str, str]:
        """A digest of each world file by world, compared on resume as an experiment's are
        (:meth:`~navlab.bench.experiment.Experiment.world_contents`)."""
        return {f"world_{w}": content_digest((self.data / f"world_{w}.world").read_bytes()) for w in self.worlds}

    def trial_specs(self) -> List[Dict[str, Any]]:
        specs = []
        for nav in self.navigators:
            cid = stable_hash(nav.to_dict())[:12]
            for world in self.worlds:
                for run in range(self.runs):
                    specs.append({"trial_id": f"{cid}-w{world:03d}-{run:03d}", "cell_id": cid, "trial": run,
                                  "world_index": world, "world_file": str(self.data / f"world_{world}.world"),
                                  "navigator": nav.to_dict(), "label": nav.label,
                                  "optimal_time": self.optimal_times[world], "lidar": self.lidar,
                                  "seed": trial_seed(self.seed, f"{cid}-{world}", run)})
        return specs

    def noise_specs(self) -> List[Dict[str, Any]]:
        return []


#: the lasers a BARN study can give the Jackal (see :mod:`navlab.sensors.lidar`)
BARN_LIDARS = ("exact", "rplidar_a1")


def make_study(data, worlds: Optional[str], navigators: Iterable[Navigator], runs: int = 1, seed: int = 0,
               straight_line: bool = False, lidar: str = "exact") -> BarnStudy:
    """A study over the worlds of ``data`` (see :func:`navlab.bench.barn.find_worlds`).

    ``lidar`` ``"rplidar_a1"`` gives the Jackal noisy sensors (the laser's
    datasheet noise, 2 % wheel-speed noise, 1 % slip, a compass; see
    :func:`navlab.sim.runner.simulate`), so the runs of one world differ by
    their seed, as the challenge's Gazebo runs do.

    Raises
    ------
    ExperimentError
        No such folder or worlds; worlds without path files (named) unless
        ``straight_line`` (then their OT is the straight line's 5 s).
    """
    if lidar not in BARN_LIDARS:
        raise ExperimentError(f"lidar '{lidar}': the BARN suite's Jackal has {' or '.join(BARN_LIDARS)}")
    found = barn.find_worlds(data)
    chosen = barn.select_worlds(worlds, list(found))
    missing = [w for w in chosen if found[w][1] is None]
    if missing and not straight_line:
        raise ExperimentError(f"--data {data}: no path file (path_files/path_N.npy) for world(s) "
                              f"{barn._ranges(missing)}: the score needs its optimal time; run the rest with "
                              "--worlds, or pass --straight-line to use the 10 m straight line (OT 5 s) for them")
    optimal = {w: barn.optimal_time(found[w][1]) if found[w][1] is not None else barn.optimal_time(None)
               for w in chosen}
    navigators = list(navigators)
    if not navigators:
        raise ExperimentError("the BARN suite needs at least one --controller")
    labels = [n.label for n in navigators]
    if len(set(labels)) != len(labels):
        raise ExperimentError(f"a navigator is named twice: {', '.join(labels)}")
    return BarnStudy(Path(data), chosen, navigators, runs, seed, optimal_times=optimal, straight_line=straight_line,
                     lidar=lidar)


def check_navigator(nav: Navigator, world_file: Optional[str] = None) -> None:
    """Refuse a navigator that cannot drive the Jackal (unknown controller, bad settings) before any run.

    With ``world_file`` the navigator is also set up there as a run would be, for one step: settings
    that only the simulation can judge (an inflation radius below the padded footprint's inscribed
    radius, a planner the controller cannot use, ...) are one line here rather than a failed study."""
    from ..control import make_controller

    make_controller(nav.controller, **nav.params)
    if nav.planner is not None:
        from ..queries import planner_names
        from ..registry import UnknownNameError, suggest

        if nav.planner not in planner_names():
            raise UnknownNameError(f"unknown planner {nav.planner!r}; valid: {', '.join(planner_names())}."
                                   + suggest(nav.planner, planner_names()))
    if world_file is None:
        return
    from ..sim.runner import NoPathError, simulate

    try:
        simulate(_world(world_file), robot="jackal", controller=nav.controller, start=barn.START, goal=barn.GOAL,
                 planner=nav.planner, lidar="exact", controller_params=dict(nav.params), dt=DT, max_time=DT)
    except NoPathError:
        pass  # an answer about that world, not about the settings
    except ValueError as exc:
        raise ExperimentError(f"navigator {nav.label}: {exc}") from None


_WORLDS: Dict[str, Any] = {}


def _world(path: str):
    """A BARN world, read once per worker process."""
    if path not in _WORLDS:
        from ..world.sdf import read_sdf

        _WORLDS[path] = read_sdf(path, start=barn.START[:2], goal=barn.GOAL)
    return _WORLDS[path]


def run_barn_trial(spec: Dict[str, Any]) -> Dict[str, Any]:
    """One BARN run (a worker's job): simulate, judge, and return the row."""
    row = {k: spec[k] for k in ("trial_id", "cell_id", "trial", "label", "seed")}
    row.update(world=spec["world_index"], navigator=spec["navigator"], ot_s=spec["optimal_time"])
    wall0 = time.perf_counter()
    try:
        from ..sim.runner import NoPathError, simulate

        nav = spec["navigator"]
        params = dict(nav["params"])
        try:
            result, _, sim = simulate(_world(spec["world_file"]), robot="jackal", controller=nav["controller"],
                                      start=barn.START, goal=barn.GOAL, planner=nav["planner"],
                                      lidar=spec.get("lidar", "exact"), controller_params=params, dt=DT,
                                      max_time=barn.TIME_LIMIT + SLACK_S, seed=spec["seed"])
        except NoPathError as exc:
            row.update(status="timeout", time_s=0.0, score=0.0, success=False, reason=f"no global path: {exc}",
                       wall_s=time.perf_counter() - wall0)
            return row
        collided = result.t[-1] if result.status.name == "COLLIDED" else None
        run = barn.judge(result.t, result.true_poses, collided)
        row.update(status=run.status, time_s=run.time_s, success=run.succeeded,
                   score=barn.score(run.succeeded, run.time_s, spec["optimal_time"]),
                   sim_status=result.status.name, reason=result.reason, distance_m=result.distance,
                   sim_time_s=result.time_s, wall_s=time.perf_counter() - wall0)
    except Exception:  # noqa: BLE001 - one failed run is data, not the end of the study
        message = traceback.format_exc()
        row.update(status="ERROR", success=False, time_s=None, score=None, error=message,
                   reason=message.strip().splitlines()[-1], wall_s=time.perf_counter() - wall0)
    return row


def summarize(study: BarnStudy, rows: List[Dict[str, Any]]) -> Dict[str, Any]:
    """The challenge's five means per navigator (per world first, then over worlds) and per-world figures."""
    out: Dict[str, Any] = {"navigators": {}, "published": published_baseline(study)}
    for nav in study.navigators:
        mine = [r for r in rows if r["label"] == nav.label and r["status"] in barn.STATUSES]
        runs = [barn.BarnRun(r["world"], r["status"], r["time_s"]) for r in mine]
        means = barn.challenge_means(runs, study.optimal_times) if runs else {}
        per_world: Dict[int, Dict[str, float]] = {}
        for r in mine:
            w = per_world.setdefault(r["world"], {"runs": 0, "success": 0.0, "score": 0.0})
            w["runs"] += 1
            w["success"] += r["success"]
            w["score"] += r["score"]
        for w in per_world.values():
            w["success"] /= w["runs"]
            w["score"] /= w["runs"]
        errors = sum(r["status"] == "ERROR" for r in rows if r["label"] == nav.label)
        out["navigators"][nav.label] = {"means": means, "per_world": per_world, "errors": errors,
                                        "wall_s": sum(r.get("wall_s") or 0.0 for r in mine)}
    return out


def published_baseline(study: BarnStudy) -> Optional[Dict[str, Any]]:
    """The challenge's move_base DWA runs (``dwa_out.txt`` beside the data, or in ../shared/data/barn)
    on the worlds of this study that it covers, with the score recomputed from the path files."""
    candidates = [study.data / "dwa_out.txt", study.data.parent / "dwa_out.txt"] + \
        [p / "shared" / "data" / "barn" / "dwa_out.txt" for p in Path(__file__).resolve().parents]
    for path in candidates:
        if path.is_file():
            runs = [r for r in barn.read_runs(path) if r.world in study.optimal_times]
            if not runs:
                return None
            return {"file": str(path), "worlds": sorted({r.world for r in runs}),
                    "means": barn.challenge_means(runs, study.optimal_times)}
    return None


def run_barn(study: BarnStudy, out, executor: str = "process", jobs: Optional[int] = None,
             scheduler: Optional[str] = None, resume: bool = False, overwrite: bool = False,
             progress: bool = True, plots: bool = True):
    """Run every unfinished BARN trial, store the rows, write summary.json, report.md and the figure."""
    import json

    from ..atomic import write_text_atomic
    from .executors import EXECUTORS, check_executor
    from .runner import _progress, stopped, stops_at_ctrl_c
    from .store import ResultStore

    for nav in study.navigators:
        check_navigator(nav, str(study.data / f"world_{study.worlds[0]}.world") if study.worlds else None)
    check_executor(executor, scheduler)
    run_trials = EXECUTORS.get(executor)
    t0 = time.perf_counter()
    with ResultStore(out, study, resume=resume, overwrite=overwrite) as store:
        specs = study.trial_specs()
        done = store.finished()
        todo = [s for s in specs if s["trial_id"] not in done]

        def stop():  # what a Ctrl-C raises, in the runs and in the report alike
            return stopped(store, specs, unit="runs")

        if todo:
            # ("2 worlds × 2 navigators × 1 runs": newcomer, session 30)
            bar = _progress(len(todo), f"BARN: {counted(len(study.worlds), 'world')} × "
                            f"{counted(len(study.navigators), 'navigator')} × {counted(study.runs, 'run')}", progress)
            # (a bare KeyboardInterrupt caught here missed the SystemError form of a Ctrl-C, and the report's
            # Ctrl-C went up as a traceback: review, session 30)
            with stops_at_ctrl_c(stop, bar) as trials:
                for row in trials.track(run_trials(todo, jobs=jobs, scheduler=scheduler, trial=run_barn_trial)):
                    store.append(row)
                    bar.update(1)
        rows = store.current_rows(specs)
        elapsed = time.perf_counter() - t0
        summary = summarize(study, rows)
        summary["elapsed_s"] = elapsed
        summary["ran"] = len(todo)
        from .barn_report import write_barn_report
        from .export import write_store_csv

        with stops_at_ctrl_c(stop):
            write_text_atomic(store.folder / "summary.json", json.dumps(summary, indent=1, default=str))
            write_barn_report(study, rows, summary, store.folder, plots=plots)
            write_store_csv(store)
    return store.folder, rows, summary


__all__ = ["BarnStudy", "Navigator", "make_study", "run_barn", "run_barn_trial", "summarize"]
