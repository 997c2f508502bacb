"""A* on costmap costs against scipy's Dijkstra with the same step costs, and through navlab.plan."""

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

import navlab
from navlab.grid.cost_search import costmap_astar, plan_on_costmap
from navlab.world.costmap import NO_INFORMATION, Costmap


def _scipy_costs(costs, passable, multiplier):
    h, w = costs.shape
    idx = np.arange(h * w).reshape(h, w)
    rows, cols, vals = [], [], []
    for y in range(h):
        for x in range(w):
            if not passable[y, x]:
                continue
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    nx, ny = x + dx, y + dy
                    if (dx, dy) == (0, 0) or not (0 <= nx < w and 0 <= ny < h) or not passable[ny, nx]:
                        continue
                    if dx and dy and not (passable[y, nx] and passable[ny, x]):
                        continue
                    step = math.sqrt(2) if dx and dy else 1.0
                    rows.append(idx[y, x])
                    cols.append(idx[ny, nx])
                    vals.append(step * (1 + multiplier * costs[ny, nx] / 252.0))
    return coo_matrix((vals, (rows, cols)), shape=(h * w, h * w)).tocsr()


@pytest.mark.parametrize("seed", range(4))
def test_astar_on_costs_equals_scipy_dijkstra(seed):
    rng = np.random.default_rng(seed)
    costs = rng.integers(0, 253, (25, 30)).astype(np.float64)
    costs[rng.random((25, 30)) < 0.15] = 254
    passable = costs < 253
    multiplier = [0.0, 2.0, 5.0, 0.5][seed]
    graph = _scipy_costs(costs, passable, multiplier)
    starts = np.flatnonzero(passable.ravel())[:3]
    truth = dijkstra(graph, indices=starts)
    for k, s in enumerate(starts):
        for goal in rng.choice(np.flatnonzero(passable.ravel()), 10, replace=False):
            parent = np.full(costs.size, -1, np.int64)
            got, _, expanded = costmap_astar(costs, passable, int(s), int(goal), multiplier, parent)
            assert got == pytest.approx(truth[k, goal], rel=1e-12) or (math.isinf(got) and math.isinf(truth[k, goal]))
            assert 1 <= expanded <= np.count_nonzero(np.isfinite(truth[k]))
        # without a goal it expands every cell it can reach, once: scipy's count of finite distances
        _, g, expanded = costmap_astar(costs, passable, int(s), -1, multiplier, np.full(costs.size, -1, np.int64))
        assert expanded == np.count_nonzero(np.isfinite(truth[k])) == np.count_nonzero(np.isfinite(g))


def test_plan_on_costmap_keeps_away_from_costly_cells():
    costs = np.zeros((20, 40), np.uint8)
    costs[8:12, 10:30] = 200  # a costly band across the straight line
    cm = Costmap(costs, 0.1, (0.0, 0.0))
    straight, _, _ = plan_on_costmap(cm, (0.55, 1.05), (3.55, 1.05), cost_travel_multiplier=0.0)
    around, cost, _ = plan_on_costmap(cm, (0.55, 1.05), (3.55, 1.05), cost_travel_multiplier=5.0)
    assert cm.cost_at(straight).max() == 200 and cm.cost_at(around[1:-1]).max() < 200
    assert cost > 3.0
    none, _, reason = plan_on_costmap(Costmap(np.full((5, 5), 254, np.uint8), 0.1), (0.25, 0.25), (0.35, 0.35))
    assert none is None and "lethal" in reason


def test_navlab_plan_with_a_costmap_keeps_clear_and_is_verified():
    plain = navlab.plan("clutter", planner="astar", robot_radius=0.2)
    on_costs = navlab.plan("clutter", planner="astar", robot_radius=0.2, costmap=True)
    assert on_costs.success and on_costs.params["costmap"] is True
    world = navlab.load_world("clutter")
    import shapely

    def clearance(path):
        line = shapely.LineString(path)
        shapes = [shapely.Point(o.center).buffer(o.radius, 64) if hasattr(o, "radius") else
                  shapely.box(*o.min, *o.max) if hasattr(o, "min") else shapely.Polygon(o.points)
                  for o in world.obstacles]
        return min(line.distance(s) for s in shapes)

    assert clearance(on_costs.path) > 0.2
    assert clearance(on_costs.path) > clearance(plain.path)
    with pytest.raises(ValueError, match="only the grid planner astar"):
        navlab.plan("clutter", planner="rrt_star", costmap=True)
    with pytest.raises(ValueError, match="costmap must be true or false"):
        navlab.plan("clutter", planner="astar", costmap="yes")


def test_a_failure_on_unknown_cells_says_allow_unknown_opens_them():
    """A band of unknown cells across the map failed with 'no path through cells below INSCRIBED cost'
    alone (newcomer check, session 16): the reason counts them and names allow_unknown."""
    costs = np.zeros((10, 20), np.uint8)
    costs[:, 9:11] = NO_INFORMATION
    cm = Costmap(costs, 0.1)
    none, _, reason = plan_on_costmap(cm, (0.25, 0.55), (1.75, 0.55))
    assert none is None and reason.endswith("the costmap's 20 unknown cells were closed to it: allow_unknown=true "
                                            "opens them")
    path, _, reason = plan_on_costmap(cm, (0.25, 0.55), (1.75, 0.55), allow_unknown=True)
    assert path is not None and reason == ""
