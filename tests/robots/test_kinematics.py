"""Kinematics against hand derivations and independent integration."""

import math

import numpy as np
import pytest

from navlab.robots import Compass, DiffDrive, Odometry, Omni3, WheelEncoders, calibrate_heading, integrate_pose
from navlab.robots.kinematics import make_robot


@pytest.mark.parametrize("angles", [(30.0, 150.0, 270.0), (0.0, 120.0, 240.0), (10.0, 100.0, 250.0)])
def test_omni3_forward_inverts_inverse(angles):
    robot = Omni3(wheel_radius=0.05, base_radius=0.2, wheel_angles_deg=angles)
    for twist in np.random.default_rng(0).normal(size=(50, 3)):
        assert robot.forward(robot.inverse(*twist)) == pytest.approx(tuple(twist), abs=1e-12)


def test_omni3_matrices_match_the_closed_form():
    robot = Omni3(wheel_radius=0.03, base_radius=0.12)
    drive = np.radians([30, 150, 270]) + np.pi / 2
    closed = np.vstack((2 / 3 * np.cos(drive), 2 / 3 * np.sin(drive), np.full(3, 1 / (3 * 0.12))))
    assert robot.forward_matrix == pytest.approx(closed, abs=1e-12)
    # pure forward motion: the wheel at 270° (drive direction 0°) turns fastest, the others at -1/2 of it... by hand
    w = robot.inverse(0.3, 0.0, 0.0) * 0.03
    assert w == pytest.approx([0.3 * math.cos(math.radians(120)), 0.3 * math.cos(math.radians(240)), 0.3])


def test_diff_drive_wheel_speeds_by_hand():
    robot = DiffDrive()
    assert robot.inverse(0.1, 0.0, 0.0) == pytest.approx([0.1 / 0.033, 0.1 / 0.033])
    assert robot.inverse(0.0, 0.0, 1.0) == pytest.approx([-0.08 / 0.033, 0.08 / 0.033])
    assert robot.forward(robot.inverse(0.15, 0.0, -0.7)) == pytest.approx((0.15, 0.0, -0.7))
    assert robot.limit(1.0, 0.5, -9.0) == (0.22, 0.0, -2.84)


def test_integrate_pose_is_the_exact_arc():
    # a unicycle at v, ω stays on the circle of radius v/ω about its centre
    v, w, T = 0.2, 0.5, 2.0
    end = integrate_pose(np.array((1.0, 2.0, 0.3)), v, 0.0, w, T)
    centre = np.array((1.0, 2.0)) + (v / w) * np.array((-math.sin(0.3), math.cos(0.3)))
    assert np.hypot(*(end[:2] - centre)) == pytest.approx(v / w, abs=1e-12)
    assert end[2] == pytest.approx(0.3 + w * T)
    # and agrees with many small Euler steps of a holonomic twist
    pose = np.array((0.0, 0.0, 0.0))
    fine = pose.copy()
    n = 20000
    for _ in range(n):
        c, s = math.cos(fine[2]), math.sin(fine[2])
        fine = fine + np.array((c * 0.3 - s * 0.1, s * 0.3 + c * 0.1, 0.8)) * (1.0 / n)
    assert integrate_pose(pose, 0.3, 0.1, 0.8, 1.0) == pytest.approx(fine, abs=1e-4)


@pytest.mark.parametrize("raw, offset, expected", [(10, 20, -10), (350, 0, -10), (190, 0, -170), (180, 0, 180),
                                                   (0, 0, 0), (5, 355, 10)])
def test_heading_calibration_eq_3_4(raw, offset, expected):
    assert calibrate_heading(raw, offset) == pytest.approx(expected)


def test_compass_with_offset_reads_the_true_heading():
    compass = Compass(offset_deg=37.0)
    for heading in np.linspace(-3.1, 3.1, 13):
        assert compass.heading(compass.read(heading)) == pytest.approx(heading, abs=1e-9)


@pytest.mark.parametrize("robot, twist", [(Omni3(), (0.2, -0.1, 0.4)), (DiffDrive(), (0.15, 0.0, 0.6))])
def test_noise_free_odometry_tracks_the_true_pose(robot, twist):
    enc = WheelEncoders(ticks_per_rev=100000)
    pose = np.zeros(3)
    odo = Odometry(robot, pose)
    angles = np.zeros(robot.n_wheels)
    ticks = enc.counts(angles)
    dt = 0.01
    for _ in range(500):
        rotation = robot.inverse(*twist) * dt
        pose = integrate_pose(pose, *robot.forward(rotation / dt), dt)
        angles += rotation
        new = enc.counts(angles)
        odo.update(enc.angles(new - ticks))
        ticks = new
    assert odo.pose[:2] == pytest.approx(pose[:2], abs=2e-3)


@pytest.mark.parametrize("name, params", [("diff", {"wheel_radius": 0.0}), ("omni3", {"wheel_radius": -1}),
                                          ("omni3", {"base_radius": 0}), ("omni3", {"wheel_angles_deg": (0, 0, 0)})])
def test_bad_robot_parameters(name, params):
    with pytest.raises(ValueError):
        make_robot(name, **params)
    with pytest.raises(ValueError, match="(?i)did you mean"):
        make_robot("omni3", wheel_radus=0.1)


@pytest.mark.parametrize("angles", [30, "abc", [30, 150], [30, 150, "abc"], {0, 120, 240}, [[0], [120], [240]]])
def test_omni3_wheel_angles_must_be_three_finite_numbers(angles):
    """(a single number or a string was a TypeError, an internal error: attack run, session 18)"""
    from navlab.errors import ParameterError

    with pytest.raises(ParameterError, match=r"wheel_angles_deg must be three finite angles in degrees"):
        make_robot("omni3", wheel_angles_deg=angles)
    assert make_robot("omni3", wheel_angles_deg=(0, 120.0, 240)).n_wheels == 3
    with pytest.raises(ParameterError, match=r"wheel_angles_deg must be finite, got \[30, 150, an integer of 401 "):
        make_robot("omni3", wheel_angles_deg=[30, 150, 10 ** 400])


def test_a_robot_settings_error_names_the_robot():
    """(--robot-param radius=-1 said "radius must be a positive number", the robot unnamed, where the
    controllers' errors say "controller 'rpp': ...": newcomer, session 31)"""
    import pytest

    from navlab.errors import ParameterError
    from navlab.robots.kinematics import make_robot

    with pytest.raises(ParameterError, match=r"^robot 'diff': radius must be a positive number, got -1$"):
        make_robot("diff", radius=-1)
