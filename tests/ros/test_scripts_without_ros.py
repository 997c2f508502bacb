"""The node console scripts without the ros2 extra: the same one line as
``navlab ros NODE`` and exit status 2, never a traceback. rclpy is hidden
by an import hook, so this runs (and must pass) with or without ROS."""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from navlab.extras import install_command

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"
SCRIPTS = {name: target for name, target in tomllib.loads(PYPROJECT.read_text())["project"]["scripts"].items()
           if name != "navlab"}

#: an import hook that makes rclpy look uninstalled, then runs each console
#: script's target (module:function, argv) in turn: its exit status and output
WITHOUT_RCLPY = """
import contextlib, importlib, io, json, sys, traceback

class HideRclpy:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] == "rclpy":
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)

sys.meta_path.insert(0, HideRclpy())
runs = []
for target, argv in json.loads(sys.argv[1]):
    module, attr = target.split(":")
    out, err, status = io.StringIO(), io.StringIO(), 0
    sys.argv = list(argv)
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            getattr(importlib.import_module(module), attr)()
        except SystemExit as exc:
            status = exc.code
        except BaseException:
            traceback.print_exc()
            status = "traceback"
    runs.append([status, out.getvalue(), err.getvalue()])
print(json.dumps(runs))
"""


def run_without_rclpy(*calls):
    """[(exit status, stdout, stderr)] of each (target, argv) run with rclpy hidden."""
    proc = subprocess.run([sys.executable, "-c", WITHOUT_RCLPY, json.dumps(calls)], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


@pytest.fixture(scope="module")
def runs():
    """``navlab ros NODE`` and then ``navlab-NODE --ros-args ...`` for every script, and one --help."""
    calls = []
    for script, target in sorted(SCRIPTS.items()):
        node = script[len("navlab-"):].replace("-", "_")
        calls += [("navlab.cli:main", ["navlab", "ros", node]), (target, [script, "--ros-args", "-p", "x:=1"])]
    calls.append((SCRIPTS["navlab-sim"], ["navlab-sim", "--help"]))
    out = run_without_rclpy(*calls)
    return {script: (out[2 * i], out[2 * i + 1]) for i, script in enumerate(sorted(SCRIPTS))}, out[-1]


def test_every_node_has_a_console_script():
    from navlab.ros.launch import NODES

    assert sorted(SCRIPTS) == sorted(f"navlab-{node.replace('_', '-')}" for node in NODES)


@pytest.mark.parametrize("script", sorted(SCRIPTS))
def test_console_scripts_without_rclpy_say_so_in_one_line(runs, script):
    reference, run = runs[0][script]
    for status, out, err in (reference, run):
        assert status == 2, err
        assert "Traceback" not in err and out == ""
    assert run[2] == reference[2]
    (line,) = run[2].splitlines()
    # the command that installs the extra into this copy of navlab (navlab.extras; not 'navlab[ros2]' from PyPI)
    assert re.fullmatch(r"Error: ROS 2 is not installed: " + re.escape(install_command("ros2")) + r" \(.*rclpy.*\)",
                        line)


def test_console_script_help_without_rclpy_still_works(runs):
    status, out, err = runs[1]
    assert status == 0 and "navlab-sim" in out and "ROS 2 is not installed" in out
