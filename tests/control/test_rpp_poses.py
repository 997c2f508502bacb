"""RPP's footprint-aware paths (``plan_poses``): planned on the costmap's LETHAL cells, tracked closely."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

from navlab.control import make_controller
from navlab.grid.cost_search import plan_poses_on_costmap
from navlab.robots import make_robot
from navlab.sim import Simulation
from navlab.sim.costmap_feed import tight_for
from navlab.world import Bounds, World
from navlab.world.costmap import build_costmap

sys.path.insert(0, str(Path(__file__).parent))
from test_rpp_collision import JACKAL, _fence_with_gap  # noqa: E402


def _posts(world):
    return shapely.union_all([shapely.Point(o.center).buffer(o.radius, 64) for o in world.obstacles])


def test_the_pose_path_keeps_the_footprint_off_every_post_and_drives_forward():
    # Hybrid A*'s footprint cells cover each 5° heading bin and each cell: the lattice needs more room
    # than the rectangle itself
    world = _fence_with_gap(0.55)
    costmap = build_costmap(world, JACKAL, inflation_radius=0.55)
    result = plan_poses_on_costmap(costmap, JACKAL, (0.0, 0.8, 0.0), (4.0, -0.8, 0.0), 0.2)
    assert result.status.success, result.reason
    poses = result.path
    assert np.allclose(poses[0], (0, 0.8, 0)) and np.allclose(poses[-1, :2], (4, -0.8), atol=1e-6)
    posts = _posts(world)
    assert min(shapely.Polygon(JACKAL.at(p)).distance(posts) for p in poses) > 0
    step = np.diff(poses[:, :2], axis=0)
    assert (np.cos(poses[:-1, 2]) * step[:, 0] + np.sin(poses[:-1, 2]) * step[:, 1] > -1e-9).all()


def test_no_pose_path_through_a_gap_narrower_than_the_jackal():
    world = _fence_with_gap(0.25)
    costmap = build_costmap(world, JACKAL, inflation_radius=0.55)
    assert not plan_poses_on_costmap(costmap, JACKAL, (0.0, 0.0, 0.0), (4.0, 0.0, 0.0), 0.2,
                                     max_expansions=20_000).status.success


def test_tight_for_agrees_with_shapely_on_a_path_through_the_gap():
    world = _fence_with_gap(0.45)
    costmap = build_costmap(world, JACKAL, inflation_radius=0.55)
    path = np.column_stack((np.linspace(0, 4, 81), np.zeros(81)))
    posts = _posts(world)
    for padding in (0.0, 0.1):
        footprint = JACKAL.padded(padding)
        touches = any(shapely.Polygon(footprint.at((x, y, 0.0))).intersects(posts) for x, y in path)
        assert tight_for(costmap, footprint, path) == touches == (padding > 0)


def test_poses_are_tracked_within_two_centimetres_on_a_tight_circle():
    world = World("open", Bounds(-3, 3, -3, 3), (0, 0), (0, 2), ())
    radius = 0.5
    phi = np.linspace(0, 1.5 * math.pi, 300)
    poses = np.column_stack((radius * np.sin(phi), radius - radius * np.cos(phi), phi))
    goal = poses[-1, :2]
    ctrl = make_controller("rpp", plan_poses=True, desired_linear_vel=1.0)
    result = Simulation(world, make_robot("jackal"), ctrl, (0.0, 0.0, 0.0), goal, path=poses,
                        max_time=30).run(seed=0)
    assert result.status.name == "REACHED", result.reason
    off = np.abs(np.hypot(result.true_poses[:, 0], result.true_poses[:, 1] - radius) - radius)
    assert off.max() < 0.02


@pytest.mark.parametrize("params, words", [
    ({"plan_poses": "yes"}, "plan_poses must be true or false"),
    ({"pose_plan_after": 0}, "pose_plan_after must be > 0"),
    ({"pose_plan_turning_radius": -1}, "pose_plan_turning_radius must be > 0"),
    ({"pose_plan_clearance": -0.1}, "pose_plan_clearance must be ≥ 0"),
    ({"pose_track_settling": float("inf")}, "pose_track_settling must be finite"),
])
def test_bad_pose_settings_name_the_field(params, words):
    with pytest.raises(ValueError, match=words):
        make_controller("rpp", **params)


def test_a_stall_at_a_gap_the_centre_path_fits_says_so_and_plan_poses_passes_it():
    """The built-in clutter scene: the costmap path runs between a cylinder and a box where the
    jackal's rectangle only passes lengthwise; Nav2's RPP stops there, and the stalled run says
    why and which setting answers it (it said only "no progress" until session 18)."""
    from navlab.sim.runner import simulate

    stalled, *_ = simulate("clutter", robot="jackal", controller="rpp")
    assert stalled.status.name == "STALLED" and np.hypot(*(stalled.final_true[:2] - stalled.goal)) > 2.0
    assert "LETHAL cell on the arc ahead" in stalled.reason and "plan_poses=true" in stalled.reason
    crept, *_ = simulate("clutter", robot="jackal", controller="rpp", controller_params={"creep_when_blocked": True})
    # (creeping, it turns in place and never stands still: the reason does not hang on a stop command)
    assert crept.status.name == "STALLED" and "LETHAL cell on the arc ahead, and creeping did not" in crept.reason
    passed, *_ = simulate("clutter", robot="jackal", controller="rpp", controller_params={"plan_poses": True})
    assert passed.status.name == "REACHED", passed.reason
