"""Maps as benchmark worlds: Moving AI scenarios and listed queries, any mix of
planners, path length against the stored optimum and against Theta*."""

import math

import pytest

from navlab.bench import ExperimentError, load_experiment, run_experiment
from navlab.bench.store import read_rows


@pytest.fixture
def movingai(tmp_path):
    """A 12 x 8 map with a wall (x = 6, rows 0-5) and a scenario file of two
    queries: (1, 1) -> (4, 1), 3 cells straight; (0, 7) -> (11, 7) along the
    open bottom row, 11 cells."""
    rows = ["." * 12 for _ in range(8)]
    rows = [r[:6] + "@" + r[7:] if y < 6 else r for y, r in enumerate(rows)]
    (tmp_path / "room.map").write_text("type octile\nheight 8\nwidth 12\nmap\n" + "\n".join(rows) + "\n")
    (tmp_path / "room.map.scen").write_text("version 1\n0\troom.map\t12\t8\t1\t1\t4\t1\t3.00000000\n"
                                            "0\troom.map\t12\t8\t0\t7\t11\t7\t11.00000000\n")
    return tmp_path


def test_astar_matches_the_grid_optimum_and_theta_star_is_the_reference(movingai):
    # query 0 only (a straight corridor): A* equals the stored optimum, Theta* too
    exp = load_experiment({"name": "m", "worlds": [{"map": str(movingai / "room.map"),
                                                    "scen": str(movingai / "room.map.scen"), "queries": 1}],
                           "planners": ["astar", "theta_star", "rrt_star"], "samplers": ["uniform", "gaussian"],
                           "budget": {"max_iter": 300}, "trials": 2, "seed": 1})
    run = run_experiment(exp, movingai / "out", executor="serial", progress=False)
    by = {c["group"]: c for c in run.summary["cells"]}
    assert set(by) == {"astar / -", "theta_star / -", "rrt_star / uniform", "rrt_star / gaussian"}
    assert by["astar / -"]["vs_optimum"]["max"] == pytest.approx(1.0, abs=1e-6)
    assert by["theta_star / -"]["vs_theta"]["median"] == pytest.approx(1.0)
    rows = list(read_rows(movingai / "out" / "results.jsonl"))
    assert {tuple(r["start"]) for r in rows} == {(1.5, 1.5)} and {tuple(r["goal"]) for r in rows} == {(4.5, 1.5)}
    for r in rows:  # grid rows have no sampler; tree rows one; every path starts and ends exactly
        assert (r["sampler"] == "-") == (r["planner"] in ("astar", "theta_star"))
    assert all(r["success"] and r["cost"] == pytest.approx(3.0, abs=1e-6) for r in rows if r["planner"] == "astar")
    md = (movingai / "out" / "report.md").read_text()
    assert "Path length against the optimum and against Theta*" in md


def test_queries_listed_in_the_experiment_and_trials_cycle_through_them(movingai):
    exp = load_experiment({"worlds": [{"map": str(movingai / "room.map"), "name": "room",
                                       "queries": [[1.5, 1.5, 4.5, 1.5], [0.5, 7.5, 11.5, 7.5]]}],
                           "planners": ["jps"], "trials": 4})
    specs = exp.trial_specs()
    assert [s["query"]["index"] for s in specs] == [0, 1, 0, 1]
    run = run_experiment(exp, movingai / "o2", executor="serial", progress=False, plots=False)
    costs = [r["cost"] for r in run.rows]
    assert costs == pytest.approx([3.0, 11.0, 3.0, 11.0]) and all(r.get("optimum") is None for r in run.rows)


@pytest.mark.parametrize("world, message", [
    ({"map": "nowhere.map", "queries": [[0, 0, 1, 1]]}, "no such map file"),
    ({"map": "ROOM", "queries": []}, "a map has no start or goal"),
    ({"map": "ROOM", "queries": [[1, 2, 3]]}, r"query 0 must be \[start x"),
    ({"map": "ROOM", "scen": "ROOM.scen", "queries": 0}, "positive integer"),
    ({"map": "ROOM", "qeries": 2}, "(?i)did you mean 'queries'"),
    ({"map": "ROOM", "queries": [[0.3, 0.3, 1e300, 4.8]]}, r"query 0 goal x = 1e\+300 is out of range"),
    ({"map": "ROOM", "queries": [[1, 1, 2, 2]], "robot_radius": -1}, "robot_radius must be non-negative"),
])
def test_bad_map_worlds_are_refused_before_anything_runs(movingai, world, message):
    world = {k: (str(movingai / "room.map") + v[4:] if isinstance(v, str) and v.startswith("ROOM") else v)
             for k, v in world.items()}
    with pytest.raises(ExperimentError, match=message):
        load_experiment({"worlds": [world], "planners": ["astar"]})


def test_a_resolution_for_a_grid_planner_on_a_map_is_refused_before_any_trial(movingai):
    """docs/bench.md's maps example gave params: {resolution: 0.05}: every astar and theta_star trial was
    an ERROR row ("a map is planned on its own cells") (review, session 22)."""
    world = {"map": str(movingai / "room.map"), "name": "room", "queries": [[1.5, 1.5, 4.5, 1.5]]}
    with pytest.raises(ExperimentError, match="resolution: world 'room' is a map, planned on its own cells"):
        load_experiment({"worlds": [world], "planners": ["astar"], "params": {"resolution": 0.05}})
    for planner in ("hybrid_astar", {"name": "rrt_star", "motion": "dubins"}):  # (attack, session 22)
        with pytest.raises(ExperimentError, match="resolution: world 'room' is a map"):
            load_experiment({"worlds": [world], "planners": [planner], "params": {"resolution": 0.05},
                             "budget": {"max_iter": 100}})
    exp = load_experiment({"worlds": [world], "planners": ["astar", "rrt_star"], "params": {"expand_dis": 2.0},
                           "budget": {"max_iter": 100}, "trials": 1})
    assert len(exp.cells()) == 2


@pytest.mark.parametrize("setting, message", [({"heading_bins": 3}, "heading_bins must be a whole number"),
                                              ({"distance_table": "yes"}, "distance_table must be true or false"),
                                              ({"turning_radius": -1}, "turning_radius must be positive")])
def test_hybrid_astars_bad_settings_on_a_map_world_are_refused_before_any_trial(movingai, setting, message):
    """On a geometric world they were (attack, session 22); on a map world each trial was an ERROR row
    (review, session 22)."""
    world = {"map": str(movingai / "room.map"), "name": "room", "queries": [[1.5, 1.5, 4.5, 1.5]]}
    with pytest.raises((ExperimentError, ValueError), match=message):
        load_experiment({"worlds": [world], "planners": [{"name": "hybrid_astar", **setting}]})
    load_experiment({"worlds": [world], "planners": [{"name": "hybrid_astar", "heading_bins": 36}], "trials": 1})


def test_a_map_named_as_a_plain_world_says_how_to_give_its_queries(movingai):
    with pytest.raises(ExperimentError, match="is a map, which has no start or goal: give it as"):
        load_experiment({"worlds": [str(movingai / "room.map")], "planners": ["astar"]})


def test_the_map_suite_needs_the_movingai_folder(monkeypatch, tmp_path):
    import navlab.bench.suites as suites

    monkeypatch.setattr(suites, "_movingai_candidates", lambda: [tmp_path / "missing"])
    with pytest.raises(ExperimentError, match=r"Moving AI maps are not in ../shared/data/movingai"):
        load_experiment("grid-vs-rrt-maps")


def test_the_map_suite_reads_the_shared_maps():
    from navlab.bench.suites import MOVINGAI_QUERIES, movingai_dir

    try:
        movingai_dir()
    except ExperimentError:
        pytest.skip("no ../shared/data/movingai here")
    exp = load_experiment("grid-vs-rrt-maps")
    assert len(exp.worlds) == 5 and all(len(exp.maps[w]["queries"]) == MOVINGAI_QUERIES for w in exp.worlds)
    assert all(q["optimum"] > 0 for w in exp.worlds for q in exp.maps[w]["queries"])
    assert math.isclose(exp.maps["arena"]["queries"][0]["start"][0] % 1, 0.5)


def test_the_terminal_says_over_which_queries_a_map_suites_costs_are(tmp_path):
    """The command's per-cell lines give cost means over the queries all cells of a map solved (issue 19), and
    say so with the counts, as the report does."""
    from click.testing import CliRunner

    from navlab.bench.suites import movingai_dir
    from navlab.cli import main

    try:
        movingai_dir()
    except ExperimentError:
        pytest.skip("no ../shared/data/movingai here")
    res = CliRunner().invoke(main, ["bench", "--suite", "grid-vs-rrt-maps", "--trials", "2", "--max-iter", "300",
                                    "--out", str(tmp_path / "out"), "--no-plots"])
    assert res.exit_code == 0, res.output
    line = next(x for x in res.output.splitlines() if x.startswith("cost and time below are over the queries"))
    import json

    compared = json.loads((tmp_path / "out" / "summary.json").read_text())["compared"]
    assert len(compared) == 5
    assert all(f"{world} {s['common']} of {s['queries']}" in line for world, s in compared.items())
    assert compared["maze512-32-9"]["common"] < 2  # 300 RRT* iterations reach the goal on the shortest query only


def test_a_scenario_cell_outside_the_map_is_named_before_any_trial(tmp_path):
    """A .scen row with a 400-digit start cell reached numpy as an object array: an internal
    UFuncTypeError (an attack on the command, session 17)."""
    from navlab.bench.experiment import ExperimentError, load_experiment

    (tmp_path / "ok.map").write_text("type octile\nheight 6\nwidth 8\nmap\n" + "........\n" * 6)
    (tmp_path / "far.scen").write_text("version 1\n" + f"0\tok.map\t8\t6\t{'9' * 400}\t0\t7\t5\t8.2\n")
    (tmp_path / "e.yaml").write_text("worlds: [{map: ok.map, scen: far.scen, queries: 1}]\nplanners: [astar]\n"
                                     "trials: 1\n")
    with pytest.raises(ExperimentError, match="scenario 1's start cell with a coordinate of over 20 digits is "
                                              "outside the 8x6 map"):
        load_experiment(tmp_path / "e.yaml")
