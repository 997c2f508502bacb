import json
from pathlib import Path

from click.testing import CliRunner

from navlab.cli import main

# shared/data/movingai beside the checkout (main and helpers' worktrees sit at different depths)
DATA = next((p / "shared" / "data" / "movingai" for p in Path(__file__).resolve().parents
             if (p / "shared" / "data" / "movingai").is_dir()), Path("shared/data/movingai"))



def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_maze_then_plan(tmp_path):
    out = tmp_path / "maze.yaml"
    res = run("grid", "maze", "--cells", 10, 10, "--seed", 4, "--out", out)
    assert res.exit_code == 0 and (tmp_path / "maze.pgm").exists()
    res = run("grid", "plan", out, "--world", "--start", 0.3, 0.3, "--goal", 4.8, 4.8, "--smooth",
              "--inflate", 0.02, "--json", "--plot", tmp_path / "p.png")
    data = json.loads(res.output)
    assert res.exit_code == 0 and data["status"] == "EXACT" and data["stats"]["raw_cost"] >= data["cost"]
    assert (tmp_path / "p.png").read_bytes()[:4] == b"\x89PNG"


def test_scen_reports_matches():
    res = run("grid", "scen", DATA / "arena.map.scen", "--algorithm", "jps")
    assert res.exit_code == 0 and "160 match the stored optimum, 0 do not" in res.output
    assert "median" in res.output and "p95" in res.output
    res = run("grid", "scen", DATA / "den312d.map.scen", "--every", 10, "--json")
    assert json.loads(res.output)["summary"]["mismatches"] == 0


def test_bad_inputs_are_clear(tmp_path):
    res = run("grid", "plan", tmp_path / "none.yaml", "--start", 0, 0, "--goal", 1, 1)
    assert res.exit_code == 2 and "no such file" in res.output
    res = run("grid", "plan", DATA / "arena.map", "--start", 0, 0, "--goal", 5, 5)
    assert res.exit_code == 1 and "INVALID_START" in res.output
    res = run("grid", "plan", DATA / "arena.map", "--start", 0.5, 0, "--goal", 5, 5)
    assert res.exit_code == 2 and "--world" in res.output
