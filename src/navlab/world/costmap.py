"""Layered 2D costmaps as Nav2's ``costmap_2d`` builds them.

A costmap is a grid of bytes over the plane, row index y and column index x,
cell (0, 0)'s lower-left corner at ``origin``. Its values are Nav2's:
``FREE_SPACE`` 0, ``INSCRIBED_INFLATED_OBSTACLE`` 253 (the robot's centre
here puts its inscribed circle on an obstacle), ``LETHAL_OBSTACLE`` 254 and
``NO_INFORMATION`` 255. :class:`LayeredCostmap` combines, as Nav2 does:

- a **static layer**: a map's occupied cells, or a world's obstacles
  rasterised (every cell whose square an obstacle reaches is lethal; a map's
  unknown cells are ``NO_INFORMATION``);
- an **obstacle layer**: cells marked lethal where LiDAR returns fall within
  ``obstacle_range`` of the sensor and cleared along each beam's ray (within
  ``raytrace_range``), Nav2's ``ObstacleLayer`` with ``marking`` and
  ``clearing``;
- an **inflation layer** (Nav2 ``InflationLayer::computeCost``): with ``d``
  the Euclidean distance from a cell's centre to the nearest lethal cell's
  centre (an exact Euclidean distance transform, scipy.ndimage), the cost is
  254 at d = 0, 253 for d ≤ the inscribed radius, and
  ``⌊252 · exp(−cost_scaling_factor · (d − inscribed))⌋`` out to
  ``inflation_radius``; beyond it the cell keeps its own cost.

A rolling-window costmap (Nav2's local costmap) is the same computed over a
window centred on the robot (:meth:`LayeredCostmap.update` with ``window``).

References
----------
D. V. Lu, D. Hershberger, W. D. Smart, "Layered Costmaps for Context-Sensitive
Navigation", IROS 2014. S. Macenski et al., "The Marathon 2: A Navigation
System", IROS 2020 (Nav2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Optional, Tuple

import numpy as np

from ..errors import NavlabError
from ..jit import njit
from ..limits import check_flag, check_length, is_finite_real, shown

FREE_SPACE = 0
INSCRIBED_INFLATED_OBSTACLE = 253
LETHAL_OBSTACLE = 254
NO_INFORMATION = 255
#: the largest cost the inflation's exponential reaches (just below INSCRIBED)
MAX_NON_OBSTACLE = 252
#: the most cells one costmap may hold (as the occupancy grids)
MAX_COSTMAP_CELLS = 100_000_000


class CostmapError(NavlabError):
    """A costmap setting that cannot work; the message names the field."""


def _read_only(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Costmap:
    """A grid of Nav2 costs (immutable).

    Attributes
    ----------
    costs : (H, W) uint8, read-only
        Indexed ``[y, x]``.
    resolution : float
        Metres per cell.
    origin : (x, y)
        World position of cell (0, 0)'s lower-left corner [m].
    """

    costs: np.ndarray
    resolution: float
    origin: Tuple[float, float] = (0.0, 0.0)
    _key: Any = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        costs = np.asarray(self.costs)
        if costs.ndim != 2 or costs.dtype != np.uint8 or costs.size == 0:
            raise CostmapError(f"costmap costs must be a non-empty (H, W) uint8 array, got {costs.dtype} "
                               f"{costs.shape}")
        object.__setattr__(self, "costs", _read_only(costs))
        if not (math.isfinite(self.resolution) and self.resolution > 0):
            raise CostmapError(f"costmap resolution must be a positive number of metres, got {self.resolution!r}")
        object.__setattr__(self, "resolution", float(self.resolution))
        object.__setattr__(self, "origin", (float(self.origin[0]), float(self.origin[1])))

    @property
    def shape(self) -> Tuple[int, int]:
        return self.costs.shape

    def world_to_cell(self, xy) -> np.ndarray:
        """(N, 2) integer cells (x, y) holding the points (may be outside the map)."""
        xy = np.asarray(xy, float).reshape(-1, 2)
        return np.floor((xy - self.origin) / self.resolution).astype(np.int64)

    def cell_to_world(self, cells) -> np.ndarray:
        """(N, 2) centres [m] of cells (x, y)."""
        cells = np.asarray(cells, float).reshape(-1, 2)
        return (cells + 0.5) * self.resolution + self.origin

    def cost_at(self, xy) -> np.ndarray:
        """(N,) costs at points; ``NO_INFORMATION`` outside the map."""
        cells = self.world_to_cell(xy)
        h, w = self.costs.shape
        inside = (cells[:, 0] >= 0) & (cells[:, 0] < w) & (cells[:, 1] >= 0) & (cells[:, 1] < h)
        out = np.full(len(cells), NO_INFORMATION, np.uint8)
        out[inside] = self.costs[cells[inside, 1], cells[inside, 0]]
        return out

    def footprint_cost(self, poses, footprint) -> np.ndarray:
        """(N,) the cost of the robot at each pose (x, y, θ), as Nav2 scores a footprint:
        the maximum over the cells under the polygon's outline (each edge traced
        cell by cell with Bresenham's line between the cells of its ends, as
        Nav2's ``FootprintCollisionChecker``); ``LETHAL`` when a vertex is off
        the map. A disc footprint costs its centre cell (the inflation's
        inscribed band already stands for its extent)."""
        poses = np.ascontiguousarray(np.asarray(poses, float).reshape(-1, 3))
        if footprint.is_disc:
            return self.cost_at(poses[:, :2])
        body = np.ascontiguousarray(footprint.vertices, dtype=float)
        out = np.empty(len(poses), np.uint8)
        _footprint_costs(self.costs, self.origin[0], self.origin[1], self.resolution, body, poses, out)
        return out

    def window(self, center_xy, width_m: float, height_m: float) -> "Costmap":
        """The part of this costmap in a ``width_m`` × ``height_m`` window centred on a point
        (cells outside the map are ``NO_INFORMATION``)."""
        nx = max(1, int(round(width_m / self.resolution)))
        ny = max(1, int(round(height_m / self.resolution)))
        c = self.world_to_cell(center_xy)[0]
        x0, y0 = int(c[0]) - nx // 2, int(c[1]) - ny // 2
        out = np.full((ny, nx), NO_INFORMATION, np.uint8)
        h, w = self.costs.shape
        sx0, sy0, sx1, sy1 = max(x0, 0), max(y0, 0), min(x0 + nx, w), min(y0 + ny, h)
        if sx0 < sx1 and sy0 < sy1:
            out[sy0 - y0:sy1 - y0, sx0 - x0:sx1 - x0] = self.costs[sy0:sy1, sx0:sx1]
        return Costmap(out, self.resolution, (self.origin[0] + x0 * self.resolution,
                                              self.origin[1] + y0 * self.resolution))

    def to_occupancy_values(self) -> np.ndarray:
        """(H, W) int8 as Nav2 publishes a costmap on ``nav_msgs/OccupancyGrid``:
        0 free, 100 lethal, 99 inscribed, −1 unknown, and 1 + 97·(c − 1)/251 between."""
        table = np.empty(256, np.int8)
        table[0] = 0
        table[1:253] = 1 + (97 * (np.arange(1, 253) - 1)) // 251
        table[INSCRIBED_INFLATED_OBSTACLE] = 99
        table[LETHAL_OBSTACLE] = 100
        table[NO_INFORMATION] = -1
        return table[self.costs]

    def passable(self) -> np.ndarray:
        """(H, W) bool: where the robot's centre may be (below ``INSCRIBED``)."""
        return self.costs < INSCRIBED_INFLATED_OBSTACLE


@njit(cache=True)
def _line_max(costs, x0, y0, x1, y1):
    """Largest cost on Bresenham's line from cell (x0, y0) to (x1, y1); LETHAL off the map."""
    h, w = costs.shape
    dx, dy = abs(x1 - x0), -abs(y1 - y0)
    sx = 1 if x0 < x1 else -1
    sy = 1 if y0 < y1 else -1
    err = dx + dy
    best = 0
    while True:
        if x0 < 0 or y0 < 0 or x0 >= w or y0 >= h:
            return LETHAL_OBSTACLE
        c = costs[y0, x0]
        if c > best:
            best = c
        if x0 == x1 and y0 == y1:
            return best
        e2 = 2 * err
        if e2 >= dy:
            err += dy
            x0 += sx
        if e2 <= dx:
            err += dx
            y0 += sy


@njit(cache=True)
def footprint_cost_one(costs, ox, oy, res, body, x, y, th):
    """The footprint cost at one pose (see :meth:`Costmap.footprint_cost`); an empty
    ``body`` (a disc) costs the centre's cell, ``NO_INFORMATION`` off the map."""
    k = body.shape[0]
    if k == 0:
        h, w = costs.shape
        cx = int(math.floor((x - ox) / res))
        cy = int(math.floor((y - oy) / res))
        if cx < 0 or cy < 0 or cx >= w or cy >= h:
            return NO_INFORMATION
        return costs[cy, cx]
    c, s = math.cos(th), math.sin(th)
    best = 0
    jx = int(math.floor((x + c * body[k - 1, 0] - s * body[k - 1, 1] - ox) / res))
    jy = int(math.floor((y + s * body[k - 1, 0] + c * body[k - 1, 1] - oy) / res))
    for i in range(k):
        ix = int(math.floor((x + c * body[i, 0] - s * body[i, 1] - ox) / res))
        iy = int(math.floor((y + s * body[i, 0] + c * body[i, 1] - oy) / res))
        v = _line_max(costs, jx, jy, ix, iy)
        if v > best:
            best = v
        jx, jy = ix, iy
    return best


@njit(cache=True)
def _footprint_costs(costs, ox, oy, res, body, poses, out):
    for n in range(poses.shape[0]):
        out[n] = footprint_cost_one(costs, ox, oy, res, body, poses[n, 0], poses[n, 1], poses[n, 2])


def inflation_costs(lethal: np.ndarray, resolution: float, inscribed_radius: float, inflation_radius: float,
                    cost_scaling_factor: float) -> np.ndarray:
    """(H, W) uint8 inflation costs around the ``lethal`` cells (Nav2's formula, see the module)."""
    if not lethal.any():
        return np.zeros(lethal.shape, np.uint8)
    from scipy.ndimage import distance_transform_edt

    d = distance_transform_edt(~lethal) * resolution
    out = np.zeros(lethal.shape, np.uint8)
    near = d <= inflation_radius
    # (the exponent capped at 0: the cells within the inscribed radius are INSCRIBED below, and a large
    # cost_scaling_factor overflowed exp there, a RuntimeWarning on the user's screen; the same costs)
    scaled = np.floor(MAX_NON_OBSTACLE * np.exp(np.minimum(0.0, -cost_scaling_factor * (d[near] - inscribed_radius))))
    out[near] = np.minimum(scaled, MAX_NON_OBSTACLE).astype(np.uint8)
    out[d <= inscribed_radius] = INSCRIBED_INFLATED_OBSTACLE
    out[lethal] = LETHAL_OBSTACLE
    return out


def _positive(name: str, value: Any, allow_zero: bool = False) -> float:
    if not is_finite_real(value) or value < 0 or (value == 0 and not allow_zero):
        raise CostmapError(f"{name} must be a {'non-negative' if allow_zero else 'positive'} number, "
                           f"got {shown(value)}")
    return float(value)


def _length(name: str, value: Any, allow_zero: bool = False) -> float:
    """:func:`_positive`, within navlab's length range (:func:`navlab.limits.check_length`): a 2e7 m
    resolution built a 1 x 1 costmap that no query could use."""
    v = _positive(name, value, allow_zero)
    try:
        return check_length(name, v, allow_zero)
    except ValueError as exc:
        raise CostmapError(str(exc)) from None


#: Nav2's inflation layer defaults: how far costs spread [m] and how fast they fall [1/m]
DEFAULT_INFLATION_RADIUS = 0.55
DEFAULT_COST_SCALING_FACTOR = 3.0


def check_costmap_resolution(resolution: Any) -> float:
    """A costmap's cell size [m], checked (a length in navlab's range)."""
    return _length("resolution", resolution)


def check_inflation(inflation_radius: Any, cost_scaling_factor: Any, inscribed: Optional[float] = None
                    ) -> Tuple[float, float]:
    """``(inflation_radius, cost_scaling_factor)`` checked: lengths in navlab's range, and, given the footprint's
    ``inscribed`` radius, an inflation radius no smaller (the costmap's own check, and the bench's before any
    trial: one rule, one message)."""
    radius = _length("inflation_radius", inflation_radius, allow_zero=True)
    if inscribed is not None and radius < inscribed:
        raise CostmapError(f"inflation_radius = {inflation_radius:g} m is below the footprint's inscribed radius "
                           f"{inscribed:g} m (footprint_padding included): cells the robot's body reaches "
                           "would cost nothing")
    return radius, _positive("cost_scaling_factor", cost_scaling_factor, allow_zero=True)


class LayeredCostmap:
    """Static, obstacle and inflation layers combined into a :class:`Costmap`.

    Parameters
    ----------
    source : World, OccupancyGrid or None
        The static layer (None: no static layer, only what the LiDAR marks).
    footprint : Footprint
        Gives the inscribed radius (the 253 band).
    inflation_radius : float
        [m] how far costs spread from obstacles (≥ the inscribed radius).
    cost_scaling_factor : float
        [1/m] the exponential's rate (Nav2's default 3.0; the BARN
        challenge's move_base uses 10).
    resolution : float, optional
        [m] cell size (default: a map's own, else 0.05 m, the challenge's).
    obstacle_range, raytrace_range : float
        [m] LiDAR returns nearer than ``obstacle_range`` mark cells, beams
        clear up to ``raytrace_range`` (the challenge's 2.5 m and 3.0 m).
    static : bool
        Whether the static layer is used (else the source only sets the extent).
    """

    def __init__(self, source, footprint, inflation_radius: float = DEFAULT_INFLATION_RADIUS,
                 cost_scaling_factor: float = DEFAULT_COST_SCALING_FACTOR, resolution: Optional[float] = None,
                 obstacle_range: float = 2.5, raytrace_range: float = 3.0, static: bool = True) -> None:
        self.footprint = footprint
        self.inscribed = footprint.inscribed_radius
        self.inflation_radius, self.cost_scaling_factor = check_inflation(inflation_radius, cost_scaling_factor,
                                                                          self.inscribed)
        self.obstacle_range = _length("obstacle_range", obstacle_range)
        self.raytrace_range = _length("raytrace_range", raytrace_range)
        self.lethal_static, self.unknown, self.resolution, self.origin = _static_layer(source, resolution,
                                                                                    check_flag("static", static))
        self.marked = np.zeros_like(self.lethal_static)
        self._static_costs: Optional[Costmap] = None

    def static_costmap(self) -> Costmap:
        """The static and inflation layers alone (computed once)."""
        if self._static_costs is None:
            self._static_costs = self._combine(self.lethal_static)
        return self._static_costs

    def _combine(self, lethal: np.ndarray) -> Costmap:
        costs = inflation_costs(lethal, self.resolution, self.inscribed, self.inflation_radius,
                                self.cost_scaling_factor)
        costs[self.unknown & ~lethal & (costs == 0)] = NO_INFORMATION
        return Costmap(costs, self.resolution, self.origin)

    def update(self, sensor_xy=None, points=None, window: Optional[Tuple[float, float]] = None,
               center=None) -> Costmap:
        """Mark and clear the obstacle layer from one scan's ``points`` (N, 2) seen from
        ``sensor_xy``, then the master costmap (a rolling ``window`` (w, h) [m] around ``center``
        when given)."""
        if points is not None and len(points):
            _mark_and_clear(self.marked, self.origin[0], self.origin[1], self.resolution,
                            np.asarray(sensor_xy, float), np.ascontiguousarray(points, dtype=float),
                            self.obstacle_range, self.raytrace_range)
        if points is None and not self.marked.any():
            full = self.static_costmap()
        else:
            full = self._combine(self.lethal_static | self.marked)
        return full.window(center, *window) if window is not None else full


@njit(cache=True)
def _mark_and_clear(marked, ox, oy, res, sensor, points, obstacle_range, raytrace_range):
    """Nav2 ObstacleLayer: clear every cell a beam crosses before its end (up to the
    raytrace range), then mark the cell of each return within the obstacle range."""
    h, w = marked.shape
    sx = int(math.floor((sensor[0] - ox) / res))
    sy = int(math.floor((sensor[1] - oy) / res))
    for n in range(points.shape[0]):
        px, py = points[n, 0], points[n, 1]
        dist = math.hypot(px - sensor[0], py - sensor[1])
        if dist > raytrace_range:
            scale = raytrace_range / dist
            px, py = sensor[0] + (px - sensor[0]) * scale, sensor[1] + (py - sensor[1]) * scale
        ex = int(math.floor((px - ox) / res))
        ey = int(math.floor((py - oy) / res))
        x, y = sx, sy
        dx, dy = abs(ex - x), -abs(ey - y)
        stx = 1 if x < ex else -1
        sty = 1 if y < ey else -1
        err = dx + dy
        while not (x == ex and y == ey):
            if 0 <= x < w and 0 <= y < h:
                marked[y, x] = False
            e2 = 2 * err
            if e2 >= dy:
                err += dy
                x += stx
            if e2 <= dx:
                err += dx
                y += sty
    for n in range(points.shape[0]):
        px, py = points[n, 0], points[n, 1]
        if math.hypot(px - sensor[0], py - sensor[1]) <= obstacle_range:
            x = int(math.floor((px - ox) / res))
            y = int(math.floor((py - oy) / res))
            if 0 <= x < w and 0 <= y < h:
                marked[y, x] = True


def _static_layer(source, resolution: Optional[float], static: bool):
    """(lethal, unknown, resolution, origin) of the static layer over the source's extent."""
    blocked = getattr(source, "blocked", None)
    if blocked is not None:  # an occupancy grid: its own cells
        if float(source.origin[2]) != 0.0:
            raise CostmapError("a costmap needs an unrotated map (origin yaw 0)")
        if resolution is not None and not math.isclose(resolution, source.resolution):
            raise CostmapError(f"resolution: a map's costmap uses the map's cells ({source.resolution:g} m), "
                               f"got {resolution!r}")
        lethal = np.array(source.blocked, bool) if static else np.zeros(source.blocked.shape, bool)
        unknown = np.array(source.unknown, bool) if static else np.zeros(source.blocked.shape, bool)
        return lethal, unknown & ~lethal, float(source.resolution), (float(source.origin[0]), float(source.origin[1]))
    res = check_costmap_resolution(0.05 if resolution is None else resolution)
    b = source.bounds
    nx, ny = int(math.ceil((b.xmax - b.xmin) / res - 1e-9)), int(math.ceil((b.ymax - b.ymin) / res - 1e-9))
    if nx * ny > MAX_COSTMAP_CELLS:
        raise CostmapError(f"resolution {res:g} m makes a {nx} × {ny} costmap, more than {MAX_COSTMAP_CELLS:.0e} "
                           "cells")
    lethal = np.zeros((ny, nx), bool)
    if static:
        from .raster import block_obstacles

        block_obstacles(lethal, (b.xmin, b.ymin), res, [o for o in source.obstacles if o.motion is None], 0.0, 0.0)
    return lethal, np.zeros_like(lethal), res, (float(b.xmin), float(b.ymin))


def build_costmap(source, footprint, inflation_radius: float = DEFAULT_INFLATION_RADIUS,
                  cost_scaling_factor: float = DEFAULT_COST_SCALING_FACTOR,
                  resolution: Optional[float] = None) -> Costmap:
    """The static and inflation layers of ``source`` (a World or OccupancyGrid) for a footprint."""
    return LayeredCostmap(source, footprint, inflation_radius, cost_scaling_factor, resolution).static_costmap()
