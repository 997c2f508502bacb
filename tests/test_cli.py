import json

import pytest
from click.testing import CliRunner

from navlab.cli import main


@pytest.fixture
def run():
    runner = CliRunner()
    return lambda *args: runner.invoke(main, list(args), catch_exceptions=False)


def test_plan_json_has_everything(run):
    res = run("plan", "squarefield", "--planner", "rrt_star", "--sampler", "integration",
              "--max-iter", "400", "--seed", "3", "--param", "expand_dis=1.5", "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.output)
    assert out["status"] == "EXACT" and out["cost"] > 0 and len(out["path"]) >= 2
    assert out["params"]["expand_dis"] == 1.5 and out["params"]["seed"] == 3
    assert out["params"]["weights"]["gaussian"] == 0.3
    assert {"iterations", "nodes", "collision_checks", "time_s", "cost_trace"} <= set(out["stats"])


def test_plan_plot_writes_png(run, tmp_path):
    out = tmp_path / "plan.png"
    res = run("plan", "trap", "--max-iter", "300", "--plot", str(out))
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "plot written" in res.output


def test_plan_world_file(run, tmp_path):
    f = tmp_path / "w.yaml"
    f.write_text("bounds: {x: [0, 5], y: [0, 5]}\nstart: [1, 1]\ngoal: [4, 4]\n")
    res = run("plan", str(f), "--planner", "rrt", "--json")
    assert json.loads(res.output)["status"] == "EXACT"


@pytest.mark.parametrize("args, text", [
    (("plan", "clutr"), "Did you mean 'clutter'"),
    (("plan", "clutter", "--sampler", "gausian"), "Did you mean 'gaussian'"),
    (("plan", "clutter", "--param", "goal_sample_rate=5"), "goal_sample_rate must be a probability"),
    (("plan", "clutter", "--param", "expand_dis"), "expected key=value"),
    (("plan", "missing.yaml"), "no such file"),
])
def test_bad_input_is_one_clear_line(args, text):
    res = CliRunner().invoke(main, list(args))
    assert res.exit_code == 2 and text in res.output and "Traceback" not in res.output


def test_failed_plan_exits_nonzero(run, tmp_path):
    f = tmp_path / "w.yaml"
    f.write_text("bounds: {x: [0, 5], y: [0, 5]}\nstart: [1, 1]\ngoal: [4, 4]\nrobot_radius: 0.5\n"
                 "obstacles: [{type: circle, center: [4, 4], radius: 0.3}]\n")
    res = run("plan", str(f))
    assert res.exit_code == 1 and "INVALID_GOAL" in res.output and "clearance" in res.output


def test_list_shows_everything(run):
    out = run("list").output
    for name in ("rrt_star", "informed_rrt_star", "growth_ratio_rrt", "integration", "boundary",
                 "pythonrobotics", "trap", "goal_sample_rate=0.05"):
        assert name in out


def test_help_explains(run):
    out = run("plan", "--help").output
    assert "--param" in out and "--plot" in out and "seed" in out
