"""move_base around the DWA: its global planner is navfn (checked against independent truth in
test_dwa_navfn.py); with a sensed costmap and ``planner_frequency`` > 0 it is move_base that plans."""

import math

import numpy as np

from navlab.control import make_controller
from navlab.control.move_base_navfn import plan_navfn
from navlab.world.costmap import Costmap
from navlab.world.footprint import Footprint

JACKAL = Footprint.polygon([[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]])
RES = 0.05


def _band_costmap(band_cost: int) -> Costmap:
    """80 × 60 free cells crossed by a 4-cell band of ``band_cost`` at x = 1.5–1.7 m, open above y = 1 m."""
    costs = np.zeros((60, 80), np.uint8)
    costs[:20, 30:34] = band_cost
    return Costmap(costs, RES)


def test_move_base_plans_with_navfn():
    costmap = _band_costmap(200)
    start, goal = np.array((0.5, 0.5, 0.0)), np.array((3.5, 0.5))
    dwa = make_controller("dwa_barn", layers="static")
    dwa.reset(goal)
    dwa.set_costmap(costmap, JACKAL)
    dwa.replan(0.0, start)
    assert np.array_equal(dwa.path, plan_navfn(costmap, start, goal, allow_unknown=False))
    cells = np.rint(dwa.path / RES).astype(int)  # navfn's nearest cells
    assert (costmap.costs[cells[:, 1], cells[:, 0]] == 0).all()  # round the band (navfn's 4.2 × per cell)


def test_a_sensed_costmap_is_planned_on_by_move_base_at_its_frequency():
    dwa = make_controller("dwa_barn")  # layers='sensor', planner_frequency 20 Hz
    assert dwa.replan_interval == math.inf  # the costmap feed leaves the global plan to move_base
    costmap = _band_costmap(0)
    dwa.reset(costmap.cell_to_world([(70, 30)])[0])
    dwa.set_costmap(costmap, JACKAL)
    pose = np.array((*costmap.cell_to_world([(5, 30)])[0], 0.0))
    for k in range(10):
        dwa.command(k * 0.05, pose)
    assert dwa.stats["replans"] == 10
    slow = make_controller("dwa_barn", planner_frequency=5.0)
    slow.reset(dwa.goal)
    slow.set_costmap(costmap, JACKAL)
    for k in range(10):
        slow.command(k * 0.05, pose)
    assert slow.stats["replans"] == 3  # at 0, 0.2 and 0.4 s
    assert make_controller("dwa", layers="sensor").replan_interval == 1.0  # planner_frequency 0: the feed's


def test_the_paths_move_base_plans_are_the_runs_replans_and_the_robot_follows_the_last():
    """DWA's global planner replaces the path the run started with (here after its local planner failed):
    those paths are the result's replans (drawn, and counted by navlab sim), and the robot follows them.
    The run had reported only its first path, 3.1 m from where the robot drove (newcomer, session 29)."""
    from click.testing import CliRunner

    from navlab.cli import main
    from navlab.sim.polyline import distance_to_polyline
    from navlab.sim.runner import simulate

    result, _, sim = simulate("clutter", robot="diff", controller="dwa")
    assert result.status.name == "REACHED" and sim.controller.stats["replans"] >= 1
    assert len(result.replans) == result.replan_count == sim.controller.stats["replans"]
    assert all(np.allclose(path[-1], result.goal, atol=0.05) for path in result.replans)
    last = result.replans[-1]
    since = int(np.argmin(np.hypot(*(result.true_poses[:, :2] - last[0]).T)))  # where it was planned from
    assert np.max(distance_to_polyline(result.true_poses[since:, :2], last)) < 0.5
    assert result.tracking_error() > 2.0  # from the first path, which the robot left
    out = CliRunner().invoke(main, ["sim", "clutter", "--robot", "diff", "--controller", "dwa"]).output
    assert (f"planned a {len(result.path)}-waypoint path and replanned {len(result.replans)} times (the last plan "
            f"{len(last)} waypoints); the farthest from the first path: {result.tracking_error():.3f} m") in out


def test_a_run_keeps_move_bases_last_plans_and_counts_them_all():
    """At 20 Hz (dwa_barn) every plan kept took 50 MB over a 341 s run (review, session 29): the run keeps
    the last KEPT_PLANS and counts them all; the costmap feed plans nothing of its own (replan_interval is
    infinite: it planned at t = 0, a path replaced in the same cycle, counted as a replan)."""
    from navlab.control.dwa import KEPT_PLANS
    from navlab.sim.runner import simulate

    result, _, sim = simulate("clutter", robot="diff", controller="dwa_barn", max_time=8.0)
    assert sim.costmap_feed.paths == [] and sim.controller.replan_interval == math.inf
    assert result.replan_count == sim.controller.stats["replans"] == result.steps > KEPT_PLANS  # one per cycle
    assert len(result.replans) == KEPT_PLANS
    assert np.array_equal(result.replans[-1], sim.controller.path)  # the last one is the path it ended on
