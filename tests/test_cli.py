import json
import shlex

import pytest
from click.testing import CliRunner

from navlab.cli import main


@pytest.fixture
def run():
    runner = CliRunner()
    return lambda *args: runner.invoke(main, list(args), catch_exceptions=False)


def test_plan_json_has_everything(run):
    res = run("plan", "squarefield", "--planner", "rrt_star", "--sampler", "integration",
              "--max-iter", "400", "--seed", "3", "--param", "expand_dis=1.5", "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.output)
    assert out["status"] == "EXACT" and out["cost"] > 0 and len(out["path"]) >= 2
    assert out["params"]["expand_dis"] == 1.5 and out["params"]["seed"] == 3
    assert out["params"]["weights"]["gaussian"] == 0.3
    assert {"iterations", "nodes", "collision_checks", "time_s", "warmup_s"} <= set(out["stats"])
    assert "cost_trace" not in out["stats"]  # a person reads this; the trace is --trace's
    traced = json.loads(run("plan", "squarefield", "--max-iter", "400", "--json", "--trace").output)
    assert len(traced["stats"]["cost_trace"]) == 400


def test_plan_trace_without_json_is_refused():
    res = CliRunner().invoke(main, ["plan", "squarefield", "--max-iter", "50", "--trace"])
    assert res.exit_code == 2
    assert "--trace adds the cost trace to the --json output: give it with --json" in res.output
    grid = CliRunner().invoke(main, ["plan", "squarefield", "--planner", "astar", "--json", "--trace"])
    assert grid.exit_code == 2 and "--trace: astar keeps no per-iteration cost trace" in grid.output


@pytest.fixture(scope="module")
def maze(tmp_path_factory):
    """The issue's maze: `navlab grid maze --cells 10 10 --seed 1 --out maze.yaml`."""
    path = tmp_path_factory.mktemp("maze") / "maze.yaml"
    res = CliRunner().invoke(main, ["grid", "maze", "--cells", "10", "10", "--seed", "1", "--out", str(path)])
    assert res.exit_code == 0, res.output
    return str(path)


def test_a_maze_names_the_cells_to_plan_between_and_that_command_plans_across_it(tmp_path):
    """(newcomer, session 30: the map gave no free coordinates to plan between)"""
    path = tmp_path / "my maze.yaml"
    res = CliRunner().invoke(main, ["grid", "maze", "--cells", "3", "7", "--cell-size", "0.33", "--seed", "2",
                                    "--out", str(path)])
    assert res.exit_code == 0, res.output
    line = res.output.splitlines()[-1]
    # cell (i, j)'s centre is wall/2 + (i + 0.5) * cell_size: 0.05 + 0.165 and 0.05 + 6.5 * 0.33
    assert line.startswith("corner cells' centres: (0.215, 0.215) and (0.875, 2.195) m: navlab grid plan ")
    args = shlex.split(line.partition(": navlab ")[2])
    assert args[:2] == ["grid", "plan"] and args[2] == str(path)
    planned = CliRunner().invoke(main, args + ["--json"])
    assert planned.exit_code == 0, planned.output
    assert json.loads(planned.output)["status"] == "EXACT"


@pytest.mark.parametrize("name, size", [("-dash.yaml", ["--cells", "3", "3"]),
                                        ("tiny.yaml", ["--cells", "3", "3", "--cell-size", "1e-6", "--wall", "1e-7",
                                                       "--resolution", "1e-7"])])
def test_the_printed_plan_command_works_for_odd_names_and_tiny_pixels(name, size, tmp_path, monkeypatch):
    """(review, session 31: '-dash.yaml' was read back as an option; a 1e-7 m pixel's centre, to six places,
    was another cell, INVALID_START)"""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["grid", "maze", *size, "--out", name])
    assert res.exit_code == 0, res.output
    args = shlex.split(res.output.splitlines()[-1].partition(": navlab ")[2])
    planned = CliRunner().invoke(main, args + ["--json"])
    assert planned.exit_code == 0, planned.output
    assert json.loads(planned.output)["status"] == "EXACT"


@pytest.mark.parametrize("verb", [["plan", "trap", "--max-iter", "200000"], ["sim", "trap"],
                                  ["grid", "plan", "MAZE", "--start", "6", "6", "--goal", "20", "20"]])
@pytest.mark.parametrize("name, words", [("nodir/p.png", "the folder"), ("out.txt", "no figure format is named .txt")])
def test_a_figure_that_cannot_be_written_is_refused_before_the_work(verb, name, words, tmp_path, monkeypatch):
    """(newcomer, session 31: navlab plan --plot nosuchdir/p.png planned for 11 s, then printed only the
    error, the plan lost)"""
    monkeypatch.chdir(tmp_path)
    if "MAZE" in verb:
        made = CliRunner().invoke(main, ["grid", "maze", "--cells", "3", "3", "--out", "m.yaml"])
        assert made.exit_code == 0, made.output
        verb = [v.replace("MAZE", "m.yaml") for v in verb]
    res = CliRunner().invoke(main, [*verb, "--plot", name])
    assert res.exit_code == 2 and "Invalid value for --plot" in res.output and words in res.output, res.output
    assert len(res.output.strip().splitlines()) == 1 and "EXACT" not in res.output and "REACHED" not in res.output


def test_a_maze_into_a_missing_folder_is_refused_before_it_is_built(tmp_path):
    res = CliRunner().invoke(main, ["grid", "maze", "--out", str(tmp_path / "nodir" / "m.yaml")])
    assert res.exit_code == 2
    assert f"the folder {tmp_path / 'nodir'} does not exist" in res.output and "--out" in res.output


@pytest.mark.parametrize("planner", ["rrt_star", "astar", "theta_star"])
def test_plan_on_a_generated_maze(run, maze, planner):
    res = run("plan", maze, "--planner", planner, "--start", "0.3", "0.3", "--goal", "4.8", "4.8", "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.output)
    assert out["status"] == "EXACT" and out["path"][0] == [0.3, 0.3] and out["path"][-1] == [4.8, 4.8]


def test_plan_on_a_map_prints_the_grid_and_draws_the_map(run, maze, tmp_path):
    png = tmp_path / "maze.png"
    res = run("plan", maze, "--planner", "astar", "--start", "0.3", "0.3", "--goal", "4.8", "4.8",
              "--robot-radius", "0.02", "--plot", str(png))
    assert res.exit_code == 0, res.output
    assert "EXACT" in res.output and "grid 102x102 at 0.05 m" in res.output and "cells expanded" in res.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left behind


@pytest.mark.parametrize("args, text", [
    (("--goal", "4.8", "4.8"), "--start is required"),
    (("--start", "0.3", "0.3"), "--goal is required"),
    (("--start", "0.3", "0.3", "--goal", "4.8", "4.8", "--param", "resolution=0.1"), "resolution"),
    (("--start", "0.3", "0.3", "--goal", "4.8", "4.8", "--planner", "astra"), "Did you mean 'astar'"),
    (("--start", "0.3", "0.3", "--goal", "4.8", "4.8", "--planner", "jps", "--param", "max_iter=5"),
     "unknown parameter 'max_iter' for grid planner 'jps'"),
    (("--start", "0.3", "0.3", "--goal", "4.8", "4.8", "--planner", "astar", "--sampler", "gaussian"),
     "draws no samples"),
    (("--start", "0.3", "nan", "--goal", "4.8", "4.8"),
     "Invalid value for '--start': coordinates and headings must be finite"),
])
def test_bad_map_queries_are_one_line_naming_the_flag(maze, args, text):
    res = CliRunner().invoke(main, ["plan", maze, *args])
    assert res.exit_code == 2, res.output
    assert text in res.output and "Traceback" not in res.output
    assert len(res.output.strip().splitlines()) == 1


def test_invalid_goal_on_a_map_names_the_cell(run, maze):
    res = run("plan", maze, "--planner", "astar", "--start", "0.3", "0.3", "--goal", "0.02", "0.32")
    assert res.exit_code == 1 and "INVALID_GOAL" in res.output and "occupied cell (0, 6)" in res.output


def test_a_too_fine_raster_is_refused(run):
    res = CliRunner().invoke(main, ["plan", "trap", "--planner", "astar", "--param", "resolution=0.00001"])
    assert res.exit_code == 2 and "more than 1e+08" in res.output and "Traceback" not in res.output


def test_plan_plot_writes_png(run, tmp_path):
    out = tmp_path / "plan.png"
    res = run("plan", "trap", "--max-iter", "300", "--plot", str(out))
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "plot written" in res.output


def test_plan_world_file(run, tmp_path):
    f = tmp_path / "w.yaml"
    f.write_text("bounds: {x: [0, 5], y: [0, 5]}\nstart: [1, 1]\ngoal: [4, 4]\n")
    res = run("plan", str(f), "--planner", "rrt", "--json")
    assert json.loads(res.output)["status"] == "EXACT"


@pytest.mark.parametrize("args, text", [
    (("plan", "clutr"), "Did you mean 'clutter'"),
    (("plan", "clutter", "--sampler", "gausian"), "Did you mean 'gaussian'"),
    (("plan", "clutter", "--param", "goal_sample_rate=5"), "goal_sample_rate must be a probability"),
    (("plan", "clutter", "--param", "expand_dis"), "expected key=value"),
    (("plan", "missing.yaml"), "no such file"),
    (("plan", "missing.map", "--start", "1", "1", "--goal", "2", "2"), "no such file"),
    (("plan", "trap", "--robot-radius", "-1"), "robot-radius"),
])
def test_bad_input_is_one_clear_line(args, text):
    res = CliRunner().invoke(main, list(args))
    assert res.exit_code == 2 and text in res.output and "Traceback" not in res.output


def test_failed_plan_exits_nonzero(run, tmp_path):
    f = tmp_path / "w.yaml"
    f.write_text("bounds: {x: [0, 5], y: [0, 5]}\nstart: [1, 1]\ngoal: [4, 4]\nrobot_radius: 0.5\n"
                 "obstacles: [{type: circle, center: [4, 4], radius: 0.3}]\n")
    res = run("plan", str(f))
    assert res.exit_code == 1 and "INVALID_GOAL" in res.output and "clearance" in res.output


def test_list_shows_everything(run):
    out = run("list").output
    for name in ("rrt_star", "informed_rrt_star", "growth_ratio_rrt", "integration", "boundary",
                 "pythonrobotics", "trap", "goal_sample_rate=0.05"):
        assert name in out


def test_help_explains(run):
    out = run("plan", "--help").output
    assert "--param" in out and "--plot" in out and "seed" in out


def test_a_point_planner_in_a_world_with_an_outline_says_what_it_ignored():
    """parking names a 4.4 x 1.8 m car and headings: rrt_star's path is for a point, and the CLI says so
    (on stderr, the exit status unchanged); hybrid_astar plans for the outline and says nothing."""
    point = CliRunner().invoke(main, ["plan", "parking", "--max-iter", "500"])
    assert point.exit_code in (0, 1)
    assert "note: parking names a robot outline and headings" in point.stderr
    assert "--planner hybrid_astar" in point.stderr and "note:" not in point.stdout
    plain = CliRunner().invoke(main, ["plan", "trap", "--max-iter", "500"])
    assert "note:" not in plain.stderr  # trap names no outline


def test_a_heading_beyond_two_pi_gets_a_degrees_hint_and_is_still_taken():
    res = CliRunner().invoke(main, ["plan", "trap", "--max-iter", "200", "--goal", "16", "6", "180", "--json"])
    assert res.stderr.count("note: goal theta 180 is beyond ±2π: headings are radians (180° would be 3.1416 rad; "
                            "it is planned as -2.2124)") == 1
    assert res.exit_code in (0, 1) and json.loads(res.stdout)["status"]
    quiet = CliRunner().invoke(main, ["plan", "trap", "--max-iter", "200", "--goal", "16", "6", "3.14"])
    assert "beyond ±2π" not in quiet.stderr
    huge = CliRunner().invoke(main, ["plan", "trap", "--max-iter", "200", "--goal", "16", "6", "1e300", "--json"])
    assert "note: goal theta 1e+300 is beyond ±2π: headings are radians (it is planned as " in huge.stderr
    assert len(huge.stderr.splitlines()[0]) < 120  # not 1e300 degrees in radians, 300 digits long


@pytest.mark.parametrize("args, status", [
    (["list"], 0), (["plan", "clutter", "--max-iter", "2000", "--json"], 0), (["--help"], 0), (["plan", "--help"], 0),
    # a verb that answers with its status keeps it (a TIMEOUT read by `head -1` ended 0: attack, session 23)
    (["plan", "clutter", "--max-iter", "10", "--json"], 1), (["plan", "one_obstacle", "--goal", "1.5", "0.02"], 1),
    (["sim", "one_obstacle", "--max-time", "1"], 1), (["sim", "one_obstacle", "--goal", "1.5", "0.02"], 1),
    (["sim", "one_obstacle", "--max-time", "60"], 0)])
def test_a_reader_that_went_away_ends_the_command_quietly(args, status):
    # `navlab list | head -1`: the reader closes the pipe; a pipe closed before the first write makes it certain
    import os
    import subprocess
    import sys

    read, write = os.pipe()
    os.close(read)
    try:
        out = subprocess.run([sys.executable, "-m", "navlab", *args], stdout=write, stderr=subprocess.PIPE,
                             timeout=300)
    finally:
        os.close(write)
    # as `ls | head -1` looks to the shell (click alone exits 1), with the answer's own status
    assert (out.returncode, out.stderr) == (status, b"")


def test_a_broken_pipe_that_is_not_stdout_stays_an_error():
    # the pipe is asked, not the exception: a verb's own broken pipe (a worker's) is reported as before
    from unittest import mock

    with mock.patch("navlab.cli.plan.parse_params", side_effect=BrokenPipeError(32, "Broken pipe")):
        result = CliRunner().invoke(main, ["plan", "clutter"])
    assert result.exit_code == 2 and "Broken pipe" in result.output


@pytest.mark.parametrize("args, typo, verb", [(["plna", "clutter"], "plna", "plan"), (["lst"], "lst", "list"),
                                              (["grid", "paln"], "paln", "plan"), (["grid", "mze"], "mze", "maze"),
                                              (["ros", "dmeo"], "dmeo", "demo")])
def test_a_misspelt_verb_gets_did_you_mean(args, typo, verb):
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 2 and f"No such command '{typo}'. Did you mean '{verb}'?" in res.output
    assert len(res.output.strip().splitlines()) == 1


@pytest.mark.parametrize("typo", ["exprot", "exports", "expotr"])
def test_a_misspelt_bench_export_gets_did_you_mean(typo, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no file of that name here
    res = CliRunner().invoke(main, ["bench", typo, "results"])
    assert res.exit_code == 2 and f"no experiment file or suite named '{typo}'" in res.output
    assert "Did you mean 'navlab bench export DIR'?" in res.output


def test_an_unknown_verb_far_from_any_is_named_alone():
    res = CliRunner().invoke(main, ["zzz"])
    assert res.exit_code == 2 and "No such command 'zzz' (see " in res.output and "Did you mean" not in res.output


@pytest.mark.parametrize("args, verbs", [([], ("plan", "list", "grid", "bench", "sim", "ros")),
                                         (["grid"], ("maze", "plan", "scen"))])
def test_a_group_alone_prints_its_help_whole(args, verbs):
    res = CliRunner().invoke(main, args)
    lines = res.output.splitlines()
    assert res.exit_code in (0, 2) and lines[0].startswith("Usage:") and len(lines) > 5  # not folded into one line
    listed = [line.split()[0] for line in lines[lines.index("Commands:") + 1:] if line.startswith("  ")]
    assert set(verbs) <= set(listed)


def test_a_count_flag_takes_a_whole_float_as_param_does(run):
    """--max-iter 1e3 is --max-iter 1000 (as --param max_iter=1e3 and experiment files take it);
    a fraction, zero or a word is one line naming the flag (until session 14 click refused 1e3)."""
    as_float = json.loads(run("plan", "trap", "--max-iter", "1e3", "--json").output)
    as_int = json.loads(run("plan", "trap", "--max-iter", "1000", "--json").output)
    assert as_float["params"]["max_iter"] == 1000 and as_float["cost"] == as_int["cost"]
    for bad, text in (("1.5", "max_iter must be a whole number"), ("0", "max_iter must be a whole number"),
                      ("lots", "'lots' is not a whole number")):
        res = CliRunner().invoke(main, ["plan", "trap", "--max-iter", bad])
        assert res.exit_code == 2 and "--max-iter" in res.output and text in res.output, res.output
        assert "Traceback" not in res.output


def test_every_count_flag_takes_a_whole_float(run):
    """--seed 1e3 is seed 1000, as --max-iter 1e3 is 1000 (newcomer check: click's IntRange called it
    'not a valid integer range'; --cells, --limit, --every, --jobs and --maze-size take the same type)."""
    seeded = json.loads(run("plan", "trap", "--seed", "1e3", "--max-iter", "300", "--json").output)
    assert seeded["params"]["seed"] == 1000
    assert json.loads(run("plan", "trap", "--seed", "1000", "--max-iter", "300", "--json").output)["cost"] == \
        seeded["cost"]


def test_a_file_heading_that_the_query_replaces_gets_no_note(tmp_path):
    """A world file's start heading of 90 (degrees by mistake) was noted, 'planned as 2.0354', when
    --start replaced it, and '--start 2 2 nan' printed that note above its one-line error (newcomer
    check, session 16). The note is for a heading that is planned: the file's when it is kept."""
    world = tmp_path / "w90.yaml"
    world.write_text("bounds: {x: [0, 20], y: [0, 12]}\nstart: [2, 2, 90]\ngoal: [16, 8, 0]\n")
    args = ["plan", str(world), "--planner", "hybrid_astar"]
    replaced = CliRunner().invoke(main, args + ["--start", "2", "2", "0"])
    assert replaced.exit_code == 0 and "note:" not in replaced.stderr
    bad = CliRunner().invoke(main, args + ["--start", "2", "2", "nan"])
    assert bad.exit_code == 2 and len(bad.stderr.splitlines()) == 1
    assert bad.stderr.startswith("Error: Invalid value for '--start': coordinates and headings must be finite, "
                                 "got '2 2 nan'")
    kept = CliRunner().invoke(main, args + ["--start", "2", "2", "--goal", "16", "8", "-270"])
    notes = [line for line in kept.stderr.splitlines() if line.startswith("note:")]
    assert kept.exit_code == 0 and len(notes) == 2 and "start theta 90 " in notes[1] and "goal theta -270 " in notes[0]


def test_the_summary_says_when_goal_bias_wraps_the_sampler():
    """(newcomer run, session 21: --param goal_sample_rate=0.5 printed "rrt_star + uniform", which docs/sampling.md
    says it wraps in goal bias)"""
    from click.testing import CliRunner

    from navlab.cli import main

    out = CliRunner().invoke(main, ["plan", "trap", "--param", "goal_sample_rate=0.5", "--param", "max_iter=300"])
    assert out.output.startswith("trap: rrt_star + uniform with goal bias 0.5, seed 0: ")
    out = CliRunner().invoke(main, ["plan", "trap", "--sampler", "goal_bias", "--param", "max_iter=300"])
    assert out.output.startswith("trap: rrt_star + goal_bias, seed 0: ")


@pytest.mark.parametrize("verb", ["plan", "sim"])
def test_a_point_whose_y_is_not_a_number_is_echoed_whole(verb):
    """(--start 1 abc was echoed as "got '1'", the abc typed dropped: newcomer, session 31)"""
    res = CliRunner().invoke(main, [verb, "trap", "--start", "1", "abc"])
    assert res.exit_code == 2 and "expected X Y or X Y THETA (numbers), got '1 abc'" in res.output, res.output


def test_one_simulated_step_is_singular():
    """("... 1 steps)": newcomer, session 31)"""
    res = CliRunner().invoke(main, ["sim", "trap", "--max-time", "0.001"])
    assert "(real-time factor" in res.output and ", 1 step)" in res.output, res.output
