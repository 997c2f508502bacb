"""The hybrid navigator and the simulator's defaults."""

import pytest

from navlab.sim import SimStatus
from navlab.sim.experiments import hybrid_vs_field
from navlab.sim.runner import default_max_time, simulate
from navlab.world import SCENES


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_default_sim_reaches_the_goal_on_every_built_in_scene(scene):
    result, _, sim = simulate(scene)  # omni3 with the hybrid navigator
    assert result.status is SimStatus.REACHED, result.reason
    assert result.error_true < 0.05 and sim.min_clearance(result) > 0


def test_trap_with_the_omni_robot_needs_the_hybrid():
    plain, _, _ = simulate("trap", controller="potential_field")
    assert plain.status is SimStatus.STALLED
    hybrid, _, _ = simulate("trap", controller="hybrid")
    assert hybrid.status is SimStatus.REACHED


def test_hybrid_reaches_19_of_20_random_cluttered_worlds_where_the_field_does_not():
    rows = hybrid_vs_field(runs=20)
    reached = {c: sum(r["status"] == "REACHED" for r in rows if r["controller"] == c)
               for c in ("potential_field", "hybrid")}
    assert reached["hybrid"] >= 19 and reached["potential_field"] < reached["hybrid"]


def test_default_max_time_scales_with_the_path_length():
    from navlab.control import GotoWaypoint
    from navlab.robots import DiffDrive

    short = default_max_time([[0, 0], [1, 0]], DiffDrive(), GotoWaypoint())
    long = default_max_time([[0, 0], [49, 0]], DiffDrive(), GotoWaypoint())
    assert short == pytest.approx(60 + 4 * 1 / 0.2) and long == pytest.approx(60 + 4 * 49 / 0.2)
