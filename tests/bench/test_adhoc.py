"""Experiments made of flags: maps with --start/--goal, and folders named by what they run."""

import pytest
from click.testing import CliRunner

from navlab.cli import main
from navlab.grid import OccupancyGrid, plan
from navlab.grid.mapio import save_map


@pytest.fixture
def a_map(tmp_path):
    import numpy as np

    blocked = np.zeros((40, 40), bool)
    blocked[5:35, 20] = True
    save_map(OccupancyGrid(blocked, resolution=0.1), tmp_path / "wall.yaml")
    return tmp_path / "wall.yaml"


def test_a_map_with_start_and_goal_runs_without_an_experiment_file(tmp_path, a_map, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = ["bench", "--world", str(a_map), "--start", "0.5", "2", "--goal", "3.5", "2", "--planner", "astar",
            "--planner", "rrt_star", "--trials", "2", "--max-iter", "2000", "-q", "--no-plots", "--executor", "serial"]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    folders = list((tmp_path / "bench-results").iterdir())
    assert len(folders) == 1 and folders[0].name.startswith("adhoc-wall-astar-rrt_star-")
    assert "success 2/2" in res.output


def test_two_different_adhoc_runs_get_two_folders_and_the_same_one_is_resumable(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    base = ["bench", "--world", "trap", "--trials", "2", "--max-iter", "200", "-q", "--no-plots",
            "--executor", "serial"]
    for planner in ("rrt", "rrt_star"):
        assert CliRunner().invoke(main, base + ["--planner", planner]).exit_code == 0
    assert len(list((tmp_path / "bench-results").iterdir())) == 2
    again = CliRunner().invoke(main, base + ["--planner", "rrt", "--resume"])
    assert again.exit_code == 0 and "0 run now" in again.output
    assert "warm-up (compiling" not in again.output  # nothing ran: no worker warmed up in this run


@pytest.mark.parametrize("args,message", [
    (["--world", "trap", "--start", "1", "1", "--goal", "2", "2"], "are for maps"),
    (["--world", "trap", "--start", "1", "1"], "together"),
])
def test_start_and_goal_misuse_is_one_line(args, message):
    res = CliRunner().invoke(main, ["bench", "--planner", "rrt"] + args)
    assert res.exit_code == 2 and message in res.output


def test_a_map_without_start_and_goal_asks_for_the_flags(a_map, tmp_path):
    """(the line gave the experiment file's form, {map: ..., scen: ...}, to a user of flags: newcomer, session 22)"""
    moving_ai = tmp_path / "tiny.map"
    moving_ai.write_text("type octile\nheight 2\nwidth 3\nmap\n...\n.@.\n")
    for world in (str(a_map), str(moving_ai)):
        res = CliRunner().invoke(main, ["bench", "--planner", "astar", "--world", world])
        assert res.exit_code == 2, res.output
        assert f"--world {world} is a map, which has no start or goal: give --start X Y and --goal X Y" in res.output


def test_grid_plan_reports_the_warm_up_apart_from_the_search():
    import numpy as np

    from navlab.grid.planner import _warmed

    _warmed.cache_clear()
    first = plan(OccupancyGrid(np.zeros((30, 30), bool)), (0, 0), (29, 29), algorithm="jps", smooth=True)
    second = plan(OccupancyGrid(np.zeros((30, 30), bool)), (0, 0), (29, 29), algorithm="jps", smooth=True)
    assert first.stats["warmup_s"] > 0 and second.stats["warmup_s"] == 0.0
    assert first.cost == second.cost


def test_a_cells_failure_note_says_when_its_reason_is_one_of_several(tmp_path, monkeypatch):
    """The summary showed the first failed trial's reason as if every failure had it (two failures,
    2.1 and 11.5 m short of the goal; newcomer run, session 17)."""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["bench", "--world", "trap", "--planner", "rrt", "--trials", "3", "--max-iter", "5",
                                    "--executor", "serial", "--no-plots", "--out", "r", "-q"])
    line = next(x for x in res.output.splitlines() if "success 0/3" in x)
    assert "[APPROXIMATE: goal not reached in 5 iterations; the path ends" in line
    assert line.endswith(": 1 of the 3 failures; report.md lists the others' reasons]"), line


def test_one_trial_is_counted_in_the_singular(tmp_path, monkeypatch):
    """("1 trials (1 run now, 0 errors; 1 noise repeats besides)" until session 18: newcomer run)"""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["bench", "--world", "trap", "--planner", "rrt", "--trials", "1", "--max-iter",
                                    "200", "-q", "--no-plots", "--executor", "serial"])
    assert res.exit_code == 0, res.output
    line = next(line for line in res.output.splitlines() if "run now" in line)
    assert line.startswith("1 trial (1 run now, 0 errors") and "trials" not in line.split("of wall")[0]
    # and what a noise repeat is, where it is counted (unexplained until session 29: newcomer run)
    assert "; 1 noise repeat besides, each timing a trial again to measure the noise and in no statistic)" in line


def test_counted_says_one_in_the_singular():
    from navlab.wording import counted

    assert [counted(n, "run") for n in (0, 1, 2)] == ["0 runs", "1 run", "2 runs"]


def test_grid_settings_a_planner_does_not_use_are_noted_once(tmp_path):
    """(newcomer run, session 19: navlab bench ran jps cells labelled heuristic=manhattan without a word;
    navlab plan and grid plan already noted it)"""
    args = ["bench", "--world", "trap", "--planner", "astar", "--planner", "jps", "--planner", "dijkstra",
            "--grid", "heuristic=[octile,manhattan]", "--param", "weight=2", "--trials", "1", "-q", "--no-plots",
            "--executor", "serial", "--out", str(tmp_path / "out")]
    res = CliRunner().invoke(main, args)
    assert res.exit_code == 0, res.output
    # (a swept heuristic no longer splits the cells of searches that ignore it: session 23)
    assert [line for line in res.stderr.splitlines() if line.startswith("note:")] == [
        "note: jps searches unweighted (of the grid planners only astar takes a weight): weight=2 is not used",
        "note: dijkstra searches unweighted (of the grid planners only astar takes a weight): weight=2 is not used",
        "note: jps does not use the swept heuristic: its cells are not split by it (each runs once, not once "
        "per value)",
        "note: dijkstra does not use the swept heuristic: its cells are not split by it (each runs once, not "
        "once per value)"]
    res = CliRunner().invoke(main, ["bench", "--world", "trap", "--planner", "astar", "--grid", "heuristic=[octile,none]",
                                    "--param", "weight=2", "--trials", "1", "-q", "--no-plots", "--executor", "serial",
                                    "--out", str(tmp_path / "none")])
    assert res.exit_code == 0 and res.stderr.splitlines() == [  # (review, session 20: it said nothing)
        "note: astar with heuristic none searches unweighted (a weight scales the heuristic): weight=2 is "
        "not used"]
    args = args[:5] + args[9:]  # astar alone: it uses both
    assert "note:" not in CliRunner().invoke(main, args[:-1] + [str(tmp_path / "out2")]).stderr


def test_samplers_no_planner_draws_do_not_stop_a_resume(tmp_path, monkeypatch):
    """A run of astar with --sampler gaussian (a note says no planner draws it) could not be resumed without
    --sampler: "differs in: samplers" (attack, session 22). With a tree planner the samplers still count."""
    from navlab.bench import load_experiment

    monkeypatch.chdir(tmp_path)
    base = ["bench", "--world", "trap", "--planner", "astar", "--trials", "1", "-q", "--no-plots",
            "--executor", "serial"]
    assert CliRunner().invoke(main, base + ["--sampler", "gaussian"]).exit_code == 0
    again = CliRunner().invoke(main, base + ["--resume"])
    assert again.exit_code == 0 and "0 run now" in again.output, again.output
    assert len(list((tmp_path / "bench-results").iterdir())) == 1
    one = {"worlds": ["trap"], "trials": 1}
    assert load_experiment({**one, "planners": ["astar"], "samplers": ["gaussian"]}).fingerprint() == \
        load_experiment({**one, "planners": ["astar"]}).fingerprint()
    assert load_experiment({**one, "planners": ["rrt"], "samplers": ["gaussian"]}).fingerprint() != \
        load_experiment({**one, "planners": ["rrt"]}).fingerprint()


def test_what_no_planner_uses_leaves_the_identity_as_a_run_without_it_has():
    """A budget or seed that no planner uses changed a grid run's identity, so a resume with --max-iter 200
    was refused ("differs in: budget.max_iter"): attack, session 23. Left out as the defaults, they keep the
    identity of runs made before (their fingerprint is the plain hash of the settings: review, session 23)."""
    from navlab.bench import load_experiment
    from navlab.bench.experiment import DESCRIPTIVE, stable_hash

    grid = {"worlds": ["trap"], "planners": ["astar"], "trials": 1}
    plain = load_experiment(grid)
    data = plain.to_dict()
    assert plain.fingerprint() == stable_hash({k: v for k, v in data.items() if k not in DESCRIPTIVE})[:16]
    for extra in ({"budget": {"max_iter": 200}}, {"seed": 7}, {"samplers": ["gaussian"]}):
        assert load_experiment({**grid, **extra}).fingerprint() == plain.fingerprint(), extra
    tree = {**grid, "planners": ["rrt"]}
    for extra in ({"budget": {"max_iter": 200}}, {"seed": 7}, {"samplers": ["gaussian"]}):
        assert load_experiment({**tree, **extra}).fingerprint() != load_experiment(tree).fingerprint(), extra


def test_more_trials_of_a_run_of_flags_resume_in_its_folder(tmp_path, monkeypatch):
    """(the folder's name hashed the trial count too, so --trials 2 --resume began a new run)"""
    monkeypatch.chdir(tmp_path)
    base = ["bench", "--world", "trap", "--planner", "astar", "-q", "--no-plots", "--executor", "serial"]
    assert CliRunner().invoke(main, base + ["--trials", "1"]).exit_code == 0
    again = CliRunner().invoke(main, base + ["--trials", "2", "--max-iter", "50", "--resume"])
    assert again.exit_code == 0 and "1 run now" in again.output, again.output
    assert len(list((tmp_path / "bench-results").iterdir())) == 1


def test_a_world_file_edited_between_a_run_and_its_resume_is_named(tmp_path, monkeypatch):
    """(one cell held costs from two versions of the world: attack, session 23)"""
    monkeypatch.chdir(tmp_path)
    world = tmp_path / "zigzag.yaml"
    text = ("name: zigzag\nbounds: {x: [0, 10], y: [0, 10]}\nstart: [1, 1]\ngoal: [9, 9]\nobstacles:\n"
            "  - {type: rectangle, min: [2.5, 0.0], max: [3.0, 7.0]}\n")
    world.write_text(text)
    base = ["bench", "--world", str(world), "--planner", "astar", "-q", "--no-plots", "--executor", "serial",
            "--out", "run"]
    assert CliRunner().invoke(main, base + ["--trials", "1"]).exit_code == 0
    same = CliRunner().invoke(main, base + ["--trials", "2", "--resume"])
    assert same.exit_code == 0, same.output
    world.write_text(text.replace("7.0]", "9.5]"))
    changed = CliRunner().invoke(main, base + ["--trials", "3", "--resume"])
    assert changed.exit_code == 2
    assert f"holds results computed on another version of {world} (the file changed since)" in changed.output


def test_an_ompl_planner_that_counts_no_iterations_is_noted_beside_max_iter(tmp_path):
    """(ompl:RRTConnect's rows recorded max_iter 50, which it never reads: attack, session 23)"""
    pytest.importorskip("ompl")
    res = CliRunner().invoke(main, ["bench", "--world", "trap", "--planner", "ompl:RRTConnect", "--planner",
                                    "ompl:RRTstar", "--max-iter", "50", "--max-time", "0.05", "--trials", "1", "-q",
                                    "--no-plots", "--executor", "serial", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert ("note: ompl:RRTConnect counts no iterations and stops on max_time alone: max_iter 50 is not used by it"
            in res.stderr.splitlines())


def test_a_max_iter_no_ompl_planner_counts_leaves_the_identity_and_is_named_as_such():
    """(ompl:RRTConnect with --max-iter 999 --resume was refused "differs in: budget.max_iter", beside a note that
    it is not used; and with no budget it was told max_iter would do: newcomer, session 23)"""
    pytest.importorskip("ompl")
    from navlab.bench import load_experiment

    base = {"worlds": ["trap"], "trials": 1}
    connect = {**base, "planners": ["ompl:RRTConnect"], "budget": {"max_time": 0.1}}
    assert load_experiment(connect).fingerprint() == load_experiment(
        {**connect, "budget": {"max_time": 0.1, "max_iter": 999}}).fingerprint()
    star = {**base, "planners": ["ompl:RRTstar"], "budget": {"max_time": 0.1}}
    assert load_experiment(star).fingerprint() != load_experiment(
        {**star, "budget": {"max_time": 0.1, "max_iter": 999}}).fingerprint()
    with pytest.raises(ValueError, match="budget: ompl:RRTConnect does not count iterations; give it max_time"):
        load_experiment({**base, "planners": ["ompl:RRTConnect"]})


def test_a_folder_made_before_the_identity_left_unused_settings_out_still_resumes(tmp_path):
    """A run of ompl:RRTConnect with a max_iter it never reads, made before session 23, recorded the identity
    of every setting; it is still this run (review, session 23: "differs in: ?")."""
    import json

    from navlab.bench import load_experiment
    from navlab.bench.experiment import DESCRIPTIVE, stable_hash
    from navlab.bench.store import ResultStore

    exp = load_experiment({"worlds": ["trap"], "planners": ["astar"], "budget": {"max_iter": 50}, "trials": 1})
    current, before = exp.fingerprints()
    data = {k: v for k, v in exp.to_dict().items() if k not in DESCRIPTIVE}
    assert before == stable_hash(data)[:16] != current
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / "experiment.json").write_text(json.dumps({"fingerprint": before, "experiment": exp.to_dict()}))
    (folder / "results.jsonl").write_text(json.dumps({"trial_id": "x-0000", "status": "EXACT"}) + "\n")
    ResultStore(folder, exp, resume=True).close()  # no "holds results of a different experiment"
    (folder / "experiment.json").write_text(json.dumps({"fingerprint": "0" * 16, "experiment": exp.to_dict()}))
    with pytest.raises(ValueError, match="differs in: no setting its experiment.json shows"):
        ResultStore(folder, exp, resume=True)


def test_a_resume_with_nothing_to_resume_says_it_is_a_new_run(tmp_path, monkeypatch):
    """(flags that differ from the earlier run name another folder, and --resume began afresh without a word:
    newcomer, session 23)"""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["bench", "--world", "trap", "--planner", "astar", "--trials", "1", "-q",
                                    "--no-plots", "--executor", "serial", "--out", "fresh", "--resume"])
    assert res.exit_code == 0
    assert "note: nothing to resume in fresh (no results there): a new run" in res.stderr


@pytest.mark.parametrize("args, line", [
    (["--world", "nothere", "--planner", "rrt"], "Error: unknown scene 'nothere'; valid: "),
    (["--world", "trap", "--planner", "rrtx"], "Error: unknown planner 'rrtx'; valid: "),
    (["--world", "trap", "--planner", "astar", "--grid", "heuristic=0"],
     "Error: grid: planner 'astar' where heuristic=0: heuristic must be one of "),
])
def test_a_bad_flag_is_said_as_any_commands_error_is(args, line, tmp_path):
    """(each opened with "the command line: ", which a file's errors have in the file's place: newcomer,
    session 30); an experiment file's errors still name the file"""
    res = CliRunner().invoke(main, ["bench", *args, "--out", str(tmp_path / "out")])
    assert res.exit_code == 2 and res.output.startswith(line) and len(res.output.splitlines()) == 1
    study = tmp_path / "study.yaml"
    study.write_text("worlds: [nothere]\nplanners: [rrt]\n")
    res = CliRunner().invoke(main, ["bench", str(study), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2 and f"{study}: unknown scene 'nothere'" in res.output


def test_an_executor_that_cannot_run_is_said_before_where_results_would_go(tmp_path, monkeypatch):
    """(--executor dask without Dask printed "results go to ..." and then the install line: newcomer, s31)"""
    import sys

    monkeypatch.setitem(sys.modules, "distributed", None)  # as if Dask were not installed
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(main, ["bench", "--world", "trap", "--planner", "rrt", "--executor", "dask",
                                    "--trials", "1"])
    assert res.exit_code == 2, res.output
    assert res.output.startswith("Error: the dask executor needs Dask, which is not installed: ")
    assert "results go to" not in res.output and not (tmp_path / "bench-results").exists()


@pytest.mark.parametrize("args, words", [
    (["--executor", "serial", "-j", "2"], "serial runs one trial at a time"),
    (["--executor", "dask", "--scheduler", "tcp://127.0.0.1:1", "--jobs", "2"], "a --scheduler's cluster has its own"),
])
def test_jobs_that_would_be_ignored_are_refused(args, words, tmp_path):
    """(-j with --executor serial was ignored, unsaid, where --scheduler with serial is refused: newcomer, s32)"""
    res = CliRunner().invoke(main, ["bench", "--suite", "smoke", "--out", str(tmp_path / "out"), *args])
    assert res.exit_code == 2 and "--jobs sets the process executor's workers" in res.output and words in res.output
    assert not (tmp_path / "out").exists()
