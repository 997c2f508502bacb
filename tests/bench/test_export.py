"""results.csv and navlab bench export: the JSON Lines' trials, flat, with their parameters."""

import csv
import json
import subprocess
import sys

import pytest

from navlab.bench import load_experiment, run_experiment
from navlab.bench.export import export, flatten

EXPERIMENT = {"name": "export-test", "worlds": ["trap"], "planners": ["rrt", "rrt_star"],
              "samplers": ["uniform", "gaussian"], "budget": {"max_iter": 300}, "trials": 3, "seed": 1}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("bench")
    run_experiment(load_experiment(dict(EXPERIMENT)), folder, executor="serial", progress=False, plots=False)
    return folder


def jsonl(folder):
    return [json.loads(line) for line in (folder / "results.jsonl").read_text().splitlines() if line.strip()]


def test_results_csv_holds_exactly_the_jsonl_trials_and_parameters(run):
    rows = jsonl(run)
    with open(run / "results.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [r["trial_id"] for r in table] == [r["trial_id"] for r in rows]
    for row, line in zip(rows, table):
        flat = flatten(row)
        assert set(line) >= set(flat)
        for key, value in flat.items():
            assert line[key] == ("" if value is None else str(value)), key
        # the parameters the planner used, derived ones included, are columns
        assert float(line["params_used.expand_dis"]) == pytest.approx(row["params_used"]["expand_dis"])
        if row["sampler"] == "gaussian":
            assert float(line["params_used.sigma"]) == row["params_used"]["sigma"]
        assert "trace" not in line and "error" not in line


def test_export_converts_any_results_folder_to_csv_and_parquet(run, tmp_path):
    out = export(run, "csv", tmp_path / "again.csv")
    assert out.read_text() == (run / "results.csv").read_text()
    pq = pytest.importorskip("pyarrow.parquet")
    table = pq.read_table(export(run, "parquet", tmp_path / "r.parquet")).to_pylist()
    assert [r["trial_id"] for r in table] == [r["trial_id"] for r in jsonl(run)]
    assert all(r["params_used.max_iter"] == 300 for r in table)


def test_export_on_the_command_line_and_its_bad_input(run, tmp_path):
    cmd = [sys.executable, "-m", "navlab", "bench", "export"]
    done = subprocess.run(cmd + [str(run), "--out", str(tmp_path / "x.csv")], capture_output=True, text=True)
    assert done.returncode == 0 and (tmp_path / "x.csv").is_file()
    for args, message in (([str(tmp_path)], "no results.jsonl"), ([], "Missing argument"),
                          ([str(run), "--format", "xls"], "--format")):
        bad = subprocess.run(cmd + args, capture_output=True, text=True)
        assert bad.returncode == 2 and message in bad.stderr and "Traceback" not in bad.stderr
