"""Independent checks of what navlab returns (shapely for worlds, plain cell arithmetic for grids)."""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from helpers import true_clearance
from navlab.result import Result, Status


def check_world_result(world, result) -> None:
    """A planner's answer in a world is right: a collision-free path from start, or a truthful failure."""
    assert isinstance(result, Result) and isinstance(result.status, Status)
    b = world.bounds
    scale = max(abs(b.xmin), abs(b.xmax), abs(b.ymin), abs(b.ymax), 1.0)
    tol = 1e-9 * scale  # float64 rounding of coordinates at this scale
    r = world.robot_radius
    start = shapely.Point(world.start)
    if result.status is Status.INVALID_START:
        outside = not bool(b.contains(np.array(world.start))[0])
        assert outside or true_clearance(world, start) <= r + tol, f"start {world.start} is free: {result.reason}"
        return
    if result.status is Status.INVALID_GOAL:
        outside = not bool(b.contains(np.array(world.goal))[0])
        assert outside or true_clearance(world, shapely.Point(world.goal)) <= r + tol, \
            f"goal {world.goal} is free: {result.reason}"
        return
    path = np.asarray(result.path, dtype=float)
    if result.status is Status.EXACT:
        assert len(path) >= 1
    if not len(path):
        assert result.status is not Status.EXACT
        return
    assert path.ndim == 2 and path.shape[1] == 2 and np.isfinite(path).all()
    assert np.allclose(path[0], world.start, rtol=0, atol=tol)
    assert (path[:, 0] >= b.xmin - tol).all() and (path[:, 0] <= b.xmax + tol).all()
    assert (path[:, 1] >= b.ymin - tol).all() and (path[:, 1] <= b.ymax + tol).all()
    for a, c in zip(path[:-1], path[1:]):
        piece = shapely.LineString([a, c]) if not np.array_equal(a, c) else shapely.Point(a)
        clearance = true_clearance(world, piece)
        # touching an obstacle is a collision (docs/scenes.md), so the clearance must exceed r
        assert clearance > r - tol, f"segment {a} -> {c} has clearance {clearance} < robot radius {r}"
    length = float(np.hypot(*np.diff(path, axis=0).T).sum())
    assert math.isclose(result.cost, length, rel_tol=1e-6, abs_tol=tol), (result.cost, length)
    if result.status is Status.EXACT:
        # the growth-ratio RRT (seed 003) succeeds within p_min of the goal; the goal is appended only when visible
        region = max(world.goal_tolerance, result.params.get("p_min") or 0.0)
        assert math.dist(path[-1], world.goal) <= region + tol, (path[-1], world.goal, region)


def grid_graph(passable: np.ndarray) -> csr_matrix:
    """8-connected grid graph without corner cutting (the rule navlab's planners follow), weights in cells."""
    h, w = passable.shape
    rows, cols, weights = [], [], []
    for y in range(h):
        for x in range(w):
            if not passable[y, x]:
                continue
            for dx, dy in ((1, 0), (0, 1), (1, 1), (1, -1)):
                nx, ny = x + dx, y + dy
                if not (0 <= nx < w and 0 <= ny < h and passable[ny, nx]):
                    continue
                if dx and dy and not (passable[y, nx] and passable[ny, x]):
                    continue
                rows += [y * w + x, ny * w + nx]
                cols += [ny * w + nx, y * w + x]
                weights += [math.hypot(dx, dy)] * 2
    return csr_matrix((weights, (rows, cols)), shape=(h * w, h * w))


def grid_optimum(passable: np.ndarray, start, goal) -> float:
    """Shortest 8-connected path length in cells (scipy's Dijkstra), inf when disconnected."""
    w = passable.shape[1]
    dist = dijkstra(grid_graph(passable), indices=start[1] * w + start[0])
    return float(dist[goal[1] * w + goal[0]])


def check_grid_result(passable: np.ndarray, start, goal, result, algorithm: str) -> None:
    """A grid planner's answer is right: free cells, legal steps, optimal cost where promised."""
    assert isinstance(result, Result) and isinstance(result.status, Status)
    h, w = passable.shape
    inside = [0 <= c[0] < w and 0 <= c[1] < h for c in (start, goal)]
    if result.status is Status.INVALID_START:
        assert not inside[0] or not passable[start[1], start[0]]
        return
    if result.status is Status.INVALID_GOAL:
        assert inside[0] and passable[start[1], start[0]]
        assert not inside[1] or not passable[goal[1], goal[0]]
        return
    assert all(inside) and passable[start[1], start[0]] and passable[goal[1], goal[0]]
    best = grid_optimum(passable, start, goal)
    if result.status is Status.FAILED:
        assert math.isinf(best), f"no path reported, but one of {best} cells exists"
        return
    assert result.status is Status.EXACT
    cells = np.asarray(result.cells, dtype=np.int64)
    assert tuple(cells[0]) == tuple(start) and tuple(cells[-1]) == tuple(goal)
    assert passable[cells[:, 1], cells[:, 0]].all()
    length = float(np.hypot(*np.diff(cells, axis=0).T).sum())
    cost_cells = result.stats.get("cost_cells", result.cost)  # grids with a resolution: cost in metres
    assert math.isclose(cost_cells, length, rel_tol=1e-9, abs_tol=1e-12), (cost_cells, length)
    if algorithm != "theta_star":
        steps = np.diff(cells, axis=0)
        assert (np.abs(steps) <= 1).all(), "a step jumps over cells"
        for (x, y), (dx, dy) in zip(cells[:-1], steps):
            if dx and dy:
                assert passable[y, x + dx] and passable[y + dy, x], f"corner cut at {(x, y)}"
        assert math.isclose(cost_cells, best, rel_tol=1e-9), (cost_cells, best)
    else:
        assert cost_cells <= best + 1e-9
