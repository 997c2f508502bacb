"""Potential-field forces by hand (seed 004, eq. 9 and 12) and followers."""

import numpy as np
import pytest

from navlab.control import GotoWaypoint, PotentialField, attractive, make_controller, repulsive


def test_attractive_force_eq9():
    assert attractive(0.005, 0.0, 2.0, 0.01, 0.5) == pytest.approx([0, 0])  # inside r
    assert attractive(0.0, 0.3, 2.0, 0.1, 0.5) == pytest.approx([0, 2.0 * 0.2])  # α(d − r)
    assert attractive(3.0, 4.0, 2.0, 0.1, 0.5) == pytest.approx([0.6, 0.8])  # α·s beyond s + r, continuous
    below = np.hypot(*attractive(0.6 - 1e-9, 0, 2.0, 0.1, 0.5))
    assert below == pytest.approx(np.hypot(*attractive(0.6 + 1e-9, 0, 2.0, 0.1, 0.5)))


def test_repulsive_force_eq12():
    pts = np.array([[0.05, 0.0], [0.0, 0.3], [2.0, 0.0]])  # inside r, in the band, beyond
    f = repulsive(pts, beta=1.0, delta=5.0, r=0.1, s=0.4)
    assert f == pytest.approx([-5.0, -(0.5 - 0.3)])


def test_potential_field_body_velocity_and_reached():
    pf = PotentialField(alpha=1.0, r=0.01, s=0.3, max_speed=0.3, min_speed=0.0)
    pf.reset((0.0, 3.0))
    cmd = pf.command(0.0, np.array((0.0, 0.0, np.pi / 2)))  # facing the goal: body x forward
    assert (cmd.vx, cmd.vy) == pytest.approx((0.3, 0.0))
    assert cmd.omega == pytest.approx(-2.0 * np.pi / 2)  # heading held at 0
    assert pf.command(1.0, np.array((0.0, 2.995, 0.0))).status == "REACHED"


def test_goto_waypoint_turns_harder_and_slows_when_off_course():
    g = GotoWaypoint(speed=0.2, heading_gain=1.0, turn_threshold=0.5, slow_speed=0.0, turn_boost=2.0)
    g.reset((2.0, 0.0), np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))
    on = g.command(0.0, np.array((0.0, 0.0, 0.1)))
    off = g.command(0.0, np.array((0.0, 0.0, 1.2)))
    assert on.vx == pytest.approx(0.2 * np.cos(0.1)) and on.omega == pytest.approx(-0.1)
    assert off.vx == 0.0 and off.omega == pytest.approx(-2.4)
    assert g.command(0.0, np.array((0.95, 0.0, 0.0))).status == "RUNNING"  # passes (1, 0) within reach
    assert g.index == 2
    assert g.command(0.0, np.array((1.99, 0.0, 0.0))).status == "REACHED"


def test_unknown_controller_and_bad_gains():
    with pytest.raises(ValueError, match="(?i)did you mean 'potential_field'"):
        make_controller("potential_feild")
    with pytest.raises(ValueError):
        make_controller("potential_field", alpha=0)


def test_every_numeric_setting_of_every_controller_refuses_an_integer_past_floats_range():
    """10**400 written out (a YAML file's or --controller-param's number) is bad input naming the
    setting, never an OverflowError: 176 settings were internal errors until session 18."""
    from navlab.control.base import CONTROLLERS
    from navlab.errors import ParameterError
    from navlab.registry import parameters_of

    tried = 0
    for name in CONTROLLERS.names():
        for key, default in parameters_of(CONTROLLERS.get(name)).items():
            if isinstance(default, bool) or not isinstance(default, (int, float)):
                continue
            for huge in (10 ** 400, -(10 ** 400)):
                with pytest.raises(ParameterError, match=f"{key} must be finite, got an integer of 401 digits"):
                    make_controller(name, **{key: huge})
            tried += 1
    assert tried > 150


@pytest.mark.parametrize("name, setting, words", [
    ("hybrid", {"carrot": "abc"}, "hybrid carrot must be a finite number"),
    ("hybrid", {"carrot": True}, "hybrid carrot must be a finite number, got True"),
    ("hybrid", {"replan_interval": "abc"}, "hybrid replan_interval must be a finite number"),
    ("hybrid", {"max_replans": True}, "hybrid max_replans must be a whole number"),
    ("goto_waypoint", {"slow_speed": "abc"}, "goto_waypoint slow_speed must be a finite number"),
    ("goto_waypoint", {"slow_speed": -1.0}, "goto_waypoint slow_speed must be ≥ 0"),
    ("goto_waypoint", {"turn_boost": 0.0}, "goto_waypoint turn_boost must be > 0"),
    ("rear_wheel_feedback", {"settling_distance": 1e-300}, "settling_distance must be ≥ 0.001 and ≤ 1000"),
    ("rear_wheel_feedback", {"settling_distance": 1e308}, "settling_distance must be ≥ 0.001 and ≤ 1000")])
def test_settings_once_unchecked_are_named(name, setting, words):
    """Each was a TypeError, ZeroDivisionError or OverflowError mid-run, or silently taken (attack run, session 18)."""
    from navlab.errors import ParameterError

    with pytest.raises(ParameterError, match=words):
        make_controller(name, **setting)
    sensible = {key: 2 if key == "max_replans" else 0.5 for key in setting}
    assert make_controller(name, **sensible)
