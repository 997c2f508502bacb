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
