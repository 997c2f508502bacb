"""The node console scripts without the ros2 extra: the same one line as
``navlab ros NODE`` and exit status 2, never a traceback. rclpy is hidden
by an import hook, so this runs (and must pass) with or without ROS."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = pytest.importorskip("tomli")

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"
SCRIPTS = {name: target for name, target in tomllib.loads(PYPROJECT.read_text())["project"]["scripts"].items()
           if name != "navlab"}

#: an import hook that makes rclpy look uninstalled, then runs a console script's target
WITHOUT_RCLPY = """
import importlib, sys

class HideRclpy:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] == "rclpy":
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)

sys.meta_path.insert(0, HideRclpy())
module, attr = sys.argv[1].split(":")
sys.argv = [sys.argv[2], *sys.argv[3:]]
getattr(importlib.import_module(module), attr)()
"""


def run_without_rclpy(target, *args):
    return subprocess.run([sys.executable, "-c", WITHOUT_RCLPY, target, *args], capture_output=True, text=True,
                          timeout=120)


def test_every_node_has_a_console_script():
    from navlab.ros.launch import NODES

    assert sorted(SCRIPTS) == sorted(f"navlab-{node.replace('_', '-')}" for node in NODES)


@pytest.mark.parametrize("script", sorted(SCRIPTS))
def test_console_scripts_without_rclpy_say_so_in_one_line(script):
    node = script[len("navlab-"):].replace("-", "_")
    reference = run_without_rclpy("navlab.cli:main", "navlab", "ros", node)
    proc = run_without_rclpy(SCRIPTS[script], script, "--ros-args", "-p", "x:=1")
    for p in (reference, proc):
        assert p.returncode == 2, p.stderr
        assert "Traceback" not in p.stderr and p.stdout == ""
    assert proc.stderr == reference.stderr
    (line,) = proc.stderr.splitlines()
    assert re.fullmatch(r"Error: ROS 2 is not installed: pip install 'navlab\[ros2\]' \(.*rclpy.*\)", line)


def test_console_script_help_without_rclpy_still_works():
    proc = run_without_rclpy(SCRIPTS["navlab-sim"], "navlab-sim", "--help")
    assert proc.returncode == 0 and "navlab-sim" in proc.stdout and "ROS 2 is not installed" in proc.stdout
