"""``navlab ros delay`` on real topics: the sim node injects seed 004's
measured delays and the tool measures them back."""

import json
import math
import sys

import pytest

from navlab.ros.delay import TopicDelay, table

pytest.importorskip("rclpy", reason="rclpy cannot be imported: the ros2 extra is not installed")

from ros_helpers import run_isolated  # noqa: E402


def test_summary_and_table_by_hand():
    d = TopicDelay("/scan", "sensor_msgs/msg/LaserScan", True)
    for k, (receive, stamp) in enumerate(((1.0, 0.5), (1.1, 0.7), (1.2, 0.6))):
        d.add(receive, stamp)
    s = d.summary()
    assert s["count"] == 3 and s["rate_hz"] == pytest.approx(10.0)
    assert s["delay_mean_s"] == pytest.approx(0.5) and s["delay_min_s"] == pytest.approx(0.4)
    assert s["delay_max_s"] == pytest.approx(0.6)
    clock = TopicDelay("/clock", "rosgraph_msgs/msg/Clock", False)
    clock.add(1.0, None)
    clock.add(1.5, None)
    text = table([s, clock.summary()], "sim")
    assert "/clock: rosgraph_msgs/msg/Clock has no header stamp: no delay, rate only" in text
    assert math.isnan(clock.summary()["delay_mean_s"]) and clock.summary()["rate_hz"] == pytest.approx(2.0)


def test_injected_latency_is_measured_back_on_real_topics():
    py = sys.executable
    script = (
        f"{py} -m navlab ros sim --ros-args -p world:=one_obstacle -p robot:=omni3 -p dt:=0.01 "
        "-p real_time_factor:=2.0 -p scan_latency:=0.5 -p odom_latency:=0.08 -p odom_rate:=50.0 "
        "> /dev/null 2>&1 & SIM=$!; "
        f"{py} -m navlab ros delay /scan /odom /clock --duration 3 --json; STATUS=$?; "
        "kill -INT $SIM; wait $SIM; exit $STATUS")
    out = run_isolated(["sh", "-c", script], timeout=120)
    assert out.returncode == 0, out.stdout + out.stderr
    rows = {r["topic"]: r for r in map(json.loads, out.stdout.splitlines())}
    scan, odom, clock = rows["/scan"], rows["/odom"], rows["/clock"]
    assert scan["clock"] == "sim" and scan["count"] > 20 and odom["count"] > 100
    assert abs(scan["delay_mean_s"] - 0.5) < 0.02 and abs(odom["delay_mean_s"] - 0.08) < 0.02
    # rates on the receiving (simulated) clock: 10 Hz scans, 50 Hz odometry
    assert scan["rate_hz"] == pytest.approx(10.0, rel=0.1) and odom["rate_hz"] == pytest.approx(50.0, rel=0.1)
    assert clock["has_stamp"] is False and clock["count"] > 100 and clock["delay_mean_s"] is None  # JSON null
