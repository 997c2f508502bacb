"""Conservative rasterisation: the grid a grid planner searches for a World.

A grid planner moves between cell centres, and every step between two
neighbouring free cells (diagonal steps only when both orthogonal neighbours
are free, line-of-sight tests over every cell a segment touches) stays inside
the closed squares of free cells. So a cell is blocked when *any part* of its
square comes within the robot radius of an obstacle; then every grid path is
collision-free in the exact world, whatever the resolution. Cell-centre tests
would not give that guarantee: an obstacle can reach into a cell without
covering its centre.

Distances are exact: analytic for circles and axis-aligned rectangles,
shapely's exact polygon distance for polygons. Maps keep their own cells;
the robot radius blocks every cell whose square lies within that radius of
an occupied (or unknown, unless allowed) cell's square.

World objects are read duck-typed (``bounds``, ``obstacles``,
``robot_radius``, ``occupancy``, ``allow_unknown``); the exact cell test is
:func:`navlab.world.raster.block_obstacles`, shared with the costmaps.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..errors import ParameterError
from ..limits import is_finite_real, shown
from ..world.raster import block_obstacles  # noqa: F401  (re-exported: the grid's rasteriser uses it)
from .occupancy import MAX_CELLS, OccupancyGrid  # MAX_CELLS: the largest grid navlab makes or reads

DEFAULT_CELLS_ALONG_LONGER_SIDE = 200  #: default resolution = longer side of the bounds / this


def default_resolution(bounds) -> float:
    """1/200 of the bounds' longer side (m)."""
    return max(bounds.xmax - bounds.xmin, bounds.ymax - bounds.ymin) / DEFAULT_CELLS_ALONG_LONGER_SIDE


def grid_shape(bounds, resolution: float) -> tuple[int, int]:
    """(width, height) in whole cells inside ``bounds``; raises before anything is allocated.

    The grid starts at the bounds' lower-left corner and holds only whole
    cells, so a sliver narrower than a cell along the upper edges is left out
    (conservative: every cell lies inside the bounds).
    """
    if not is_finite_real(resolution) or resolution <= 0:
        raise ParameterError(f"resolution must be a positive number of metres per cell, got {shown(resolution)}")
    sx, sy = bounds.xmax - bounds.xmin, bounds.ymax - bounds.ymin
    # a hair of slack so that 10 m / 0.05 m counts 200 cells, not 199
    fx, fy = sx / resolution * (1 + 1e-12), sy / resolution * (1 + 1e-12)
    if not fx * fy <= MAX_CELLS:  # counted in floats: 1e-300 m cells are more than an int can format
        # (no product: at 1e-300 m it said "= inf cells")
        raise ParameterError(f"resolution {resolution:g} m would rasterise the {sx:g} m x {sy:g} m bounds to "
                             f"{fx:.3g} x {fy:.3g} cells, more than {MAX_CELLS:.0e}; use a coarser resolution")
    nx, ny = math.floor(fx), math.floor(fy)
    if nx < 1 or ny < 1:
        raise ParameterError(f"resolution {resolution:g} m is larger than the {sx:g} m x {sy:g} m bounds")
    return nx, ny


def _margin(bounds) -> float:
    """Floating-point slack (m) added to every clearance test, so rounding never frees a cell."""
    scale = max(1.0, abs(bounds.xmin), abs(bounds.xmax), abs(bounds.ymin), abs(bounds.ymax))
    return 1e-9 * scale


def inflate_cells(blocked: np.ndarray, resolution: float, radius: float, margin: float = 0.0) -> np.ndarray:
    """Block every cell whose square is closer than ``radius`` (+ ``margin``)
    to a blocked cell's square (squares that touch are 0 m apart)."""
    if radius <= 0 or not blocked.any():
        return blocked.copy()
    from scipy.ndimage import binary_dilation

    k = math.ceil(radius / resolution) + 1
    d = np.arange(-k, k + 1)
    gap = np.maximum(np.abs(d) - 1, 0) * resolution
    footprint = np.hypot(gap[None, :], gap[:, None]) < radius + margin
    return binary_dilation(blocked, structure=footprint)


def rasterize(world, resolution: Optional[float] = None) -> OccupancyGrid:
    """The grid a grid planner searches for ``world``.

    Parameters
    ----------
    world : World
        A geometric world, or one carrying an ``occupancy`` map.
    resolution : float, optional
        Metres per cell for geometric worlds (default: :func:`default_resolution`).
        A map is searched on its own cells; giving a resolution for it is an error.

    Returns
    -------
    OccupancyGrid
        ``blocked`` is every cell the robot may not enter (occupied, unknown
        unless ``world.allow_unknown``, or within the robot radius of either);
        its ``unknown`` is empty.

    Raises
    ------
    ParameterError
        A bad resolution, one giving more than :data:`MAX_CELLS` cells (before
        anything is allocated), or a resolution for a map.
    """
    r = world.robot_radius
    margin = _margin(world.bounds)
    grid = world.occupancy
    if grid is not None:
        if resolution is not None:
            raise ParameterError(f"resolution: a map is planned on its own cells ({grid.resolution:g} m); "
                                 "leave resolution out")
        # Many queries on one map (a benchmark, a ROS node) share its raster and
        # so its search buffers. A grid is immutable (read-only arrays, frozen
        # fields), so a raster hung on it can never go stale.
        cache = getattr(grid, "_cache", None)
        key = ("navlab.plan raster", r, bool(world.allow_unknown), tuple(world.obstacles))
        if isinstance(cache, dict) and key in cache:
            return cache[key]
        blocked = ~grid.passable(world.allow_unknown)
        blocked = inflate_cells(blocked, grid.resolution, r, margin)
        if world.obstacles:
            if grid.origin[2] != 0.0:
                raise ParameterError("obstacles on a rotated map (origin yaw != 0) cannot be rasterised onto its cells")
            block_obstacles(blocked, grid.origin[:2], grid.resolution, world.obstacles, r, margin)
        raster = OccupancyGrid(blocked, grid.resolution, grid.origin, name=grid.name)
        if isinstance(cache, dict):
            for old in [k for k in cache if isinstance(k, tuple) and k and k[0] == "navlab.plan raster"]:
                del cache[old]  # one raster per map: a new radius replaces the old one
            cache[key] = raster
        return raster
    if resolution is None:
        resolution = default_resolution(world.bounds)
    nx, ny = grid_shape(world.bounds, resolution)
    blocked = np.zeros((ny, nx), dtype=bool)
    origin = (world.bounds.xmin, world.bounds.ymin)
    block_obstacles(blocked, origin, float(resolution), world.obstacles, r, margin)
    return OccupancyGrid(blocked, float(resolution), (*origin, 0.0), name=world.name)
