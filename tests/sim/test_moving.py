"""Moving obstacles: motion against hand computation, the LiDAR and the swept
collision check at the right time, bad input, and replanning around one."""

import math
import re

import numpy as np
import pytest

from navlab.control import GotoWaypoint
from navlab.planning import plan
from navlab.robots import DiffDrive
from navlab.sensors import Lidar
from navlab.sim import Simulation, SimStatus
from navlab.sim.runner import simulate
from navlab.sim.scene import Scene
from navlab.world import World, WorldFormatError, world_from_dict
from navlab.world.motion import track

BASE = {"bounds": {"x": [0, 10], "y": [0, 4]}, "start": [1, 2], "goal": [9, 2]}


def world_with(*obstacles):
    return world_from_dict(BASE | {"obstacles": list(obstacles)})


@pytest.mark.parametrize("motion, expected", [
    # reflect: the box's min corner x = 4.5 + 2t folded into [0, 9] (the box is 1 m wide in [0, 10]):
    # t = 1 → 6.5; 2.25 → 9 (the wall); 2.5 → 18 − 9.5 = 8.5; 5 → 14.5 → 3.5; 7.25 → 19 − 18 = 1
    ({"velocity": [2.0, 0.0]}, [2.0, 4.5, 4.0, -1.0, -3.5]),
    # stop: the wall at x = 9 is reached after 2.25 s, for good
    ({"velocity": [2.0, 0.0], "at_bounds": "stop"}, [2.0, 4.5, 4.5, 4.5, 4.5]),
])
def test_constant_velocity_against_hand_computation(motion, expected):
    world = world_with({"type": "rectangle", "min": [4.5, 1.5], "max": [5.5, 2.5], "motion": motion})
    tr = track(world.obstacles[0], world.bounds)
    assert [tr.offset(t)[0] for t in (1.0, 2.25, 2.5, 5.0, 7.25)] == pytest.approx(expected)
    assert all(tr.offset(t)[1] == 0 for t in (1.0, 5.0))


def test_waypoints_loop_stop_and_back_and_forth_against_hand_computation():
    circle = {"type": "circle", "center": [3, 3.5], "radius": 0.3}
    loop = world_with(circle | {"motion": {"waypoints": [[3, 3.5], [3, 0.5], [6, 0.5]], "speed": 0.5}})
    tr = track(loop.obstacles[0], loop.bounds)
    # legs at 0.5 m/s: 3 m down (6 s), 3 m right (6 s), 3√2 m back to the first (6√2 s)
    cycle = 12.0 + 6 * math.sqrt(2)
    assert tr.offset(2.0) == pytest.approx((0.0, -1.0))
    assert tr.offset(9.0) == pytest.approx((1.5, -3.0))
    assert tr.offset(12.0 + 3 * math.sqrt(2)) == pytest.approx((1.5, -1.5))  # half way back
    assert tr.offset(2.0 + cycle) == pytest.approx((0.0, -1.0))
    once = world_with(circle | {"motion": {"waypoints": [[3, 3.5], [3, 0.5]], "speed": 0.5, "loop": False}})
    assert track(once.obstacles[0], once.bounds).offset(100.0) == pytest.approx((0.0, -3.0))
    # between: from the drawn place (3, 3.5) to a = (3, 2.5) (2 s), then a ↔ b = (3, 0.5) (4 s each way)
    bf = world_with(circle | {"motion": {"between": [[3, 2.5], [3, 0.5]], "speed": 0.5}})
    tb = track(bf.obstacles[0], bf.bounds)
    assert [tb.offset(t)[1] for t in (1.0, 2.0, 6.0, 8.0, 10.0, 14.0)] == pytest.approx(
        [-0.5, -1.0, -3.0, -2.0, -1.0, -3.0])


def test_lidar_sees_a_moving_circle_at_the_analytic_range_at_scan_time():
    world = world_with({"type": "circle", "center": [8, 2], "radius": 0.5, "motion": {"velocity": [-0.7, 0.0]}})
    scene = Scene(world, 0.1)
    lidar = Lidar(beams=4, range_min=0.0)  # beam 0 looks along +x
    for t in (0.0, 1.3, 4.0):
        scene.set_time(t)
        ranges = lidar.scan(scene, np.array((1.0, 2.0, 0.0)))
        assert ranges[0] == pytest.approx((8.0 - 0.7 * t) - 0.5 - 1.0, abs=1e-12)
    assert math.isinf(lidar.scan(world, np.array((1.0, 2.0, math.pi)))[0])


def test_head_on_obstacle_passing_between_two_steps_is_a_collision():
    # a 5 cm disc at 30 m/s goes from 0.7 m ahead of the robot to 0.8 m behind it within one 0.05 s step
    world = world_with({"type": "circle", "center": [2.2, 2.0], "radius": 0.05,
                        "motion": {"velocity": [-30.0, 0.0], "at_bounds": "stop"}})
    sim = Simulation(world, DiffDrive(), GotoWaypoint(), (1.5, 2.0, 0.0), (9.0, 2.0),
                     path=np.array([[1.5, 2.0], [9.0, 2.0]]), dt=0.05)
    r = sim.run(0)
    assert r.status is SimStatus.COLLIDED and r.steps == 1
    assert r.reason.startswith("moving obstacle 0 (circle) hit the robot")
    # at both ends of that step the disc is clear of the robot: only the swept check sees the hit
    scene = Scene(world, DiffDrive().radius)
    for t, pose in ((0.0, r.true_poses[0]), (0.05, r.true_poses[1])):
        centre = np.array((2.2, 2.0)) + scene.offsets_at(t)[0]
        assert np.hypot(*(pose[:2] - centre)) > 0.05 + DiffDrive().radius


def test_the_robot_hitting_a_slow_obstacle_is_told_apart():
    world = world_with({"type": "circle", "center": [3.0, 2.0], "radius": 0.3,
                        "motion": {"velocity": [0.0, 0.01]}})
    sim = Simulation(world, DiffDrive(), GotoWaypoint(), (1.0, 2.0, 0.0), (9.0, 2.0),
                     path=np.array([[1.0, 2.0], [9.0, 2.0]]))
    r = sim.run(0)
    assert r.status is SimStatus.COLLIDED and r.reason.startswith("the robot hit moving obstacle 0 (circle)")


@pytest.mark.parametrize("motion, field", [
    ({"waypoints": [[1, 1], [2, 2]], "speed": 0}, "obstacles[1].motion.speed"),
    ({"between": [[1, 1], [2, 2]], "speed": -0.3}, "obstacles[1].motion.speed"),
    ({"waypoints": [[1, 1]], "speed": 1}, "obstacles[1].motion.waypoints"),
    ({"velocity": [float("nan"), 1]}, "obstacles[1].motion.velocity"),
    ({"velocity": [0, 0]}, "obstacles[1].motion.velocity"),
    ({"velocity": [1, 0], "at_bounds": "bounce"}, "obstacles[1].motion.at_bounds"),
    ({"velocity": [1, 0], "speed": 2}, "obstacles[1].motion.speed"),
    ({"waypoints": [[1, 1], [2, 2]]}, "obstacles[1].motion.speed"),
    ("fast", "obstacles[1].motion"),
])
def test_bad_motions_name_the_obstacle_and_the_field(motion, field):
    with pytest.raises(WorldFormatError, match=re.escape(f"field '{field}'")):
        world_with({"type": "circle", "center": [5, 1], "radius": 0.2},
                   {"type": "circle", "center": [5, 3], "radius": 0.2, "motion": motion})


def test_start_inside_a_moving_obstacle_at_time_zero_is_invalid_start():
    world = world_with({"type": "circle", "center": [1.0, 2.0], "radius": 0.3,
                        "motion": {"between": [[1, 2], [5, 2]], "speed": 0.3}})
    assert plan(world, seed=0, max_iter=200).status.name == "INVALID_START"
    goal_blocked = world_from_dict(BASE | {"obstacles": [{"type": "circle", "center": [9, 2], "radius": 0.3,
                                                           "motion": {"velocity": [0, 0.1]}}]})
    assert plan(goal_blocked, seed=0, max_iter=200).status.name == "INVALID_GOAL"


def test_motion_round_trips_through_the_world_file_form():
    world = world_with({"type": "polygon", "points": [[4, 1], [5, 1], [4.5, 2]],
                        "motion": {"waypoints": [[4.5, 1.5], [6, 1.5]], "speed": 0.2, "loop": False}})
    again = world_from_dict(world.to_dict())
    assert again.obstacles == world.obstacles and isinstance(again, World)


def crossing(y0: float, speed: float):
    return world_with({"type": "circle", "center": [5, y0], "radius": 0.3,
                       "motion": {"waypoints": [[5, 3.5], [5, 0.5]], "speed": speed}})


@pytest.mark.parametrize("planner", ["rrt_star", "astar"])
def test_diff_drive_with_replan_survives_an_obstacle_crossing_its_path(planner):
    world = crossing(0.6, 0.2)  # without replanning the obstacle runs into the robot at x ≈ 5
    plain, _, _ = simulate(world, robot="diff", planner=planner, controller_params={"replan": False})
    assert plain.status is SimStatus.COLLIDED and "hit the robot" in plain.reason
    replanned, _, sim = simulate(world, robot="diff", planner=planner, controller_params={"replan": True})
    assert replanned.status is SimStatus.REACHED
    assert sim.min_clearance(replanned) > 0
    # the default follower replans by itself where obstacles move (an explicit replan=False is kept, above)
    default, _, _ = simulate(world, robot="diff", planner=planner)
    assert default.status is SimStatus.REACHED


def test_seed004_with_its_measured_delays_reaches_but_a_crossing_obstacle_hits_it():
    from navlab.sim.latency import MEASURED, NONE, _simulation

    target = (3.0, 0.0)
    late = _simulation(target, "static", MEASURED)
    r = late.run(1)
    assert r.status is SimStatus.REACHED and r.error_true < 0.040 and late.min_clearance(r) > 0
    crossing_now = _simulation(target, "crossing", NONE)
    assert crossing_now.run(1).status is SimStatus.REACHED
    r = _simulation(target, "crossing", MEASURED).run(1)
    assert r.status is SimStatus.COLLIDED and "hit the robot" in r.reason


def test_the_latency_table_shows_a_dash_where_no_run_reached():
    """The sensor-latency table printed 'nan' for the time of a setting no run reached, where
    docs/navigation.md shows '–' (newcomer run, session 17)."""
    from navlab.sim.latency import latency_table

    row = {"part": "table", "obstacle": "crossing", "delays": "measured", "max_speed": 0.3, "status": "COLLIDED",
           "error_true_mm": 1747.3, "time_s": 5.0, "min_clearance_mm": 0.0}
    line = latency_table([row]).splitlines()[1]
    assert "nan" not in line and line.split("|")[3].strip() == "–"
