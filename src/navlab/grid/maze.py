"""Perfect mazes (one path between any two cells) as occupancy grids."""

from __future__ import annotations

from typing import Callable, Optional

import numpy as np

from ..errors import ParameterError
from ..limits import MAX_COORDINATE, available_memory, check_count, check_length, check_seed, shown
from .occupancy import MAX_CELLS, OccupancyGrid

#: Bytes a maze cell costs while it is carved: three bool arrays and, at
#: worst, one (x, y) tuple on the Python stack (~120 B measured).
BYTES_PER_MAZE_CELL = 130
#: Bytes a map pixel costs at the peak of :func:`make_maze` and ``save_map``:
#: the broadcast wall masks, the grid's two arrays and the flipped image.
BYTES_PER_PIXEL = 12


def maze_size(cells_x: int, cells_y: int, cell_size: float, wall: float, resolution: float) -> tuple:
    """The map's size in pixels (nx, ny), after checking the maze fits: at
    most MAX_CELLS pixels, walls and corridors at least a pixel wide, and an
    estimate of the memory it needs below what the machine has available.
    Raises ParameterError naming the parameter, before anything is allocated."""
    cell_size, wall, resolution = (check_length(name, v, allow_zero=False) for name, v in
                                   (("cell_size", cell_size), ("wall", wall), ("resolution", resolution)))
    if wall >= cell_size:
        raise ParameterError(f"wall ({wall:g} m) must be thinner than cell_size ({cell_size:g} m)")
    extent = max(cells_x, cells_y) * cell_size + wall
    if extent > MAX_COORDINATE:
        raise ParameterError(f"a {cells_x}x{cells_y}-cell maze of {cell_size:g} m cells is {extent:.3g} m across, more "
                             f"than the {MAX_COORDINATE:g} m navlab supports")
    if wall < resolution:
        raise ParameterError(f"resolution {resolution:g} m is coarser than the {wall:g} m wall: walls would vanish "
                             f"from the map; use a resolution of at most {wall:g} m")
    if cell_size - wall < resolution:
        raise ParameterError(f"resolution {resolution:g} m is coarser than the {cell_size - wall:g} m corridor "
                             f"(cell_size - wall): corridors would vanish; use a resolution of at most "
                             f"{cell_size - wall:g} m")
    nx = int(round((cells_x * cell_size + wall) / resolution))
    ny = int(round((cells_y * cell_size + wall) / resolution))
    if nx * ny > MAX_CELLS:
        raise ParameterError(f"a {cells_x}x{cells_y}-cell maze at {resolution:g} m is a {nx:.3g}x{ny:.3g}-pixel map, more than "
                             f"the {MAX_CELLS:.0e} cells navlab supports; use fewer cells or a coarser resolution")
    need = cells_x * cells_y * BYTES_PER_MAZE_CELL + nx * ny * BYTES_PER_PIXEL
    have = available_memory()
    if have is not None and need > have:
        raise ParameterError(f"a {cells_x}x{cells_y}-cell maze ({nx}x{ny} pixels) needs about {need / 2**30:.1f} GiB, "
                             f"more than the {have / 2**30:.1f} GiB available")
    return nx, ny


def maze_walls(cells_x: int, cells_y: int, rng: np.random.Generator,
               progress: Optional[Callable[[int], None]] = None):
    """Carve a perfect maze by randomized depth-first search (recursive backtracker).

    Returns ``(east, north)`` bool arrays of shape (cells_y, cells_x): whether
    the wall on the cell's east / north side stands. ``progress(n)``, when
    given, is called with the number of cells carved so far (every 1024 cells
    and at the end).
    """
    east = np.ones((cells_y, cells_x), dtype=bool)
    north = np.ones((cells_y, cells_x), dtype=bool)
    seen = np.zeros((cells_y, cells_x), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True
    carved = 1
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
        carved += 1
        if progress is not None and carved % 1024 == 0:
            progress(carved)
    if progress is not None:
        progress(carved)
    return east, north


def make_maze(cells_x: int = 10, cells_y: int = 10, seed=0, cell_size: float = 0.5,
              wall: float = 0.1, resolution: float = 0.05,
              progress: Optional[Callable[[int], None]] = None) -> OccupancyGrid:
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
        Grid resolution, m per pixel: at most the wall thickness and the
        corridor width (``cell_size − wall``), so neither vanishes from the map.
    progress : callable, optional
        Called with the number of maze cells carved (see :func:`maze_walls`).

    Raises
    ------
    ParameterError
        Naming the parameter: bad sizes, a resolution too coarse for the
        walls, or a maze whose map exceeds MAX_CELLS pixels or the memory
        available (checked before anything is allocated; :func:`maze_size`).

    Cell (i, j) of the maze has its centre at world
    ``(wall/2 + (i + 0.5)·cell_size, wall/2 + (j + 0.5)·cell_size)``.
    """
    # numpy's integers count too, and the seed and progress are checked here, not by numpy (a raw ValueError
    # or TypeError for seed=-1 or progress=5: API attack, session 29)
    cells_x, cells_y = (check_count(name, v) for name, v in (("cells_x", cells_x), ("cells_y", cells_y)))
    check_seed(seed)
    if progress is not None and not callable(progress):
        raise ParameterError(f"progress must be a callable taking a count, or None, got {shown(progress)}")
    if cells_x * cells_y > MAX_CELLS:
        raise ParameterError(f"a {cells_x}x{cells_y}-cell maze has more than the {MAX_CELLS:.0e} cells navlab supports")
    nx, ny = maze_size(cells_x, cells_y, cell_size, wall, resolution)
    rng = np.random.default_rng(seed)
    east, north = maze_walls(cells_x, cells_y, rng, progress)
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
