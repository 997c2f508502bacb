"""Fuzzing the ``navlab`` command: never a traceback, never an "internal error", the documented exit statuses.

Exit 0 (success), 1 (no path / goal not reached), 2 (bad input: the last line is
``Error: ...``). Most runs use click's CliRunner; two run the real console command
in a subprocess, where a traceback would really reach the terminal.
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner
from hypothesis import example, given
from hypothesis import strategies as st

from navlab.cli import main

from fuzz.strategies import examples, world_documents

SRC = str(Path(__file__).resolve().parents[2] / "src")
NUMBER_TEXT = st.one_of(
    st.floats(-20, 20).map(repr), st.integers(-5, 30).map(str),
    st.sampled_from(["inf", "-inf", "nan", "1e400", "-1e400", "9" * 40, "1e-320", "-0", "0x10", "1_0", "", "abc"]))
PARAM_TEXT = st.one_of(
    st.sampled_from(["max_iter", "expand_dis", "goal_sample_rate", "connect_circle_dist", "batch_size", "sigma",
                     "typo"]).flatmap(lambda k: st.one_of(NUMBER_TEXT, st.sampled_from(
                         [".inf", ".nan", "[1, 2]", "{a: 1}", "null", "'5'", "[", "!!binary aGk="])).map(
                         lambda v: f"{k}={v}")),
    st.text(max_size=12))


def check_cli(result, args=()):
    """The CLI's contract for any input."""
    out = result.output
    assert "Traceback" not in out and "Error: internal error" not in out, (args, out)
    assert result.exit_code in (0, 1, 2), (args, result.exit_code, out, result.exception)
    if result.exit_code == 2:
        last = [line for line in out.split("\n") if line.strip()][-1]
        assert last.startswith("Error: "), (args, out)


def run(args):
    result = CliRunner().invoke(main, args)
    check_cli(result, args)
    return result


@examples(40)
@given(world_documents(), st.lists(PARAM_TEXT, max_size=2), st.sampled_from(["rrt", "rrt_star", "jps", "rrtx"]))
def test_plan_any_world_file_and_params(tmp_path_factory, doc, params, planner):
    path = tmp_path_factory.mktemp("cli") / "world.yaml"
    path.write_text(yaml.safe_dump(doc))
    args = ["plan", str(path), "--planner", planner, "--max-iter", "50", "--json"]
    for p in params:
        args += ["--param", p]
    run(args)


@examples(20)
@given(st.binary(max_size=64))
@example(b"\x89PNG\r\n\x1a\n\xff")
def test_plan_any_bytes_as_world_file(tmp_path_factory, content):
    path = tmp_path_factory.mktemp("cli") / "w.yaml"
    path.write_bytes(content)
    assert run(["plan", str(path)]).exit_code in (1, 2)


MAP = "type octile\nheight 4\nwidth 6\nmap\n......\n.@@@..\n......\n..@...\n"


@examples(40)
@given(st.tuples(NUMBER_TEXT, NUMBER_TEXT, NUMBER_TEXT, NUMBER_TEXT).filter(
    lambda t: not any(v in ("inf", "-inf", "1e400", "-1e400") for v in t)), st.booleans(),
    st.sampled_from(["astar", "jps", "theta_star"]))
def test_grid_plan_any_cells(tmp_path_factory, numbers, in_world, algorithm):
    path = tmp_path_factory.mktemp("cli") / "m.map"
    path.write_text(MAP)
    args = ["grid", "plan", str(path), "--start", *numbers[:2], "--goal", *numbers[2:], "--algorithm", algorithm]
    run(args + (["--world"] if in_world else []))


@examples(10)
@given(st.sampled_from(["inf", "-inf", "1e400"]), st.booleans())
@example("inf", False)
def test_grid_plan_infinite_cells(tmp_path_factory, value, in_world):
    path = tmp_path_factory.mktemp("cli") / "m.map"
    path.write_text(MAP)
    run(["grid", "plan", str(path), "--start", value, "0", "--goal", "1", "1"] + (["--world"] if in_world else []))


@examples(20)
@given(st.tuples(NUMBER_TEXT, NUMBER_TEXT, NUMBER_TEXT))
@example(("1", "1", "inf"))
@example(("nan", "0", "0"))
def test_sim_any_start(start):
    run(["sim", "one_obstacle", "--start", *start, "--max-time", "0.5"])


@pytest.mark.parametrize("args", [
    ["list"], ["--help"], ["--version"], ["plan", "--help"], ["grid", "--help"], ["bench", "--help"],
    ["sim", "--help"], ["ros", "--help"], ["plan"], ["plan", "clutter", "--max-iter", "0"],
    ["plan", "clutter", "--max-time", "nan"], ["plan", "nowhere/world.yaml"], ["plan", "/"], ["plan", ""],
    ["plan", "clutter", "--param", "max_iter=" + "9" * 40], ["plan", "clutter", "--param", "expand_dis=.inf"],
    ["plan", "clutter", "--param", "=3"], ["grid", "plan", "/", "--start", "0", "0", "--goal", "1", "1"],
    ["sim", "one_obstacle", "--dt", "nan"], ["sim", "one_obstacle", "--max-time", "-1"],
])
def test_fixed_awkward_invocations(args):
    run(args)


def real_navlab(args, **kwargs):
    env = {**os.environ, "PYTHONPATH": SRC, "MPLBACKEND": "Agg"}
    env.pop("NAVLAB_DEBUG", None)
    return subprocess.run([sys.executable, "-m", "navlab", *args], capture_output=True, text=True, env=env,
                          timeout=300, **kwargs)


def test_real_command_bad_world_file(tmp_path):
    (tmp_path / "w.yaml").write_bytes(b"start: {a: 1}\nbounds: {x: [0, " + b"9" * 400 + b"], y: [0, 1]}\ngoal: [1, 1]\n")
    proc = real_navlab(["plan", str(tmp_path / "w.yaml")])
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.count("\n") == 1 and "field 'bounds.x[1]'" in proc.stderr, proc.stderr


def test_real_command_ctrl_c_is_one_line(tmp_path):
    """SIGINT during a long plan: "Interrupted.", exit 130, no KeyboardInterrupt traceback."""
    env = {**os.environ, "PYTHONPATH": SRC, "MPLBACKEND": "Agg"}
    env.pop("NAVLAB_DEBUG", None)
    code = ("import sys; from navlab.cli import main; print('ready', flush=True); "
            "sys.argv[0] = 'navlab'; main()")
    proc = subprocess.Popen([sys.executable, "-c", code, "plan", "clutter", "--planner", "rrt_star",
                             "--max-iter", "2000000", "--max-time", "120"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(1.0)  # into the planning loop (the interrupt lands wherever it lands: any point must be clean)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert "Traceback" not in err, err
    assert proc.returncode == 130 and err.strip() == "Interrupted.", (proc.returncode, err)
