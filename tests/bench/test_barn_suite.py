"""The BARN suite end to end: two shipped worlds through the CLI, resumable, and its bad inputs."""

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from navlab.bench import barn
from navlab.bench.barn_run import Navigator, make_study
from navlab.cli import main

BARN = Path(__file__).resolve().parents[3] / "shared" / "data" / "barn"
pytestmark = pytest.mark.skipif(not BARN.is_dir(), reason="../shared/data/barn is not beside the checkout")


def _run(*args):
    return CliRunner().invoke(main, ["bench", "--suite", "barn", *args, "--executor", "serial", "-q"])


def test_two_worlds_end_to_end_and_resume(tmp_path):
    out = tmp_path / "barn"
    result = _run("--data", str(BARN), "--worlds", "0,36", "--controller", "rpp", "--out", str(out))
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    assert sorted(r["world"] for r in rows) == [0, 36]
    with open(out / "results.csv", newline="") as f:  # the same runs as one flat table
        table = list(csv.DictReader(f))
    assert sorted(r["trial_id"] for r in table) == sorted(r["trial_id"] for r in rows)
    for row in rows:
        assert row["status"] in barn.STATUSES
        # the row's OT is the path file's, by hand: start, cells in metres, goal, at 2 m/s
        cells = np.load(BARN / "path_files" / f"path_{row['world']}.npy")
        pts = np.vstack([(-2, 3), np.column_stack((cells[:, 0] * 0.15 - 4.575, cells[:, 1] * 0.15 + 5.075)),
                         (-2, 13)])
        assert row["ot_s"] == pytest.approx(np.hypot(*np.diff(pts, axis=0).T).sum() / 2.0)
        expected = barn.score(row["success"], row["time_s"], row["ot_s"])
        assert row["score"] == pytest.approx(expected)
        if row["success"]:
            assert 0 < row["score"] <= 0.5
    report = (out / "report.md").read_text()
    assert "move_base DWA, Gazebo (published, same worlds)" in report and "2D kinematic simulation" in report
    assert "| rpp | 2 | 2 |" in report
    summary = json.loads((out / "summary.json").read_text())
    assert summary["published"]["worlds"] == [0, 36]
    # a second navigator on the same folder is another study; resuming the same one runs nothing
    again = _run("--data", str(BARN), "--worlds", "0,36", "--controller", "rpp", "--out", str(out), "--resume")
    assert again.exit_code == 0 and "(0 run now)" in again.output
    assert "time: total " in again.output and "; runs 0.0 s; start-up, compiling kernels" in again.output
    assert again.output.splitlines()[-2].startswith("report: ")  # then the time, as an experiment's run ends
    assert again.output.splitlines()[-1].startswith("time: total ")


def test_any_navlab_planner_as_the_global_planner(tmp_path):
    out = tmp_path / "rrt"
    result = _run("--data", str(BARN), "--worlds", "0", "--controller", "rpp:desired_linear_vel=1.0",
                  "--planner", "rrt", "--out", str(out))
    assert result.exit_code == 0, result.output
    row = json.loads((out / "results.jsonl").read_text().splitlines()[0])
    assert row["status"] in barn.STATUSES and row["navigator"]["planner"] == "rrt"


@pytest.mark.parametrize("args, words", [
    (["--data", "/nonexistent"], "not a folder"),
    (["--data", str(BARN), "--worlds", "1"], "no world file for 1"),
    (["--data", str(BARN), "--controller", "nonesuch"], "unknown controller 'nonesuch'"),
    (["--data", str(BARN), "--controller", "rpp:lookahead_dist=-1"], "lookahead_dist must be > 0"),
    (["--data", str(BARN), "--controller", "rpp", "--controller", "rpp"], "named twice"),
    # settings only a run can judge are judged on the first world before any trial (they failed every trial)
    (["--data", str(BARN), "--worlds", "0", "--controller", "rpp:inflation_radius=0.1"],
     "inflation_radius = 0.1 m is below the footprint's inscribed radius"),
    (["--data", str(BARN), "--worlds", "0", "--controller", "potential_field"], "commands sideways motion"),
    (["--data", str(BARN), "--worlds", "0", "--controller", "rpp", "--planner", "hybrid_astar"],
     "cannot follow a path of poses"),
    ([], "needs --data"),
])
def test_bad_input_is_one_line(args, words, tmp_path):
    result = _run(*args, "--out", str(tmp_path / "x"))
    assert result.exit_code == 2
    assert words in result.output
    assert not (tmp_path / "x" / "results.jsonl").exists()


def test_a_world_without_its_path_file(tmp_path):
    data = tmp_path / "BARN"
    (data / "path_files").mkdir(parents=True)
    shutil.copy(BARN / "world_0.world", data / "world_0.world")
    shutil.copy(BARN / "world_36.world", data / "world_36.world")
    shutil.copy(BARN / "path_files" / "path_36.npy", data / "path_files" / "path_36.npy")
    refused = _run("--data", str(data), "--controller", "rpp", "--out", str(tmp_path / "a"))
    assert refused.exit_code == 2 and "no path file" in refused.output and "world(s) 0" in refused.output
    ran = _run("--data", str(data), "--worlds", "0", "--controller", "rpp", "--straight-line",
               "--out", str(tmp_path / "b"))
    assert ran.exit_code == 0, ran.output
    row = json.loads((tmp_path / "b" / "results.jsonl").read_text().splitlines()[0])
    assert row["ot_s"] == pytest.approx(5.0)


def test_a_noisy_laser_makes_the_runs_of_a_world_differ_and_is_recorded(tmp_path):
    """--lidar rplidar_a1: the runs of one world get different scans (their seeds), as the challenge's
    ten Gazebo runs per world do; the study and its rows say which laser, and an exact study's folder is
    another study (its fingerprint), while an exact study's fingerprint is what it was before the option."""
    out = tmp_path / "noisy"
    result = _run("--data", str(BARN), "--worlds", "0", "--controller", "rpp", "--lidar", "rplidar_a1",
                  "--trials", "2", "--out", str(out), "--no-plots")
    assert result.exit_code == 0, result.output
    rows = [json.loads(line) for line in (out / "results.jsonl").read_text().splitlines()]
    assert len(rows) == 2 and rows[0]["seed"] != rows[1]["seed"]
    # different scans drive different trajectories: the runs' distances differ
    assert rows[0]["distance_m"] != rows[1]["distance_m"]
    report = (out / "report.md").read_text()
    assert "Laser: rplidar_a1" in report and "a noisy LiDAR" in report and "noise-free" not in report
    assert "a noisy LiDAR" in result.output
    exact = make_study(BARN, "0", [Navigator("rpp")])
    noisy = make_study(BARN, "0", [Navigator("rpp")], lidar="rplidar_a1")
    assert "lidar" not in exact.to_dict() and exact.fingerprint() != noisy.fingerprint()
    assert all(spec["lidar"] == "rplidar_a1" for spec in noisy.trial_specs())
    typo = CliRunner().invoke(main, ["bench", "--suite", "barnn"])
    assert typo.exit_code == 2 and "Did you mean 'barn'?" in typo.output
    bad = _run("--data", str(BARN), "--lidar", "sick_lms")
    assert bad.exit_code == 2 and "sick_lms" in bad.output
    elsewhere = CliRunner().invoke(main, ["bench", "--world", "trap", "--lidar", "rplidar_a1"])
    assert elsewhere.exit_code == 2 and "go with --suite barn" in elsewhere.output


def test_the_per_world_plot_holds_a_long_navigator_label_without_a_warning(tmp_path):
    """(a tuned rpp's label, 120 characters, made tight_layout print a UserWarning on stderr: newcomer, session 23)"""
    import types
    import warnings

    from PIL import Image

    from navlab.bench.barn_report import _plot

    label = "rpp(" + ",".join(f"setting_{k}=1.5" for k in range(9)) + ")"
    summary = {"navigators": {label: {"per_world": {0: {"score": 0.4, "success": 1.0},
                                                    36: {"score": 0.2, "success": 0.5}}}}, "published": None}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        name = _plot(types.SimpleNamespace(worlds=[0, 36]), summary, tmp_path)
    width, height = Image.open(tmp_path / name).size
    assert width > 1.5 * height  # the legend beside the axes, whole


def test_a_ctrl_c_in_the_report_says_every_run_is_kept(tmp_path, monkeypatch):
    """BARN's suite caught a bare KeyboardInterrupt around its runs only: a Ctrl-C while its report was
    written went up as a traceback (review, session 30). Now it is exit 130 naming every run as kept."""
    import navlab.bench.barn_report as barn_report

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(barn_report, "write_barn_report", interrupted)
    out = tmp_path / "barn"
    result = _run("--data", str(BARN), "--worlds", "0", "--controller", "rpp", "--out", str(out))
    assert result.exit_code == 130, result.output
    assert f"interrupted: 1 of 1 runs are kept in {out}, every one; the report is not complete" in result.output
    assert "Traceback" not in result.output and len((out / "results.jsonl").read_text().splitlines()) == 1
