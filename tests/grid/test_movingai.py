"""navlab's grid search against the Moving AI benchmark's optimal lengths."""

from pathlib import Path

import numpy as np
import pytest

from navlab.grid import load_map, plan, read_scen
from navlab.grid.scen_runner import benchmark_length, run_scenarios

# shared/data/movingai beside the checkout (main and helpers' worktrees sit at different depths)
DATA = next((p / "shared" / "data" / "movingai" for p in Path(__file__).resolve().parents
             if (p / "shared" / "data" / "movingai").is_dir()), Path("shared/data/movingai"))

FILES = [("arena.map", "arena.map.scen", 1), ("den312d.map", "den312d.map.scen", 3),
         ("random-32-32-10.map", "random-32-32-10-random-1.scen", 2),
         ("Berlin_1_256.map", "Berlin_1_256.map.scen", 9), ("maze512-32-9.map", "maze512-32-9.map.scen", 200)]

pytestmark = pytest.mark.skipif(not DATA.exists(), reason=f"Moving AI data not found at {DATA}")


def assert_valid_8_path(grid, cells, start, goal):
    assert tuple(cells[0]) == tuple(start) and tuple(cells[-1]) == tuple(goal)
    assert not grid.blocked[cells[:, 1], cells[:, 0]].any()
    step = np.diff(cells, axis=0)
    assert np.all(np.abs(step).max(axis=1) == 1)
    diag = np.all(np.abs(step) == 1, axis=1)
    a = cells[:-1][diag]
    s = step[diag]
    # No corner cutting: both orthogonal neighbours of every diagonal step are free.
    assert not grid.blocked[a[:, 1], a[:, 0] + s[:, 0]].any()
    assert not grid.blocked[a[:, 1] + s[:, 1], a[:, 0]].any()


@pytest.mark.parametrize("algorithm", ["astar", "dijkstra", "jps"])
@pytest.mark.parametrize("map_name, scen_name, every", FILES)
def test_stored_optima_reproduced(map_name, scen_name, every, algorithm):
    grid = load_map(DATA / map_name)
    scenarios = read_scen(DATA / scen_name)[::every]
    if algorithm == "dijkstra" and map_name.startswith("maze"):
        scenarios = scenarios[::4]
    for sc in scenarios:
        r = plan(grid, sc.start, sc.goal, algorithm=algorithm)
        assert r.success, sc
        assert_valid_8_path(grid, r.cells, sc.start, sc.goal)
        assert abs(benchmark_length(r.cells) - sc.optimal) <= sc.tolerance(), (sc, r.cost)
        # The exact length agrees with the benchmark's √2 to 4e-10 per diagonal step.
        assert abs(r.cost - sc.optimal) <= sc.tolerance() + 4e-10 * len(r.cells)


def test_scen_runner_summary():
    out = run_scenarios(DATA / "random-32-32-10-random-1.scen", algorithm="jps")
    assert out["summary"]["scenarios"] == 461 and out["summary"]["mismatches"] == 0
    assert out["summary"]["time_p95_ms"] >= out["summary"]["time_median_ms"]


def test_scen_runner_rows_name_the_scenarios_place_in_the_file():
    """With every=10 the row of file scenario 10 was numbered 1 (newcomer, session 22)."""
    scen = DATA / "random-32-32-10-random-1.scen"
    out = run_scenarios(scen, algorithm="jps", every=10, limit=4)
    stored = read_scen(scen)
    assert [row["index"] for row in out["rows"]] == [0, 10, 20, 30]
    for row in out["rows"]:
        assert tuple(row["start"]) == tuple(stored[row["index"]].start)


def test_movingai_rows_index_blocked_directly():
    grid = load_map(DATA / "arena.map")
    rows = (DATA / "arena.map").read_text().splitlines()[4:]
    for y in (0, 10, 48):
        for x in (0, 7, 48):
            assert grid.blocked[y, x] == (rows[y][x] not in ".GS")
