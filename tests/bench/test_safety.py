"""The output folder made safe, optional dependencies checked before anything
runs, sweeps as cells, failures that explain themselves, warm-up apart."""

import errno
import json
import os
import re
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import pytest
from click.testing import CliRunner

from navlab.bench import ExperimentError, load_experiment, run_experiment
from navlab.bench.store import FolderLock, read_rows
from navlab.extras import install_command
from navlab.cli import main

TINY = {"name": "tiny", "worlds": ["trap"], "planners": ["rrt_star"], "samplers": ["uniform"],
        "budget": {"max_iter": 120}, "trials": 2, "seed": 3}
SRC = str(Path(__file__).resolve().parents[2] / "src")


def navlab(*args, cwd=None, **kw):
    """``navlab`` in a fresh process, as a user runs it."""
    env = {**os.environ, "PYTHONPATH": SRC, "MPLBACKEND": "Agg"}
    return subprocess.Popen([sys.executable, "-m", "navlab", *args], cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kw)


def test_two_runs_on_one_folder_leave_no_duplicate_trials(tmp_path):
    out = tmp_path / "o"
    args = ["bench", "--world", "trap", "--planner", "rrt_star", "--sampler", "uniform", "--sampler", "gaussian",
            "--trials", "6", "--max-iter", "200", "--out", str(out), "--no-plots", "-q", "-j", "1"]
    procs = [navlab(*args), navlab(*args)]
    results = [p.communicate(timeout=300) + (p.returncode,) for p in procs]
    codes = sorted(r[2] for r in results)
    assert codes == [0, 2], results
    refused = next(r for r in results if r[2] == 2)[1]
    # refused while the other holds the lock, or after it ended (then it holds results already)
    assert ("in use by another navlab bench run (pid" in refused or "--resume" in refused), refused
    assert len(refused.strip().splitlines()) == 1
    ids = [r["trial_id"] for r in read_rows(out / "results.jsonl")]
    assert len(ids) == 12 + 4 and not [t for t, n in Counter(ids).items() if n > 1]


def hold_lock(folder):
    """Another process holding the folder's lock (a record lock is per process)."""
    import subprocess
    import sys

    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from navlab.bench.store import FolderLock; "
                               f"FolderLock(__import__('pathlib').Path({str(folder)!r})); print('held', flush=True); "
                               "sys.stdin.read()"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "held"
    return holder


def test_a_held_folder_is_refused_naming_the_holder(tmp_path):
    holder = hold_lock(tmp_path)
    try:
        for flags in ({}, {"resume": True}, {"overwrite": True}):
            with pytest.raises(ExperimentError, match=f"in use by another navlab bench run \\(pid {holder.pid}\\)"):
                run_experiment(load_experiment(TINY), tmp_path, executor="serial", progress=False, **flags)
    finally:
        holder.communicate("")
    assert run_experiment(load_experiment(TINY), tmp_path, executor="serial", progress=False, plots=False).ran == 4


def test_resume_and_overwrite_together_are_refused(tmp_path):
    res = CliRunner().invoke(main, ["bench", "--suite", "smoke", "--resume", "--overwrite", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "give one" in res.output and not list(tmp_path.iterdir())
    with pytest.raises(ExperimentError, match="give one"):
        run_experiment(load_experiment(TINY), tmp_path, resume=True, overwrite=True)


@pytest.mark.parametrize("name", ["../../x", "a/b", "..", "a\\b", ""])
def test_experiment_names_are_plain_file_names(name):
    with pytest.raises(ExperimentError, match="plain file name"):
        load_experiment({**TINY, "name": name})


def test_a_full_disk_is_one_line_naming_the_file_and_keeps_what_was_written(tmp_path, monkeypatch):
    import navlab.bench.store as store

    real_fsync, calls = os.fsync, []

    def fsync(fd):
        calls.append(fd)
        if len(calls) > 3:
            raise OSError(errno.ENOSPC, "No space left on device")
        real_fsync(fd)

    monkeypatch.setattr(store.os, "fsync", fsync)
    path = tmp_path / "exp.yaml"
    path.write_text(json.dumps({**TINY, "trials": 4}))
    res = CliRunner().invoke(main, ["bench", str(path), "--out", str(tmp_path / "o"), "--executor", "serial", "-q"])
    assert res.exit_code == 2
    assert res.output.strip() == f"Error: cannot write '{tmp_path / 'o' / 'results.jsonl'}': No space left on device"
    monkeypatch.setattr(store.os, "fsync", real_fsync)
    kept = list(read_rows(tmp_path / "o" / "results.jsonl"))
    assert len(kept) >= 2  # the rows before the failure are intact
    again = run_experiment(load_experiment(path), tmp_path / "o", executor="serial", resume=True, progress=False,
                           plots=False)
    ids = [r["trial_id"] for r in read_rows(tmp_path / "o" / "results.jsonl")]
    assert len(again.rows) == 4 and len(ids) == len(set(ids)) == 4 + 2  # and two noise repeats


def test_experiment_json_is_replaced_atomically(tmp_path, monkeypatch):
    import navlab.bench.store as store

    written = []
    real = store.write_text_atomic
    monkeypatch.setattr(store, "write_text_atomic", lambda p, t: (written.append(Path(p).name), real(p, t)))
    run_experiment(load_experiment(TINY), tmp_path, executor="serial", progress=False, plots=False)
    assert written == ["experiment.json"]
    assert json.loads((tmp_path / "experiment.json").read_text())["experiment"]["name"] == "tiny"


def test_ctrl_c_exits_130_keeping_trials_and_printing_the_resume_command(tmp_path):
    out = tmp_path / "o"
    proc = navlab("bench", "--world", "trap", "--planner", "rrt_star", "--trials", "400", "--max-iter", "3000",
                  "--out", str(out), "--no-plots", "-q", "-j", "1")
    results = out / "results.jsonl"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (results.exists() and results.read_text().count("\n") >= 2):
        time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    kept = len(list(read_rows(results)))  # the noise repeats run last: none yet
    # the progress bar counts the noise repeats too (one per cell): the message says both counts
    assert re.search(rf"interrupted: {kept} of 400 trials and 0 of \d+ noise repeats are kept in {re.escape(str(out))}",
                     err), err
    assert "navlab bench --world trap" in err and err.strip().endswith("--resume")
    assert "Traceback" not in err


def test_missing_ompl_is_one_error_before_anything_runs(tmp_path, monkeypatch):
    import navlab.bench.ompl_planners as ompl_planners

    monkeypatch.setattr(ompl_planners, "ompl_available", lambda: False)
    with pytest.raises(ExperimentError, match=r"'ompl:RRTstar' needs OMPL.*" + re.escape(install_command("ompl"))):
        load_experiment({**TINY, "planners": ["rrt_star", "ompl:RRTstar"]})


def test_missing_dask_and_an_unreachable_scheduler_are_one_line_exit_2(tmp_path, monkeypatch):
    import navlab.bench.executors as executors

    monkeypatch.setitem(sys.modules, "distributed", None)  # import fails as if not installed
    args = ["bench", "--suite", "smoke", "--executor", "dask", "--out", str(tmp_path / "a")]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 2 and res.output.strip() == (
        "Error: the dask executor needs Dask, which is not installed: " + install_command("dask"))
    monkeypatch.undo()
    pytest.importorskip("distributed")
    monkeypatch.setattr(executors, "DASK_CONNECT_TIMEOUT", 1)
    res = CliRunner().invoke(main, args[:-1] + [str(tmp_path / "b"), "--scheduler", "tcp://127.0.0.1:9"])
    assert res.exit_code == 2, res.output
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: --scheduler tcp://127.0.0.1:9: not a Dask scheduler, or not reachable")
    assert not (tmp_path / "b" / "results.jsonl").exists()


def test_a_sweep_is_one_cell_per_value_everywhere(tmp_path):
    exp = load_experiment({**TINY, "planners": ["rrt"], "grid": {"expand_dis": [0.3, 3.0]}, "trials": 3})
    run = run_experiment(exp, tmp_path, executor="serial", progress=False)
    cells = json.loads((tmp_path / "summary.json").read_text())["cells"]
    assert [(c["swept"], c["trials"]) for c in cells] == [({"expand_dis": 0.3}, 3), ({"expand_dis": 3.0}, 3)]
    assert run.summary["swept"] == ["expand_dis"]
    assert len(run.summary["comparisons"]["trap"]["cost"]) == 1  # the two values compared with each other
    md = (tmp_path / "report.md").read_text()
    assert "| world | planner | sampler | expand_dis | success |" in md
    assert "rrt / uniform / expand_dis=0.3" in md and "rrt / uniform / expand_dis=3.0" in md
    assert "in 2 cells, 3 per cell" in md


def test_failures_list_statuses_and_reasons_per_cell(tmp_path):
    world = tmp_path / "blocked.yaml"
    world.write_text("name: blocked\nbounds: {x: [0, 10], y: [0, 10]}\nstart: [1, 1]\ngoal: [9, 9]\n"
                     "obstacles:\n  - {type: circle, center: [1, 1], radius: 0.5}\n")
    run = run_experiment(load_experiment({**TINY, "worlds": [str(world), "trap"]}), tmp_path / "o",
                         executor="serial", progress=False, plots=False)
    blocked = next(c for c in run.summary["cells"] if c["world"] == str(world))
    assert blocked["statuses"] == {"INVALID_START": 2}
    assert blocked["reasons"][0][0].startswith("INVALID_START: ") and blocked["reasons"][0][1] == 2
    md = (tmp_path / "o" / "report.md").read_text()
    assert "Trials that did not succeed" in md and "INVALID_START 2" in md and blocked["reasons"][0][0] in md


def test_an_error_rows_reason_is_the_exceptions_last_line():
    from bench_helpers import raising_trial

    spec = next(s for s in load_experiment({**TINY, "trials": 3}).trial_specs() if s["trial_id"].endswith("-0002"))
    row = raising_trial(spec)
    assert row["status"] == "ERROR" and row["reason"] == "RuntimeError: planner blew up"


def test_relative_world_paths_are_read_from_the_experiment_files_folder(tmp_path):
    study = tmp_path / "study"
    study.mkdir()
    (study / "room.yaml").write_text("name: room\nbounds: {x: [0, 5], y: [0, 5]}\nstart: [1, 1]\ngoal: [4, 4]\n"
                                     "obstacles: []\n")
    (study / "exp.yaml").write_text("worlds: [room.yaml, trap]\nplanners: [rrt_star]\nbudget: {max_iter: 100}\n"
                                    "trials: 1\n")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    proc = navlab("bench", "../study/exp.yaml", "--executor", "serial", "--no-plots", "-q", cwd=elsewhere)
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    rows = list(read_rows(elsewhere / "bench-results" / "exp" / "results.jsonl"))
    assert {r["world"] for r in rows} == {str(Path("../study") / "room.yaml"), "trap"}


def test_each_trial_is_timed_apart_from_the_warm_up(tmp_path, monkeypatch):
    import navlab.bench.trial as trial

    monkeypatch.setattr(trial, "_WARMED", set())  # as in a fresh worker
    run = run_experiment(load_experiment({**TINY, "samplers": ["uniform", "gaussian"]}), tmp_path,
                         executor="serial", progress=False, plots=False)
    rows = run.rows
    assert all(r["cpu_s"] > 0 and r["wall_s"] > 0 and "warmup_s" in r for r in rows)
    # each row says which clock each time is (issue 19), and the planner's own time lies inside the trial's
    assert all("cpu_s: the trial's thread CPU time" in r["clocks"] and "time_s: the planner's own wall time"
               in r["clocks"] and r["time_s"] <= r["wall_s"] for r in rows)
    # one warm-up per kind of query in this process, before its first trial, then none
    assert sorted((r["sampler"], r["trial"]) for r in rows if r["warmup_s"] > 0) == [("gaussian", 0), ("uniform", 0)]
    assert run.summary["warmup_s"] == pytest.approx(sum(r["warmup_s"] for r in rows), abs=1e-9)


def test_warm_up_covers_tree_grid_and_ompl_planners():
    from navlab.warmup import warm_up

    for planner in ("rrt_star", "jps"):
        assert warm_up(planner, "integration") >= 0.0
    if pytest.importorskip("ompl"):
        assert warm_up("ompl:RRTstar") >= 0.0


def test_a_time_budget_starts_after_the_warm_up(tmp_path):
    # a fresh process: the first trial must not spend its 0.1 s budget compiling
    proc = navlab("bench", "--world", "trap", "--planner", "rrt_star", "--max-time", "0.1", "--max-iter", "100000",
                  "--trials", "4", "--executor", "serial", "--out", str(tmp_path), "--no-plots", "-q")
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    rows = list(read_rows(tmp_path / "results.jsonl"))
    assert all(r["success"] for r in rows), [(r["status"], r["iterations"]) for r in rows]


def test_a_results_folder_that_cannot_be_made_is_named_as_such(tmp_path):
    """(it read "cannot write '/proc/nope'", a file's write: newcomer, session 31)"""
    blocker = tmp_path / "file"
    blocker.write_text("")
    res = CliRunner().invoke(main, ["bench", "--suite", "smoke", "--out", str(blocker / "out"), "-q"])
    assert res.exit_code == 2
    assert res.output.strip().startswith(f"Error: cannot make the results folder '{blocker / 'out'}': ")
