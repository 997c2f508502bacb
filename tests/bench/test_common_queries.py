"""On map experiments (rows carry a ``query``) every cell's cost and time
statistics, the report's tables and the box plots are over the queries all
cells of the world solved (issue 19); experiments without queries describe
each cell over its own solved trials, as before. Truth: means by hand."""

import pytest

from navlab.bench import runner
from navlab.bench.analysis import compared_rows, side_by_side, summarize, timed
from navlab.bench.report import build, to_markdown
from navlab.viz import bench_plot

#: (query, cost [m] or None when the trial failed, CPU time [s]) per trial
ASTAR = [(0, 3.0, 0.01), (1, 600.0, 0.5), (0, 3.2, 0.03), (1, 610.0, 0.7)]
RRT = [(0, 3.5, 0.2), (1, None, 2.0), (0, 3.9, 0.4), (1, None, 2.2)]
NOTHING = [(0, None, 1.0), (1, None, 1.0), (0, None, 1.0), (1, None, 1.0)]
OLD_CAPTION = ("Cost and time over the trials that reached the goal (a failed trial has no path, and its time is "
               "the time it took to give up); iterations over every trial that ran. CI: 95% t-interval of the mean.")


def cell(planner, trials, world="maze", queries=True):
    return [{"trial_id": f"{planner}-{i}", "cell_id": planner, "trial": i, "world": world, "planner": planner,
             "sampler": "-", "status": "EXACT" if cost is not None else "APPROXIMATE", "success": cost is not None,
             "cost": cost, "cpu_s": t, "time_s": t, "iterations": 10, "query": q if queries else None}
            for i, (q, cost, t) in enumerate(trials)]


def by_planner(summary):
    return {c["planner"]: c for c in summary["cells"]}


def report(rows):
    summary = summarize(rows)
    blocks = build({"name": "t", "seed": 0}, timed(rows), summary, {}, None, {})
    return summary, to_markdown(blocks)


def box_figure(rows, tmp_path, monkeypatch):
    """The box-plot figure the runner draws for the rows' world (as make_plots hands them over)."""
    drawn = []
    monkeypatch.setattr(bench_plot, "_save", lambda fig, out, dpi: drawn.append(fig))
    groups = {}
    for r in timed(rows):
        groups.setdefault(f"{r['planner']} / -", []).append(runner._plot_fields(r))
    runner._plot_world((rows[0]["world"], groups, {}, {}, str(tmp_path), "thread CPU time"))
    return drawn[0]


def plotted(ax):
    """Every y value drawn in a box-plot axis (boxes, whiskers, medians, means)."""
    return [y for line in ax.lines for y in line.get_ydata() if y == y]


def test_cells_are_described_on_the_queries_all_of_them_solved(tmp_path, monkeypatch):
    rows = cell("astar", ASTAR) + cell("rrt_star", RRT)
    summary, md = report(rows)
    cells = by_planner(summary)
    # astar over query 0 only: (3.0 + 3.2) / 2, not (3.0 + 600 + 3.2 + 610) / 4
    assert cells["astar"]["cost"]["mean"] == pytest.approx(3.1)
    assert cells["astar"]["cost"]["max"] == pytest.approx(3.2) and cells["astar"]["cost"]["n"] == 2
    assert cells["astar"]["time"]["mean"] == pytest.approx(0.02)
    assert cells["rrt_star"]["cost"]["mean"] == pytest.approx(3.7)
    assert cells["rrt_star"]["time"]["mean"] == pytest.approx(0.3)  # its failed trials' 2 s are not times
    assert (cells["astar"]["successes"], cells["rrt_star"]["successes"]) == (4, 2)  # success: every trial
    assert summary["compared"] == {"maze": {"common": 1, "queries": 2}}
    assert "maze: cost and time over the 1 query all cells solved (of 2)" in md
    assert "| maze | astar | - | 4/4 | 3.100 |" in md and "| maze | rrt_star | - | 2/4 | 3.700 |" in md
    fig = box_figure(rows, tmp_path, monkeypatch)
    assert fig._suptitle.get_text() == "maze: cost and time over the 1 query all cells solved (of 2)"
    assert max(plotted(fig.axes[0])) == pytest.approx(3.9)  # no 600 m box beside RRT*'s 3 m
    assert max(plotted(fig.axes[1])) == pytest.approx(0.4)


def test_a_cell_that_solved_nothing_is_said_so_and_the_others_still_compare(tmp_path, monkeypatch):
    rows = cell("astar", ASTAR) + cell("rrt_star", RRT) + cell("boundary", NOTHING)
    summary, md = report(rows)
    cells = by_planner(summary)
    assert summary["compared"]["maze"] == {"common": 1, "queries": 2}
    assert cells["astar"]["cost"]["mean"] == pytest.approx(3.1) and cells["rrt_star"]["cost"]["mean"] == 3.7
    assert cells["boundary"]["cost"]["n"] == 0
    assert "| maze | boundary | - | 0/4 | no path in any trial | [-, -] | - |" in md
    fig = box_figure(rows, tmp_path, monkeypatch)
    marks = [t.get_text() for t in fig.axes[0].texts]
    assert marks == ["no path in\nany trial"]
    assert fig.axes[0].texts[0].get_position()[0] == 3  # where boundary's box would stand
    assert max(plotted(fig.axes[0])) == pytest.approx(3.9)


def test_cells_with_no_query_in_common_compare_nothing_and_say_so():
    rows = cell("astar", [(0, 3.0, 0.1), (1, None, 1.0)]) + cell("rrt_star", [(0, None, 1.0), (1, 7.0, 0.2)])
    summary, md = report(rows)
    assert summary["compared"]["maze"] == {"common": 0, "queries": 2}
    assert all(c["cost"]["n"] == 0 and c["time"]["n"] == 0 for c in summary["cells"])
    assert md.count("no query all cells solved") == 2
    assert "over the 0 queries all cells solved (of 2)" in md


def test_the_seed_layout_means_are_over_the_queries_both_solved():
    groups = {"a": timed(cell("astar", ASTAR)), "b": timed(cell("rrt_star", RRT))}
    mean = next(r for r in side_by_side(groups, "a", "b") if r[0] == "mean")
    assert mean[1:] == pytest.approx([3.1, 0.02, 3.7, 0.3])
    # the same rule picks them as the verdicts' values: per group, the solved trials of the common queries
    picked, scope = compared_rows(groups)
    assert [r["trial"] for r in picked["a"]] == [0, 2] and [r["trial"] for r in picked["b"]] == [0, 2]
    assert scope == {"common": 1, "queries": 2}


def test_without_queries_each_cell_keeps_its_own_solved_trials(tmp_path, monkeypatch):
    # the samplers suite: one start and goal, trials differ by seed; a failed trial is not a query left out
    rows = cell("astar", ASTAR, world="trap", queries=False) + cell("rrt_star", RRT, world="trap", queries=False)
    summary, md = report(rows)
    cells = by_planner(summary)
    assert cells["astar"]["cost"]["mean"] == pytest.approx((3.0 + 600.0 + 3.2 + 610.0) / 4)
    assert cells["astar"]["time"]["mean"] == pytest.approx((0.01 + 0.5 + 0.03 + 0.7) / 4)
    assert cells["rrt_star"]["cost"]["mean"] == pytest.approx(3.7)
    assert summary["compared"] == {}
    assert OLD_CAPTION + "\n" in md and "all cells solved" not in md
    fig = box_figure(rows, tmp_path, monkeypatch)
    assert fig._suptitle.get_text() == "trap: cost and time of the trials that reached the goal"
    assert max(plotted(fig.axes[0])) == pytest.approx(610.0)
