"""Perfect mazes (one path between any two cells) as occupancy grids."""

from __future__ import annotations

import math

import numpy as np

from .occupancy import OccupancyGrid


def maze_walls(cells_x: int, cells_y: int, rng: np.random.Generator):
    """Carve a perfect maze by randomized depth-first search (recursive backtracker).

    Returns ``(east, north)`` bool arrays of shape (cells_y, cells_x): whether
    the wall on the cell's east / north side stands.
    """
    east = np.ones((cells_y, cells_x), dtype=bool)
    north = np.ones((cells_y, cells_x), dtype=bool)
    seen = np.zeros((cells_y, cells_x), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    while stack:
        x, y = stack[-1]
        options = [(dx, dy) for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))
                   if 0 <= x + dx < cells_x and 0 <= y + dy < cells_y and not seen[y + dy, x + dx]]
        if not options:
            stack.pop()
            continue
        dx, dy = options[int(rng.integers(len(options)))]
        nx, ny = x + dx, y + dy
        if dx == 1:
            east[y, x] = False
        elif dx == -1:
            east[ny, nx] = False
        elif dy == 1:
            north[y, x] = False
        else:
            north[ny, nx] = False
        seen[ny, nx] = True
        stack.append((nx, ny))
    return east, north


def make_maze(cells_x: int = 10, cells_y: int = 10, seed=0, cell_size: float = 0.5,
              wall: float = 0.1, resolution: float = 0.05) -> OccupancyGrid:
    """A perfect maze of ``cells_x × cells_y`` cells as an occupancy grid.

    Parameters
    ----------
    cells_x, cells_y : int
        Maze size in cells (the seed used 10 × 10 and 15 × 15).
    seed : int or Generator
    cell_size : float
        Distance between neighbouring cell centres, m.
    wall : float
        Wall thickness, m (walls are centred on cell borders; the outer wall
        is included).
    resolution : float
        Grid resolution, m per pixel.

    Cell (i, j) of the maze has its centre at world
    ``(wall/2 + (i + 0.5)·cell_size, wall/2 + (j + 0.5)·cell_size)``.
    """
    for name, v in (("cells_x", cells_x), ("cells_y", cells_y)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise ValueError(f"{name} must be a positive integer, got {v!r}")
    for name, v in (("cell_size", cell_size), ("wall", wall), ("resolution", resolution)):
        if not (isinstance(v, (int, float)) and v > 0 and math.isfinite(v)):
            raise ValueError(f"{name} must be a positive number of metres, got {v!r}")
    if wall >= cell_size:
        raise ValueError(f"wall ({wall} m) must be thinner than cell_size ({cell_size} m)")
    rng = np.random.default_rng(seed)
    east, north = maze_walls(cells_x, cells_y, rng)
    width_m, height_m = cells_x * cell_size + wall, cells_y * cell_size + wall
    nx, ny = int(round(width_m / resolution)), int(round(height_m / resolution))
    xs = (np.arange(nx) + 0.5) * resolution - wall / 2  # pixel centres, cell-border frame
    ys = (np.arange(ny) + 0.5) * resolution - wall / 2
    # Which border line (if any) each pixel column / row lies on.
    col_line = np.where(np.abs(xs - np.round(xs / cell_size) * cell_size) <= wall / 2,
                        np.round(xs / cell_size).astype(int), -1)
    row_line = np.where(np.abs(ys - np.round(ys / cell_size) * cell_size) <= wall / 2,
                        np.round(ys / cell_size).astype(int), -1)
    col_cell = np.clip(np.floor(xs / cell_size).astype(int), 0, cells_x - 1)
    row_cell = np.clip(np.floor(ys / cell_size).astype(int), 0, cells_y - 1)
    li, lj = col_line[None, :], row_line[:, None]
    rc, cc = row_cell[:, None], col_cell[None, :]
    outer_v = (li == 0) | (li == cells_x)
    outer_h = (lj == 0) | (lj == cells_y)
    on_v = (li >= 0) & (outer_v | east[rc, np.clip(li - 1, 0, cells_x - 1)])
    on_h = (lj >= 0) & (outer_h | north[np.clip(lj - 1, 0, cells_y - 1), cc])
    blocked = ((li >= 0) & (lj >= 0)) | (on_v & (lj < 0)) | (on_h & (li < 0))
    return OccupancyGrid(blocked, resolution, (0.0, 0.0, 0.0), name=f"maze{cells_x}x{cells_y}-s{seed}")


def maze_cell_center(i: int, j: int, cell_size: float = 0.5, wall: float = 0.1) -> tuple:
    """World coordinates of maze cell (i, j)'s centre (for start and goal)."""
    return (wall / 2 + (i + 0.5) * cell_size, wall / 2 + (j + 0.5) * cell_size)
