"""Sensor rates and latencies: delayed measurements are the undelayed ones
shifted by the latency."""

import numpy as np
import pytest

from navlab.control.base import Command, Controller
from navlab.robots import Omni3
from navlab.sensors import Lidar
from navlab.sensors.timing import DelayLine, SensorTiming
from navlab.sim import Simulation
from navlab.sim.experiments import seed004_world


class OpenLoop(Controller):
    """Drives a fixed twist whatever it sees, and records what it saw."""

    needs_scan = True
    holonomic = True

    def reset(self, goal, path=None):
        self.seen = []

    def command(self, t, pose, points=None):
        self.seen.append((t, np.array(pose), None if points is None else np.array(points)))
        return Command(0.1, 0.05, 0.2)


def run(lidar_timing=None, odometry_timing=None, seed=3):
    ctrl = OpenLoop()
    sim = Simulation(seed004_world((3.0, 0.0), True), Omni3(), ctrl, (0, 0, 0), (3.0, 0.0),
                     lidar=Lidar(noise="rplidar_a1"), dt=0.02, max_time=3.0,
                     lidar_timing=lidar_timing, odometry_timing=odometry_timing)
    result = sim.run(seed)
    return result, ctrl.seen


def test_delayed_measurements_are_the_undelayed_ones_shifted_by_the_latency():
    plain, seen = run()
    late, seen_late = run({"latency": 0.5}, {"latency": 0.08})
    # open loop: the same trajectory and the same noise draws
    assert np.array_equal(plain.true_poses, late.true_poses)
    lag_scan, lag_odom = 25, 4  # 0.5 s and 0.08 s in 0.02 s steps
    for k in range(lag_scan, len(seen)):
        assert np.array_equal(seen_late[k][2], seen[k - lag_scan][2])
    for k in range(lag_odom, len(seen)):
        assert np.array_equal(seen_late[k][1], seen[k - lag_odom][1])
    # before the first one arrives: the start pose and no scan
    assert np.array_equal(seen_late[0][1], [0, 0, 0]) and len(seen_late[lag_scan - 1][2]) == 0


def test_rate_holds_the_last_sample_between_samples():
    _, seen = run({"rate": 10.0})  # a scan every 5 steps of 0.02 s
    for k in range(len(seen)):
        assert np.array_equal(seen[k][2], seen[k - k % 5][2])
    assert not np.array_equal(seen[5][2], seen[0][2])


def test_jitter_comes_from_the_seeded_generator_and_never_runs_backwards():
    line = DelayLine(SensorTiming(latency=0.5, jitter=0.2), np.random.default_rng(1))
    times = np.arange(0, 10, 0.02)
    got = []
    for t in times:
        line.push(t, t)
        got.append(line.read(t))
    got = [g for g in got if g is not None]
    assert all(b >= a for a, b in zip(got, got[1:]))  # never an older sample after a newer one
    lag = times[-len(got):] - np.array(got)
    # the newest arrival wins, so the age is at most the slowest delay and usually below the mean latency
    assert lag.min() >= 0 and lag.max() < 0.5 + 4 * 0.2 and 0.1 < np.mean(lag) < 0.5
    again = DelayLine(SensorTiming(latency=0.5, jitter=0.2), np.random.default_rng(1))
    assert [again.push(t, t) or again.read(t) for t in times][-len(got):] == got


@pytest.mark.parametrize("timing, field", [
    ({"latency": -0.1}, "latency"), ({"rate": 0}, "rate"), ({"jitter": float("nan")}, "jitter"),
    ({"delay": 0.1}, "delay"),
])
def test_bad_timings_name_the_sensor_and_the_field(timing, field):
    with pytest.raises(ValueError, match=rf"lidar: field '{field}'"):
        run(timing)
