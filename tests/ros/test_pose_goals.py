"""A /goal_pose's heading reaches a pose planner over real ROS 2, and the
/plan's poses carry the planned headings (pose_goal_scenario.py)."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rclpy", reason="rclpy cannot be imported: the ros2 extra is not installed")

from ros_helpers import run_isolated  # noqa: E402

from navlab.sampling import reeds_shepp  # noqa: E402

SCENARIO = Path(__file__).with_name("pose_goal_scenario.py")


def test_hybrid_astar_plans_to_the_goal_pose_heading_and_publishes_headings():
    proc = run_isolated([sys.executable, str(SCENARIO)], timeout=120)
    assert proc.returncode == 0, proc.stderr[-4000:]
    seen = json.loads(proc.stdout.strip().splitlines()[-1])
    assert seen["plans"] == 1
    poses = np.array(seen["poses"])
    assert np.allclose(poses[0], (1.0, 2.0, 0.0), atol=1e-9)
    assert np.allclose(poses[-1][:2], (4.0, 2.0), atol=1e-9)
    assert abs(math.remainder(poses[-1][2] - math.pi, 2 * math.pi)) < 1e-6  # facing west, as the goal asked
    # a path that turns round: it is at least the Reeds–Shepp distance, which a straight 3 m line is not
    length = float(np.sum(np.hypot(*np.diff(poses[:, :2], axis=0).T)))
    rs = reeds_shepp.shortest((1.0, 2.0, 0.0), (4.0, 2.0, math.pi), 0.5).length
    assert length >= rs - 0.05 and rs > 3.5
    # each pose faces along the path, forwards or backwards (a car's path, not a point's)
    chords = np.arctan2(*np.diff(poses[:, :2], axis=0).T[::-1])
    off = np.abs(np.remainder(chords - poses[1:, 2] + math.pi / 2, math.pi) - math.pi / 2)
    assert off.max() < 0.2
