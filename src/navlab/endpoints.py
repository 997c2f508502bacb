"""Start and goal of a query: why one is invalid, and how a grid path reaches it.

Every planner answers an invalid start or goal with ``INVALID_START`` /
``INVALID_GOAL`` and a reason a user can act on: outside the bounds (or the
map), in an occupied or unknown map cell, or within the robot radius of an
occupied cell or an obstacle, naming the map cell.

A grid planner searches between cell centres, but the path must begin and end
at the exact points: :func:`attach` picks a free cell near the point whose
centre the point sees in a straight line, with the leg checked exactly.
"""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np

Cell = Tuple[int, int]


def _fmt(p) -> str:
    return f"({p[0]:g}, {p[1]:g})"


def _cell_squares_near(grid, point, reach: float):
    """Cells (x, y) within ``reach`` cells of ``point``'s cell, clipped to the grid."""
    cx, cy = (int(v) for v in grid.world_to_cell(np.asarray(point, dtype=float)))
    k = int(math.ceil(reach)) + 1
    xs = np.arange(max(cx - k, 0), min(cx + k + 1, grid.width))
    ys = np.arange(max(cy - k, 0), min(cy + k + 1, grid.height))
    return xs, ys


def _local(grid, point) -> np.ndarray:
    """``point`` in the map's frame, in cells (cell (i, j) is the square [i, i+1] x [j, j+1])."""
    c, s = math.cos(grid.origin[2]), math.sin(grid.origin[2])
    dx, dy = point[0] - grid.origin[0], point[1] - grid.origin[1]
    return np.array([c * dx + s * dy, -s * dx + c * dy]) / grid.resolution


def nearest_blocking_cell(grid, point, radius: float, allow_unknown: bool) -> Optional[Tuple[Cell, float, str]]:
    """The occupied (or unknown) cell whose square is nearest to ``point``, if
    closer than ``radius``: ((x, y), distance in m, "occupied" or "unknown")."""
    xs, ys = _cell_squares_near(grid, point, radius / grid.resolution)
    if not len(xs) or not len(ys):
        return None
    lx, ly = _local(grid, point)
    gx = np.maximum(np.maximum(xs - lx, lx - (xs + 1)), 0.0)
    gy = np.maximum(np.maximum(ys - ly, ly - (ys + 1)), 0.0)
    dist = np.hypot(gx[None, :], gy[:, None]) * grid.resolution
    blocked = grid.blocked[np.ix_(ys, xs)]
    unknown = grid.unknown[np.ix_(ys, xs)] & ~blocked
    bad = blocked | (unknown if not allow_unknown else False)
    dist = np.where(bad, dist, np.inf)
    j, i = np.unravel_index(int(np.argmin(dist)), dist.shape)
    if not dist[j, i] < radius:
        return None
    return (int(xs[i]), int(ys[j])), float(dist[j, i]), "occupied" if blocked[j, i] else "unknown"


def endpoint_problem(world, point, label: str, checker) -> Optional[str]:
    """Why ``point`` (the query's ``label``: "start" or "goal") cannot be used, or None."""
    p = np.asarray(point, dtype=float)
    where = f"{label} {_fmt(p)}"
    b = world.bounds
    grid = world.occupancy
    cell = tuple(int(v) for v in grid.world_to_cell(p)) if grid is not None else None
    if not b.contains(p)[0]:
        return f"{where} is outside the bounds {b.text()}" + \
            (f" (cell {cell}, outside the {grid.width}x{grid.height} map)" if grid is not None else "")
    if grid is not None:
        if not grid.contains([cell])[0]:
            return f"{where} is in cell {cell}, outside the {grid.width}x{grid.height} map"
        if grid.blocked[cell[1], cell[0]]:
            return f"{where} is in occupied cell {cell}"
        if grid.unknown[cell[1], cell[0]] and not world.allow_unknown:
            return f"{where} is in unknown cell {cell} (allow_unknown is off)"
        near = nearest_blocking_cell(grid, p, world.robot_radius, world.allow_unknown)
        if near is not None:
            other, dist, kind = near
            return (f"{where} in cell {cell} is within the robot radius {world.robot_radius:g} m of {kind} cell "
                    f"{other} ({dist:.3g} m away)")
    if not checker.points_free(p)[0]:
        gap = float(checker.clearance(p)[0])
        why = "inside an obstacle (clearance 0 m)" if gap == 0 else \
            f"within the robot radius {world.robot_radius:g} m of an obstacle (clearance {gap:.4g} m)"
        return f"{where} is in collision: {why}"
    return None


def map_segment_clear(world, a, b) -> bool:
    """Whether segment ab keeps the robot radius from every occupied (and, unless
    allowed, unknown) map cell's square; exact, with shapely, near the segment only."""
    grid = world.occupancy
    if grid is None:
        return True
    import shapely

    r = world.robot_radius
    a, b = np.asarray(a, float), np.asarray(b, float)
    mid = (a + b) / 2
    reach = (np.linalg.norm(b - a) / 2 + r) / grid.resolution + 1
    xs, ys = _cell_squares_near(grid, mid, reach)
    if not len(xs) or not len(ys):
        return True
    bad = ~grid.passable(world.allow_unknown)[np.ix_(ys, xs)]
    if not bad.any():
        return True
    jj, ii = np.nonzero(bad)
    corners = np.stack([np.stack([xs[ii] + dx, ys[jj] + dy], axis=-1) for dx, dy in ((0, 0), (1, 0), (1, 1), (0, 1))],
                       axis=1).astype(float) * grid.resolution
    c, s = math.cos(grid.origin[2]), math.sin(grid.origin[2])
    world_corners = corners @ np.array([[c, s], [-s, c]]) + np.asarray(grid.origin[:2])
    squares = shapely.polygons(world_corners)
    segment = shapely.LineString([a, b]) if np.any(a != b) else shapely.Point(a)
    dist = shapely.distance(squares, segment)
    return bool(np.all(dist >= r) and (r > 0 or np.all(dist > 0)))


def leg_free(world, checker, a, b) -> bool:
    """Whether the straight leg ab is free in the exact world (shapes and map)."""
    return bool(checker.segments_free(np.asarray([a], float), np.asarray([b], float))[0]) and \
        map_segment_clear(world, a, b)


def attach(world, grid, passable: np.ndarray, point, checker, search_cells: int = 3) -> Optional[Cell]:
    """A passable cell of ``grid`` whose centre ``point`` reaches by a free
    straight leg: the point's own cell if it can, else the nearest such cell
    within ``search_cells`` cells (a point near a wall lies in a cell the
    conservative raster blocks). None when there is none."""
    p = np.asarray(point, dtype=float)
    cx, cy = (int(v) for v in grid.world_to_cell(p))
    k = search_cells
    xs = np.arange(max(cx - k, 0), min(cx + k + 1, grid.width))
    ys = np.arange(max(cy - k, 0), min(cy + k + 1, grid.height))
    if not len(xs) or not len(ys):
        return None
    X, Y = np.meshgrid(xs, ys)
    cells = np.column_stack((X.ravel(), Y.ravel()))
    cells = cells[passable[cells[:, 1], cells[:, 0]]]
    if not len(cells):
        return None
    centres = grid.cell_to_world(cells)
    order = np.argsort(np.hypot(*(centres - p).T), kind="stable")
    for i in order:
        if leg_free(world, checker, p, centres[i]):
            return int(cells[i, 0]), int(cells[i, 1])
    return None
