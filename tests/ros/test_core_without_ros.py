"""The core never imports rclpy: everything but navlab.ros's node modules
works without the ros2 extra."""

import subprocess
import sys

CODE = """
import sys, pkgutil, importlib
import navlab
from navlab.cli import main
import navlab.ros.core, navlab.ros.launch, navlab.ros.entry
for info in pkgutil.walk_packages(navlab.__path__, "navlab."):
    if not info.name.startswith("navlab.ros") and info.name != "navlab.__main__":
        importlib.import_module(info.name)
main(["ros", "--help"], standalone_mode=False)
print(sorted(m for m in sys.modules if m.split(".")[0] in ("rclpy", "rosbags", "nav_msgs", "geometry_msgs", "visualization_msgs")))
"""


def test_nothing_outside_the_ros_nodes_imports_ros():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, check=True).stdout
    assert out.strip().splitlines()[-1] == "[]"
