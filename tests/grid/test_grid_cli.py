import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from navlab.cli import main

# shared/data/movingai beside the checkout (main and helpers' worktrees sit at different depths)
DATA = next((p / "shared" / "data" / "movingai" for p in Path(__file__).resolve().parents
             if (p / "shared" / "data" / "movingai").is_dir()), Path("shared/data/movingai"))
# a clone without ../shared (a newcomer's) skips the tests that read it, as tests/grid/test_movingai.py does
needs_data = pytest.mark.skipif(not DATA.is_dir(), reason=f"Moving AI data not found at {DATA}")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_maze_then_plan(tmp_path):
    out = tmp_path / "maze.yaml"
    res = run("grid", "maze", "--cells", 10, 10, "--seed", 4, "--out", out)
    assert res.exit_code == 0 and (tmp_path / "maze.pgm").exists()
    res = run("grid", "plan", out, "--world", "--start", 0.3, 0.3, "--goal", 4.8, 4.8, "--smooth",
              "--inflate", 0.02, "--json", "--plot", tmp_path / "p.png")
    data = json.loads(res.output)
    assert res.exit_code == 0 and data["status"] == "EXACT" and data["stats"]["raw_cost_cells"] >= data["stats"]["cost_cells"]
    assert (tmp_path / "p.png").read_bytes()[:4] == b"\x89PNG"


@needs_data
def test_scen_reports_matches():
    res = run("grid", "scen", DATA / "arena.map.scen", "--algorithm", "jps")
    assert res.exit_code == 0 and "160 match, 0 do not" in res.output
    assert "median" in res.output and "p95" in res.output
    res = run("grid", "scen", DATA / "den312d.map.scen", "--every", 10, "--json")
    assert json.loads(res.output)["summary"]["mismatches"] == 0


@needs_data
def test_settings_an_algorithm_does_not_use_are_noted_not_dropped_silently():
    """(newcomer run, session 19: jps with --heuristic manhattan --weight 3 exited 0 without a word, and
    grid scen named theta_star's search 'theta_star (octile)')"""
    query = ("--start", 1, 11, "--goal", 12, 35)
    res = run("grid", "plan", DATA / "arena.map", *query, "--algorithm", "jps", "--heuristic", "manhattan",
              "--weight", 3, "--json")
    assert res.exit_code == 0 and json.loads(res.stdout)["params"]["heuristic"] == "octile"
    assert res.stderr.splitlines() == [
        "note: jps searches with its own heuristic (octile): --heuristic manhattan is not used",
        "note: jps searches unweighted (of the grid planners only astar takes a weight): --weight 3 is not used"]
    res = run("grid", "plan", DATA / "arena.map", *query, "--algorithm", "dijkstra", "--heuristic", "euclidean")
    assert res.stderr == "note: dijkstra searches with no heuristic: --heuristic euclidean is not used\n"
    for given in (("--algorithm", "astar", "--heuristic", "manhattan", "--weight", 3), ("--algorithm", "jps"),
                  ("--algorithm", "theta_star", "--heuristic", "euclidean")):
        assert run("grid", "plan", DATA / "arena.map", *query, *given).stderr == ""
    res = run("grid", "scen", DATA / "arena.map.scen", "--algorithm", "theta_star", "--heuristic", "manhattan",
              "--limit", 5)
    assert res.stdout.startswith("arena: 5 scenarios, theta_star (euclidean),") and "--heuristic manhattan" in res.stderr
    summary = json.loads(run("grid", "scen", DATA / "arena.map.scen", "--algorithm", "dijkstra", "--limit", 5,
                             "--json").stdout)["summary"]
    assert summary["heuristic"] == "none"
    # navlab plan's --param, and the params a result reports (they said heuristic 'manhattan', weight 3)
    res = run("plan", DATA / "arena.map", "--planner", "jps", "--start", 1.5, 11.5, "--goal", 12.5, 35.5,
              "--param", "heuristic=manhattan", "--param", "weight=3", "--json")
    assert json.loads(res.stdout)["params"]["heuristic"] == "octile" and json.loads(res.stdout)["params"]["weight"] == 1
    assert res.stderr.splitlines() == [
        "note: jps searches with its own heuristic (octile): --param heuristic=manhattan is not used",
        "note: jps searches unweighted (of the grid planners only astar takes a weight): --param weight=3 is not used"]
    res = run("plan", DATA / "arena.map", "--planner", "astar", "--start", 1.5, 11.5, "--goal", 12.5, 35.5,
              "--param", "heuristic=manhattan", "--param", "weight=3", "--json")
    assert json.loads(res.stdout)["params"]["weight"] == 3 and res.stderr == ""


@needs_data
def test_heuristic_none_is_accepted_and_a_result_lists_every_setting_it_ran_with():
    """(newcomer run, session 19: Dijkstra's params said heuristic 'none', but heuristic=none was refused;
    navlab plan --json listed only the settings given, and a weight as 3 when given, 1.0 by default)"""
    import navlab
    from navlab.grid import load_map, plan

    grid = load_map(DATA / "den312d.map")
    none = plan(grid, (10, 11), (21, 70), heuristic="none")
    dijkstra = plan(grid, (10, 11), (21, 70), algorithm="dijkstra")
    octile = plan(grid, (10, 11), (21, 70))
    assert none.cost == dijkstra.cost == octile.cost and none.params["heuristic"] == "none"
    assert none.stats["expanded"] == dijkstra.stats["expanded"] > octile.stats["expanded"]  # no guidance
    assert plan(grid, (10, 11), (21, 70), heuristic="none", weight=5).params["weight"] == 1.0
    query = ("--start", 10.5, 11.5, "--goal", 21.5, 70.5)
    res = run("plan", DATA / "den312d.map", "--planner", "astar", *query, "--param", "heuristic=none",
              "--param", "weight=3", "--json")
    assert res.exit_code == 0 and json.loads(res.stdout)["params"]["weight"] == 1.0
    assert res.stderr == ("note: astar with heuristic none searches unweighted (a weight scales the heuristic): "
                          "--param weight=3 is not used\n")
    res = run("grid", "scen", DATA / "arena.map.scen", "--heuristic", "none", "--limit", 5)
    assert res.stdout.startswith("arena: 5 scenarios, astar (none),") and "5 match, 0 do not" in res.stdout
    res = run("grid", "plan", DATA / "den312d.map", "--start", 10, 11, "--goal", 21, 70, "--algorithm", "dijkstra",
              "--heuristic", "none")
    assert res.exit_code == 0 and res.stderr == ""
    defaults = navlab.plan(DATA / "den312d.map", planner="astar", start=(10.5, 11.5), goal=(21.5, 70.5)).params
    assert {k: defaults[k] for k in ("heuristic", "connectivity", "smooth", "weight", "allow_unknown")} == {
        "heuristic": "octile", "connectivity": 8, "smooth": False, "weight": 1.0, "allow_unknown": False}
    assert plan(grid, (10, 11), (21, 70), smooth=True, smooth_method="supercover").params["smooth_method"] == \
        "supercover"  # (newcomer run, session 20: grid.plan's params left it out)
    listed = run("list").stdout
    assert "heuristic='none', connectivity=8" in listed and "smooth_method" not in listed  # navlab plan's settings
    given = navlab.plan(DATA / "den312d.map", planner="astar", start=(10.5, 11.5), goal=(21.5, 70.5), weight=3).params
    assert type(given["weight"]) is float and given["weight"] == 3.0


@needs_data
def test_a_weight_past_greedy_is_refused_and_a_refused_setting_gets_no_note():
    """(final newcomer run, session 19: at weight 1e306 weight × heuristic overflowed to inf and A* returned
    665.6 against the optimum's 392.8; jps given --weight -1 printed 'jps ran unweighted', then the error)"""
    import navlab
    from navlab.grid import load_map, plan

    res = run("grid", "plan", DATA / "Berlin_1_256.map", "--start", 5, 5, "--goal", 250, 250, "--weight", 1e306)
    assert res.exit_code == 2 and res.stderr.startswith("Error: weight must be at most 1e+06")
    with pytest.raises(ValueError, match="weight must be at most 1e"):
        plan(load_map(DATA / "Berlin_1_256.map"), (5, 5), (250, 250), weight=1e7)
    with pytest.raises(ValueError, match="weight must be at most 1e"):
        navlab.plan(DATA / "Berlin_1_256.map", planner="astar", start=(5.5, 5.5), goal=(250.5, 250.5), weight=1e7)
    greedy = plan(load_map(DATA / "Berlin_1_256.map"), (5, 5), (250, 250), weight=1e6)
    assert greedy.success and greedy.cost < 1e6  # the largest weight still searches
    res = run("grid", "plan", DATA / "den312d.map", "--start", 10, 11, "--goal", 21, 70, "--algorithm", "jps",
              "--weight", -1)
    assert res.exit_code == 2 and "note:" not in res.stderr and "weight must be" in res.stderr
    res = run("plan", DATA / "den312d.map", "--planner", "dijkstra", "--start", 10.5, 11.5, "--goal", 21.5, 70.5,
              "--param", "weight=nan")
    assert res.exit_code == 2 and "note:" not in res.stderr


@needs_data
def test_scen_prints_the_length_at_the_stored_optimums_digits():
    """(a row read 'stored 20.313709, got 20.313708 (EXACT, match, ...)': the file stores 20.31370850)"""
    res = run("grid", "scen", DATA / "random-32-32-10-random-1.scen", "--algorithm", "dijkstra")
    worst = [line for line in res.stdout.splitlines() if line.startswith("    #")]
    assert res.exit_code == 0 and len(worst) == 5
    # what the rows rank by, and what a match's difference is (newcomer run, session 29)
    assert "  worst 5: failed first, then by |length - stored optimum| (cells (x, y); a match is within the " \
           "stored value's rounding):" in res.stdout
    for line in worst:
        stored, got = line.split("stored ")[1].split(" (")[0].split(", got ")
        assert stored == got and len(stored.split(".")[1]) == 8, line


def test_a_missing_map_is_clear(tmp_path):
    res = run("grid", "plan", tmp_path / "none.yaml", "--start", 0, 0, "--goal", 1, 1)
    assert res.exit_code == 2 and "no such file" in res.output


@needs_data
def test_bad_inputs_are_clear():
    res = run("grid", "plan", DATA / "arena.map", "--start", 0, 0, "--goal", 5, 5)
    assert res.exit_code == 1 and "INVALID_START" in res.output
    res = run("grid", "plan", DATA / "arena.map", "--start", 0.5, 0, "--goal", 5, 5)
    assert res.exit_code == 2 and "--world" in res.output


def write_scen(tmp_path, rows, blocked_cell=(2, 1)):
    """A 6x4 open map with one blocked cell, and a scenario file of (start, goal, optimum) rows."""
    lines = ["." * 6 for _ in range(4)]
    x, y = blocked_cell
    lines[y] = lines[y][:x] + "@" + lines[y][x + 1:]
    (tmp_path / "tiny.map").write_text("type octile\nheight 4\nwidth 6\nmap\n" + "\n".join(lines) + "\n")
    text = "version 1\n" + "".join(f"0\ttiny.map\t6\t4\t{s[0]}\t{s[1]}\t{g[0]}\t{g[1]}\t{opt}\n"
                                     for s, g, opt in rows)
    (tmp_path / "tiny.map.scen").write_text(text)
    return tmp_path / "tiny.map.scen"


def test_scen_with_blocked_or_outside_cells_counts_them(tmp_path):
    scen = write_scen(tmp_path, [((0, 0), (5, 0), 5), ((2, 1), (5, 0), 3), ((0, 0), (9, 9), 1), ((0, 0), (0, 3), 3)])
    res = run("grid", "scen", scen)
    assert res.exit_code == 1 and "Traceback" not in res.output
    assert "2 match, 0 do not, 2 invalid" in res.output
    assert "INVALID_GOAL 1" in res.output and "INVALID_START 1" in res.output
    data = json.loads(run("grid", "scen", scen, "--json").output)
    assert data["summary"]["statuses"] == {"EXACT": 2, "INVALID_START": 1, "INVALID_GOAL": 1}
    assert [r["time_s"] is not None for r in data["rows"]] == [True] * 4


def test_scen_prints_a_summary_not_every_mismatch(tmp_path):
    rows = [((0, 0), (5, 0), 99 + k) for k in range(12)]  # every stored optimum is wrong
    res = run("grid", "scen", write_scen(tmp_path, rows))
    assert res.exit_code == 1 and "0 match, 12 do not" in res.output
    listed = [line for line in res.output.splitlines() if line.strip().startswith("#")]
    assert len(listed) == 5 and all("MISMATCH" in line for line in listed)
    assert "#11:" in listed[0]  # the largest error first


def test_scen_theta_star_is_bounded_by_the_octile_optimum(tmp_path):
    # (0,3) -> (5,0) on an open map: octile 3·√2 + 2 = 6.2426; any-angle √34 = 5.831
    scen = write_scen(tmp_path, [((0, 3), (5, 0), 6.24264069)], blocked_cell=(5, 3))
    assert run("grid", "scen", scen).exit_code == 0
    res = run("grid", "scen", scen, "--algorithm", "theta_star", "--json")
    row = json.loads(res.output)["rows"][0]
    assert res.exit_code == 0 and row["match"] and row["exact_length"] < 6.24 and row["excess"] < 0


@needs_data
def test_scen_theta_star_matches_every_arena_scenario():
    res = run("grid", "scen", DATA / "arena.map.scen", "--algorithm", "theta_star")
    assert res.exit_code == 0 and "160 match, 0 do not" in res.output and "any-angle length" in res.output


def test_progress_is_reported_per_scenario_and_per_carved_cell(tmp_path):
    from navlab.grid import make_maze
    from navlab.grid.scen_runner import run_scenarios

    scen = write_scen(tmp_path, [((0, 0), (5, 0), 5)] * 3)
    done = []
    run_scenarios(scen, progress=done.append)
    assert done == [1, 2, 3]
    carved = []
    make_maze(40, 30, progress=carved.append)
    assert carved == [1024, 1200]  # every 1024 cells and at the end


@pytest.mark.parametrize("radius", ["-1", "nan"])
def test_a_bad_robot_radius_is_named_by_its_flag(tmp_path, radius):
    """(it said "inflation radius", OccupancyGrid.inflate's name for it: second attack run, session 18)"""
    from navlab.grid import OccupancyGrid
    from navlab.grid.mapio import save_map

    save_map(OccupancyGrid(np.zeros((8, 8), bool), resolution=0.1), tmp_path / "open.yaml")
    res = run("grid", "plan", str(tmp_path / "open.yaml"), "--start", "0", "0", "--goal", "7", "4",
              "--robot-radius", radius)
    words = f"Invalid value for '--robot-radius' / '--inflate': '{radius}' is not a finite number of at least 0"
    assert res.exit_code == 2 and f"Error: {words}" in res.output


def test_a_cell_is_echoed_as_written(tmp_path):
    """(newcomer run, session 19: --start was parsed as a float, so cell 2**63 - 1 came back as 2**63)"""
    out = tmp_path / "maze.yaml"
    assert run("grid", "maze", "--cells", 4, 4, "--out", out).exit_code == 0
    res = run("grid", "plan", out, "--start", 2**63 - 1, 0, "--goal", 1, 1)
    assert res.exit_code == 1 and f"start cell ({2**63 - 1}, 0) is outside" in res.stdout
    res = run("grid", "plan", out, "--start", 10**30, 0, "--goal", 1, 1)
    assert res.exit_code == 1 and f"start cell ({10**30}, 0) is outside" in res.stdout
    for start, message in (("1.5", "cells are integers; use --world for metres, got 1.5 2"),
                           ("nan", "must be finite numbers, got nan 2"), ("x", "'x' is not a number")):
        res = run("grid", "plan", out, "--start", start, 2, "--goal", 1, 1)
        assert res.exit_code == 2 and message in res.stderr


@pytest.mark.parametrize("total, shown", [(0.0042, "total 4.200 ms"), (0.9994, "total 999.400 ms"),
                                          (1.0, "total 1.000 s"), (2.5, "total 2.500 s")])
def test_scen_report_gives_the_total_in_ms_below_a_second(total, shown):
    """(newcomer check, session 20: five small queries printed "total 0.000 s")"""
    from navlab.cli.grid import scen_report

    summary = {"map": "arena", "scenarios": 5, "algorithm": "astar", "heuristic": "octile", "comparison": "exact",
               "matches": 5, "mismatches": 0, "invalid": 0, "statuses": {"EXACT": 5}, "time_median_ms": 0.03,
               "time_p95_ms": 0.04, "time_total_s": total, "worst": []}
    assert scen_report(summary).splitlines()[2] == f"  time per query: median 0.030 ms, p95 0.040 ms, {shown}"


def test_a_scenario_file_name_is_cut_to_one_short_line():
    """(attack, session 21: a 60 000-character name printed in full, one with newlines on 5 001 lines)"""
    for name in ("é" * 60_000 + ".scen", "a\nb" * 5000 + ".scen"):
        res = run("grid", "scen", name)
        assert res.exit_code == 2 and res.output.count("\n") == 1 and len(res.output) < 800, res.output[:300]
        assert "characters): no such file" in res.output


def test_a_weighted_path_is_said_to_be_possibly_longer_than_the_shortest():
    """(newcomer check, session 21: EXACT beside a weight-3 path of 67.46 cells, where the shortest is 51.01, read
    as the shortest)"""
    query = ("--start", 1, 11, "--goal", 40, 40)
    res = run("grid", "plan", DATA / "arena.map", *query, "--weight", 3)
    assert res.exit_code == 0 and ("  weighted A* (weight 3): at most 3 times the shortest path's length, usually "
                                   "far less (weight 1 finds the shortest)\n") in res.stdout
    res = run("grid", "plan", DATA / "arena.map", *query)
    assert res.exit_code == 0 and "weighted" not in res.stdout
    res = run("grid", "plan", DATA / "arena.map", *query, "--weight", 3, "--algorithm", "jps")  # searched unweighted
    assert res.exit_code == 0 and "weighted A*" not in res.stdout
    res = run("grid", "plan", DATA / "arena.map", *query, "--heuristic", "manhattan")  # not admissible on 8
    assert res.exit_code == 0 and "manhattan on 8 connections overestimates a diagonal move" in res.stdout
    res = run("grid", "plan", DATA / "arena.map", *query, "--heuristic", "manhattan", "--connectivity", 4)
    assert res.exit_code == 0 and "overestimates" not in res.stdout  # (exact on 4 connections)


@pytest.mark.parametrize("name", ["m5.pgm", "m3.png", "m4"])
def test_a_maze_written_to_a_name_that_is_not_a_yaml_is_refused_before_it_is_built(name, tmp_path):
    """--out m5.pgm wrote the YAML over its own image (and m3.png, m4: a map nothing reads as one; newcomer,
    session 30)."""
    result = CliRunner().invoke(main, ["grid", "maze", "--cells", "4", "4", "--out", str(tmp_path / name)])
    assert result.exit_code == 2 and "must end in .yaml or .yml" in result.output, result.output
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["nofile.txt", "nofile", "trap"])
def test_a_missing_map_is_said_missing_not_an_unknown_scene(name, tmp_path, monkeypatch):
    """(grid plan nofile.txt listed the built-in scenes, which grid plan does not take: newcomer, session 32)"""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["grid", "plan", name, "--start", "1", "1", "--goal", "2", "2"])
    assert res.exit_code == 2 and res.output.strip() == f"Error: {name}: no such file", res.output
