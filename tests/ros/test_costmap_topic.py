"""The sim node publishes the world's Nav2-style costmap on /costmap (nav_msgs/OccupancyGrid, 0–100)."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rclpy", reason="rclpy cannot be imported: the ros2 extra is not installed")

from ros_helpers import run_isolated  # noqa: E402

BARN = Path(__file__).resolve().parents[3] / "shared" / "data" / "barn"


@pytest.mark.skipif(not BARN.is_dir(), reason="../shared/data/barn is not beside the checkout")
def test_sim_publishes_the_costmap_of_its_world():
    proc = run_isolated([sys.executable, str(Path(__file__).with_name("costmap_scenario.py")),
                         str(BARN / "world_0.world")], timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    seen = json.loads(proc.stdout.strip().splitlines()[-1])
    from navlab.robots import make_robot
    from navlab.world import load_world
    from navlab.world.costmap import build_costmap

    expected = build_costmap(load_world(str(BARN / "world_0.world")), make_robot("jackal").shape, 0.5, 3.0)
    values = expected.to_occupancy_values()
    assert (seen["height"], seen["width"]) == expected.shape
    assert seen["lethal"] == int((values == 100).sum()) > 0
    assert seen["inscribed"] == int((values == 99).sum()) > 0
    assert seen["unknown"] == 0 and seen["resolution"] == pytest.approx(0.05)
    assert np.isclose(seen["resolution"], expected.resolution)
