"""A controller speed set above the robot's top speed is refused by name, for
every controller that has one (the robot would cut the speed, not the turn rate)."""

import pytest

from navlab.control.base import CONTROLLERS
from navlab.control.potential_field import PotentialField
from navlab.registry import parameters_of
from navlab.robots import make_robot
from navlab.sim.runner import simulate


def test_every_speed_setting_names_a_setting_of_its_controller():
    named = 0
    for name in CONTROLLERS.names():
        factory = CONTROLLERS.get(name)
        setting = factory.speed_setting
        if setting is None:
            continue
        named += 1
        # the hybrid hands its extra settings on to its potential field
        valid = parameters_of(PotentialField if name == "hybrid" else factory)
        assert setting in valid, (name, setting)
    assert named == len(CONTROLLERS.names())  # every controller here has a top speed


@pytest.mark.parametrize("controller, setting", [("rpp", "desired_linear_vel"), ("dwa", "max_vel_x"),
                                                 ("mppi", "vx_max"), ("pure_pursuit", "speed"),
                                                 ("goto_waypoint", "speed"), ("potential_field", "max_speed")])
def test_a_speed_above_the_robots_is_refused_naming_both(controller, setting):
    top = make_robot("diff").max_speed
    with pytest.raises(ValueError, match=f"controller {controller} {setting} 150 m/s is more than the robot's "
                                         f"max_speed {top:g} m/s"):
        simulate("clutter", robot="diff", controller=controller, controller_params={setting: 150.0}, max_time=1.0)


def test_a_speed_at_the_robots_top_speed_runs():
    top = make_robot("diff").max_speed
    result, _, _ = simulate("clutter", robot="diff", controller="pure_pursuit", controller_params={"speed": top},
                            max_time=1.0)
    assert result.status.name == "TIMEOUT"  # drove for its second, nothing refused


@pytest.mark.parametrize("robot, world, controller", [("diff", "clutter", "pure_pursuit"),
                                                      ("diff", "clutter", "goto_waypoint"), ("omni3", "parking", None)])
@pytest.mark.parametrize("value", ["fast", None])
def test_a_speed_that_is_not_a_number_is_named_not_a_type_error(robot, world, controller, value):
    with pytest.raises(ValueError, match=r"speed must be a (finite|positive) number"):
        simulate(world, robot=robot, controller=controller, controller_params={"speed": value}, max_time=1.0)


@pytest.mark.parametrize("controller, setting", [("rpp", "desired_linear_vel"), ("dwa", "max_vel_x"),
                                                 ("mppi", "vx_max")])
def test_a_default_speed_above_the_robots_is_lowered_to_it(controller, setting):
    top = make_robot("diff").max_speed
    assert parameters_of(CONTROLLERS.get(controller))[setting] > top  # the case in question
    _, _, sim = simulate("clutter", robot="diff", controller=controller, max_time=0.5)
    assert getattr(sim.controller, setting) == top


def test_rpp_regulated_min_speed_follows_a_slower_desired_speed():
    from navlab.control.rpp import NAV2_MIN_SPEED, RegulatedPurePursuit

    assert RegulatedPurePursuit().min_speed == NAV2_MIN_SPEED  # Nav2's default where it fits
    assert RegulatedPurePursuit(desired_linear_vel=0.2).min_speed == 0.2  # no second setting needed
    with pytest.raises(ValueError, match="regulated_linear_scaling_min_speed must be"):
        RegulatedPurePursuit(desired_linear_vel=0.2, regulated_linear_scaling_min_speed=0.3)
