"""``navlab list``: every kind of registered part, each description whole."""

import re

import pytest
from click.testing import CliRunner

import navlab.sim.latency  # noqa: F401 - registers sensor-latency, which navlab list must show
from navlab.bench.executors import EXECUTORS
from navlab.bench.suites import SUITES
from navlab.cli import main
from navlab.cli.listing import KINDS, first_paragraph
from navlab.control.base import CONTROLLERS
from navlab.grid.planner import GRID_ALGORITHMS, HEURISTICS
from navlab.pose_queries import POSE_PLANNERS, TREE_POSE_PLANNERS
from navlab.robots.kinematics import ROBOTS
from navlab.sampling import PLANNERS, SAMPLERS
from navlab.sensors.lidar import NOISE_MODELS
from navlab.sim.experiments import EXPERIMENTS
from navlab.world import SCENES

REGISTRIES = {"planners": PLANNERS, "grid": GRID_ALGORITHMS, "samplers": SAMPLERS, "scenes": SCENES,
              "controllers": CONTROLLERS, "robots": ROBOTS, "lidar": NOISE_MODELS, "suites": SUITES,
              "executors": EXECUTORS, "experiments": EXPERIMENTS}


def listing(*args):
    result = CliRunner().invoke(main, ["list", *args])
    assert result.exit_code == 0, result.output
    return result.output


def entries(text):
    """name → its description, unwrapped (the lines up to the parameters or the next name)."""
    out, name = {}, None
    for line in text.splitlines():
        m = re.match(r"  (\S+) +(.*)", line)
        if m and not line.startswith(" " * 23):
            name = m.group(1)
            out[name] = [m.group(2)]
        elif name and line.startswith(" " * 23):
            out[name].append(line.strip())
    return {k: " ".join(v) for k, v in out.items()}


def test_every_kind_has_a_registry_checked_here():
    assert set(KINDS) == set(REGISTRIES) | {"pose"}  # pose planners: test_pose_planners_have_their_own_kind


def test_pose_planners_have_their_own_kind():
    pose = entries(listing("pose"))
    assert set(POSE_PLANNERS) <= set(pose) and not set(POSE_PLANNERS) & set(entries(listing("grid")))
    assert all(name in pose["(trees)"] for name in TREE_POSE_PLANNERS) and "motion=reeds_shepp" in pose["(trees)"]
    assert "motion='reeds_shepp'" in pose["hybrid_astar"] and "heading_bins=72" in pose["hybrid_astar"]


@pytest.mark.parametrize("kind", sorted(REGISTRIES))
def test_lists_every_entry_of_each_kind(kind):
    whole = listing()
    one = listing(kind)
    assert one.splitlines()[0] in whole
    found = entries(one)
    for name in REGISTRIES[kind]:
        entry = REGISTRIES[kind].get(name)
        own = getattr(entry, "registered_name", name)  # an alias is listed under its entry's own name
        assert own in found, (name, one)
        text = entry if isinstance(entry, str) else first_paragraph(entry.__doc__)
        assert found[own].startswith(text), (name, found[own])  # the whole first paragraph
        if own != name:
            assert "alias: " in found[own] and name in found[own], (name, found[own])


def test_informed_rrt_star_description_is_not_cut():
    assert "from the informed ellipse |x − start| + |x − goal| ≤ c." in entries(listing("planners"))["informed_rrt_star"]


def test_heuristics_listed():
    assert all(h in listing("grid") for h in HEURISTICS)


def test_the_costmap_settings_are_listed_with_the_defaults_a_query_uses():
    """astar's costmap=true was in no listing (newcomer check, session 16); the defaults shown are the ones
    a costmap query reports it used."""
    import navlab

    used = navlab.plan("trap", planner="astar", costmap=True).params
    text = " ".join(listing("grid").split())
    assert "(costmap) astar with costmap=true plans on a Nav2-style costmap" in text
    for key in ("inflation_radius", "cost_scaling_factor", "cost_travel_multiplier"):
        assert f"{key}={used[key]!r}" in text


def test_first_paragraph():
    assert first_paragraph("One\n    two.\n\n    Later.") == "One two."
    assert first_paragraph(None) == "" and first_paragraph("\n\n  Only.") == "Only."


def test_unknown_kind_is_a_usage_error():
    result = CliRunner().invoke(main, ["list", "planers"])
    assert result.exit_code == 2 and "Traceback" not in result.output


@pytest.mark.parametrize("typo, kind", [("poses", "pose"), ("planner", "planners"), ("scene", "scenes")])
def test_a_misspelt_kind_gets_did_you_mean(typo, kind):
    result = CliRunner().invoke(main, ["list", typo])
    assert result.exit_code == 2 and f"Did you mean '{kind}'?" in result.output
    assert result.output.count("Invalid value") == 1 and len(result.output.strip().splitlines()) == 1


def test_a_suite_whose_data_is_missing_is_listed_not_fatal(monkeypatch, tmp_path):
    """Without ../shared beside the checkout, `navlab list` stopped at the suites with the Moving AI
    error and exit 2 (newcomer check, session 16): the suite is listed with what it lacks."""
    import navlab.bench.suites as suites

    monkeypatch.setattr(suites, "_movingai_candidates", lambda: [tmp_path / "absent"])
    text = listing()
    assert "not runnable here: the Moving AI maps are not in" in text
    assert "bench executors" in text or "executors" in text  # the kinds after the suites are listed too
    assert "not runnable here" not in listing("planners")
