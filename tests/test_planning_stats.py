"""Every result of ``navlab.plan`` carries the same stats keys whatever its status (issue 13)."""

import pytest

import navlab

QUERIES = {  # on `trap`: a solvable query, a start outside the bounds, a goal inside an obstacle
    "EXACT": ((1.0, 1.0), (9.0, 9.0)),
    "INVALID_START": ((-1.0, 0.3), (9.0, 9.0)),
    "INVALID_GOAL": ((1.0, 1.0), (1e6, 1.0)),
}


@pytest.mark.parametrize("planner", ["astar", "theta_star", "rrt", "rrt_star"])
def test_stats_keys_do_not_depend_on_the_status(planner):
    extra = {} if planner in ("astar", "theta_star") else {"max_iter": 300}
    keys = {}
    for expected, (start, goal) in QUERIES.items():
        result = navlab.plan("trap", planner=planner, start=start, goal=goal, seed=1, **extra)
        assert result.status.name == expected or expected == "EXACT" and result.status.name == "APPROXIMATE"
        keys[expected] = sorted(result.stats)
    assert keys["EXACT"] == keys["INVALID_START"] == keys["INVALID_GOAL"]
    assert "time_s" in keys["EXACT"] and "warmup_s" in keys["EXACT"]
