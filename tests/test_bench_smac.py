"""benchmarks/smac: the Smac side of ``bench_hybrid.py --smac-maps --smac-driver``.

The costmap, interpolation and overlap helpers are checked against hand-derived values; the
driver itself (built from a Nav2 checkout by benchmarks/smac/build.sh, never on CI) only when
$SMAC_DRIVER names it, else those tests skip.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))

from smac.compare import BlockedCells, SmacDriver, binary_costs, densified, inflated_costs  # noqa: E402

RES = 0.05
ROBOT = [[-0.25, -0.2], [0.25, -0.2], [0.25, 0.2], [-0.25, 0.2]]


def test_inflated_costs_follow_nav2s_formula():
    blocked = np.zeros((40, 40), dtype=bool)
    blocked[20, 10] = True
    cost = inflated_costs(blocked, RES, inscribed_radius=0.2, radius=0.55, scaling=10.0)
    assert cost[20, 10] == 254
    assert cost[20, 14] == 253  # 4 cells = 0.2 m: inscribed
    assert cost[20, 15] == math.floor(252 * math.exp(-10 * 0.05)) == 152  # 0.25 m
    assert cost[23, 14] == 152  # (3, 4) cells: 5 cells away too
    assert cost[20, 21] == math.floor(252 * math.exp(-10 * 0.35)) == 7  # 11 cells = 0.55 m, the radius
    assert cost[20, 22] == 0  # beyond it
    assert binary_costs(blocked)[20, 10] == 254 and binary_costs(blocked).sum() == 254


def test_densified_steps_and_turns_the_short_way():
    poses = densified([[0.0, 0.0, 3.1], [0.05, 0.0, -3.1]], step=0.01)
    assert len(poses) == 6
    np.testing.assert_allclose(np.diff(poses[:, 0]), 0.01)
    # 3.1 -> -3.1 through pi: +0.0832 rad in all, not -6.2
    np.testing.assert_allclose(poses[-1, 2], 3.1 + (2 * math.pi - 6.2))
    assert np.all(np.diff(poses[:, 2]) > 0)


def test_overlaps_counts_area_not_touching():
    blocked = np.zeros((20, 20), dtype=bool)
    blocked[10, 10] = True  # the square [0.5, 0.55] x [0.5, 0.55]
    cells = BlockedCells(blocked, RES)
    n, area = cells.overlaps(ROBOT, [[0.25, 0.525, 0.0]])  # right edge at x = 0.5: touching
    assert (n, area) == (0, 0.0)
    n, area = cells.overlaps(ROBOT, [[0.26, 0.525, 0.0], [0.25, 0.525, 0.0], [0.1, 0.1, 0.0]])
    assert n == 1
    assert area == pytest.approx(0.01 * 0.05)  # a 1 cm strip of the cell
    n, _ = cells.overlaps(ROBOT, [[0.525, 0.525, 0.7]])  # the cell inside the robot: it counts
    assert n == 1


DRIVER = os.environ.get("SMAC_DRIVER")
needs_driver = pytest.mark.skipif(not DRIVER or not Path(DRIVER).is_file(),
                                  reason="set SMAC_DRIVER to a smac_driver built by benchmarks/smac/build.sh")


@needs_driver
def test_driver_plans_straight_and_refuses_a_blocked_goal():
    blocked = np.zeros((100, 100), dtype=bool)
    blocked[40:60, 70:90] = True  # a 1 m block at x 3.5-4.5 m, y 2-3 m
    driver = SmacDriver(Path(DRIVER), binary_costs(blocked), RES, ROBOT,
                        {"motion_model_for_search": "REEDS_SHEPP", "max_planning_time": 100.0})
    try:
        assert driver.config["circumscribed_cost"] == -1  # no inflation layer
        assert driver.config["circumscribed_radius"] == pytest.approx(math.hypot(0.25, 0.2), abs=1e-4)
        straight = driver.plan((1.0, 1.0, 0.0), (2.5, 1.0, 0.0))
        assert straight["found"]
        np.testing.assert_allclose(straight["poses"][0], [1.0, 1.0, 0.0], atol=1e-6)
        np.testing.assert_allclose(straight["poses"][-1], [2.5, 1.0, 0.0], atol=1e-6)
        assert straight["length_m"] == pytest.approx(1.5, abs=1e-6)
        blocked_goal = driver.plan((1.0, 1.0, 0.0), (4.0, 2.5, 0.0))
        assert not blocked_goal["found"] and "lethal" in blocked_goal["reason"].lower()
    finally:
        driver.close()


def test_bench_hybrid_says_when_the_driver_is_missing(tmp_path):
    run = subprocess.run([sys.executable, str(BENCHMARKS / "bench_hybrid.py"), "--smac-maps", "--smac-driver",
                          str(tmp_path / "nothing")], capture_output=True, text=True, timeout=120)
    assert run.returncode != 0
    assert "build it with benchmarks/smac/build.sh" in run.stderr
