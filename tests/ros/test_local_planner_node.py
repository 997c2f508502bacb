"""The local_planner node: its decisions without ROS (navlab.ros.costmap_drive),
and over real ROS 2 the sim's Jackal driven by it round a wall to the goal of
a /plan (local_planner_scenario.py, in a private network namespace), judged
from /ground_truth and the sim's own collision check."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from navlab.grid import OccupancyGrid, save_map
from navlab.ros.core import STOP, plan_on_map
from navlab.ros.costmap_drive import CostmapDrive, costmap_controllers, densify
from navlab.world.costmap import LETHAL_OBSTACLE, build_costmap
from navlab.world.footprint import Footprint

SCENARIO = Path(__file__).with_name("local_planner_scenario.py")
JACKAL = "[[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]]"


class Logbook(list):
    def __call__(self, level, text):
        self.append((level, text))

    def said(self, words):
        return [(level, text) for level, text in self if words in text]


def room() -> OccupancyGrid:
    """6 × 3.2 m at 0.05 m: walls round it, and one across from the bottom up to y = 2.0 at x ∈ [2.9, 3.1)."""
    blocked = np.zeros((64, 120), bool)
    blocked[[0, -1], :] = True
    blocked[:, [0, -1]] = True
    blocked[0:40, 58:62] = True
    return OccupancyGrid(blocked, 0.05, (0.0, 0.0, 0.0))


START, GOAL = (0.8, 0.8, 0.0), (5.2, 0.8)


def round_the_wall() -> np.ndarray:
    """The pathplanner's path (A*, line-of-sight smoothed, 0.35 m from the walls): 5 vertices."""
    return plan_on_map(room(), START[:2], GOAL, "astar", "uniform", 0, 0.35, False, {"smooth": True}).path


def drive(core, pose, seconds, rate=50.0, t0=0.0, scan=None):
    """Feed ``core`` odometry at ``rate`` Hz from a unicycle that obeys each command at once;
    returns the poses and the commands sent (None entries: nothing sent)."""
    pose = np.array(pose, float)
    twist, poses, sent = STOP, [pose.copy()], []
    dt = 1.0 / rate
    for k in range(int(round(seconds * rate))):
        t = t0 + k * dt
        if scan is not None:
            core.set_scan(scan(pose), now=t)
        out = core.on_odom(t, tuple(pose), now=t)
        sent.append(out)
        if out is not None:
            twist = out
        if not core.drive.active:
            break
        vx, _, w = twist
        pose = pose + dt * np.array((vx * math.cos(pose[2]), vx * math.sin(pose[2]), w))
        poses.append(pose.copy())
    return np.array(poses), sent


# -- without ROS -----------------------------------------------------------------------------------------------


def test_the_costmap_controllers_are_the_ones_it_runs():
    assert costmap_controllers() == ["dwa", "dwa_barn", "mppi", "rpp"]


@pytest.mark.parametrize("settings, words", [
    (dict(controller="rp"), "Did you mean 'rpp'?"),
    (dict(controller="goto_waypoint"), "reads no costmap"),
    (dict(controller="mppi", vx_maxx=0.3), "Did you mean 'vx_max'?"),
    (dict(controller="dwa", max_vel_x="fast"), "max_vel_x must be a finite number"),
    (dict(footprint="[[0, 0], [1, 0]]"), "footprint needs at least 3 points"),
    (dict(footprint="[[0, 0], [1, 0]"), "footprint"),
    (dict(robot_radius=0.3, inflation_radius=0.2), "below the footprint's inscribed radius"),
    (dict(layers="sensors"), "layers must be one of static, sensor, static+sensor"),
    (dict(controller_frequency=0.0), "controller_frequency must be a positive number"),
])
def test_bad_settings_are_refused_at_start_up_in_one_line(settings, words):
    with pytest.raises(ValueError) as exc:
        CostmapDrive(Logbook(), **settings)
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_controller_frequency_is_also_the_controllers_own_setting():
    for name in ("dwa", "rpp"):
        assert CostmapDrive(Logbook(), name, controller_frequency=10.0).controller.period == pytest.approx(0.1)
    core = CostmapDrive(Logbook(), "rpp", footprint=JACKAL, inflation_radius=0.5)
    assert core.footprint == Footprint.from_value(JACKAL)


def test_densify_keeps_the_polyline_with_a_point_every_step():
    path = round_the_wall()
    dense = densify(path, 0.05)
    assert np.hypot(*np.diff(dense, axis=0).T).max() <= 0.05 + 1e-12
    assert all(np.isclose(dense, p).all(axis=1).any() for p in path)  # every vertex kept
    # every new point lies on its segment
    length = lambda p: np.hypot(*np.diff(p, axis=0).T).sum()  # noqa: E731
    assert length(dense) == pytest.approx(length(path), abs=1e-9)


def test_a_path_before_the_map_waits_then_drives_round_the_wall_to_the_goal():
    log = Logbook()
    core = CostmapDrive(log, "rpp", footprint=JACKAL, inflation_radius=0.5)
    assert core.set_plan(round_the_wall()) is None and "115-pose path" in log[-1][1]  # densified to 5 cm
    assert core.on_odom(0.0, START, now=0.0) == STOP and core.on_odom(0.02, START, now=0.02) == STOP
    assert len(log.said("no /map yet")) == 1  # said once
    costmap = core.set_map(room())
    assert costmap.shape == (64, 120) and "costmap 120x64 cells" in log[-1][1]
    poses, _ = drive(core, START, 40.0, t0=0.04)
    assert log.said("resuming") and log[-1][0] == "info" and "goal reached" in log[-1][1]
    assert np.hypot(*(poses[-1, :2] - GOAL)) <= 0.25 + 0.02
    # the footprint never met a wall on the way
    exact = build_costmap(room(), core.footprint, 0.5, 3.0)
    assert exact.footprint_cost(poses, core.footprint).max() < LETHAL_OBSTACLE
    assert poses[:, 1].max() > 2.0  # round the wall's end


def test_one_control_cycle_per_period_of_odometry_stamps():
    core = CostmapDrive(Logbook(), "rpp", controller_frequency=20.0)
    core.set_map(room())
    core.set_plan(round_the_wall())
    _, sent = drive(core, START, 2.0, rate=50.0)
    assert core.cycles == 40  # 20 Hz from 50 Hz odometry
    assert sum(s is not None for s in sent) == 40
    # stamps that go back (a restarted simulator) start the grid again rather than stop the robot
    before = core.cycles
    drive(core, START, 0.2, rate=50.0, t0=0.0)
    assert core.cycles == before + 4


def test_silent_odometry_stops_the_robot_and_the_drive_resumes():
    log = Logbook()
    core = CostmapDrive(log, "rpp", odom_timeout=0.3)
    core.set_map(room())
    core.set_plan(round_the_wall())
    assert core.on_odom(0.0, START, now=0.0) not in (None, STOP)
    assert core.watchdog(0.2) is None
    assert core.watchdog(0.5) == STOP and core.watchdog(0.6) == STOP
    assert len(log.said("no odometry")) == 1 and log.said("no odometry")[0][0] == "warn"
    core.on_odom(0.1, START, now=0.7)
    assert log[-1] == ("info", "odometry is back") and core.watchdog(0.8) is None


def test_empty_and_non_finite_plans():
    log = Logbook()
    core = CostmapDrive(log, "rpp")
    core.set_map(room())
    core.set_plan(round_the_wall())
    assert core.set_plan(np.zeros((0, 2))) == STOP and log[-1][0] == "warn" and not core.drive.active
    bad = round_the_wall()
    bad[3, 0] = math.nan
    assert core.set_plan(bad) is None and log[-1][0] == "error" and not core.drive.active


def test_a_map_without_a_costmap_is_refused_and_the_old_one_kept():
    log = Logbook()
    core = CostmapDrive(log, "rpp")
    core.set_map(room())
    feed = core.feed
    rotated = OccupancyGrid(np.zeros((10, 10), bool), 0.05, (0.0, 0.0, 0.3))
    assert core.set_map(rotated) is None and log[-1][0] == "error" and core.feed is feed


def test_a_sensor_layer_waits_for_scans_and_publishes_its_costmap():
    log = Logbook()
    core = CostmapDrive(log, "rpp", layers="sensor", footprint=JACKAL, inflation_radius=0.5, costmap_interval=1.0)
    assert core.needs_scan
    empty = core.set_map(room())
    assert (empty.costs == 0).all()  # no static layer: nothing known before the first scan
    core.set_plan(round_the_wall())
    assert core.on_odom(0.0, START, now=0.0) == STOP and "waiting for the first /scan" in log[-1][1]
    wall = np.column_stack((np.full(40, 2.95), np.linspace(0.05, 1.95, 40)))  # the wall across, as a LiDAR sees it
    core.set_scan(wall, now=0.0)
    assert core.on_odom(0.02, START, now=0.02) not in (None, STOP)
    seen = core.costmap_due(0.02)
    assert seen is not None and (seen.cost_at(wall) == LETHAL_OBSTACLE).all()
    assert core.costmap_due(0.5) is None and core.costmap_due(1.1) is not None
    # the scan goes stale: stand still, warn once
    assert core.on_odom(1.0, START, now=1.0) == STOP and core.on_odom(1.02, START, now=1.02) == STOP
    assert len(log.said("no /scan in the last 0.5 s")) == 1 and log.said("no /scan")[0][0] == "warn"


def test_static_layers_publish_the_costmap_only_with_the_map():
    core = CostmapDrive(Logbook(), "mppi", layers="static", batch_size=200)
    core.set_map(room())
    core.set_plan(round_the_wall())
    assert core.on_odom(0.0, START, now=0.0) not in (None, STOP) and core.controller.costmap.shape == (64, 120)
    assert core.costmap_due(5.0) is None


def test_mppi_is_seeded():
    def commands(seed):
        core = CostmapDrive(Logbook(), "mppi", seed=seed, batch_size=200)
        core.set_map(room())
        core.set_plan(round_the_wall())
        _, sent = drive(core, START, 0.5)
        return [s for s in sent if s is not None]

    assert commands(3) == commands(3) != commands(4)


def test_the_core_needs_no_ros():
    code = ("import sys; import navlab.ros.costmap_drive; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('rclpy', 'nav_msgs', 'geometry_msgs')))")
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip() == "[]"


# -- over real ROS 2 ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("controller, settings", [("rpp", []), ("mppi", []), ("rpp", ["layers:=static+sensor"])],
                         ids=["rpp", "mppi", "rpp-sensor-layer"])
def test_the_node_drives_the_sims_jackal_round_the_wall_to_the_goal(tmp_path, controller, settings):
    pytest.importorskip("rclpy", reason="rclpy cannot be imported: the ros2 extra is not installed")
    from ros_helpers import run_isolated
    from shapely import Polygon, box, unary_union

    from navlab.sim.simulation import GOAL_TOLERANCE

    grid = room()
    save_map(grid, str(tmp_path / "room.yaml"))
    (tmp_path / "plan.json").write_text(json.dumps(round_the_wall().tolist()))
    proc = run_isolated([sys.executable, str(SCENARIO), str(tmp_path), controller, *settings], timeout=150)
    assert proc.returncode == 0, proc.stderr[-4000:]
    seen = json.loads(proc.stdout.strip().splitlines()[-1])
    assert seen["ended"] and "goal reached" in seen["planner_logs"][-1], seen["planner_logs"]
    # judged on the true pose, not the controller's opinion: at the goal, never touching a wall
    assert seen["sim_errors"] == []
    truth = np.array(seen["truth"])
    assert np.hypot(*(truth[-1, :2] - GOAL)) <= GOAL_TOLERANCE
    assert truth[:, 1].max() > 2.0  # it went round the wall's end
    walls = unary_union([box(x * 0.05, y * 0.05, (x + 1) * 0.05, (y + 1) * 0.05)
                         for y, x in zip(*np.nonzero(grid.blocked))])
    outline = Footprint.from_value(JACKAL)
    clearance = min(Polygon(outline.at(p[:3])).distance(walls) for p in truth[::5])
    assert clearance > 0.0
    # the published costmap: Nav2's scaling of the static layer (and, with a sensor layer, updates)
    assert seen["costmaps"] >= (2 if settings else 1)
    if not settings:
        # on the map as /map carries it: its resolution is a float32 (cells 0.5 m from a wall are just outside)
        carried = OccupancyGrid(grid.blocked, float(np.float32(grid.resolution)), grid.origin)
        expected = build_costmap(carried, outline, 0.5, 3.0).to_occupancy_values()
        assert seen["costmap_values"] == {str(v): int((expected == v).sum()) for v in (0, 99, 100, -1)}
