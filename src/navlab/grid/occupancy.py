"""Occupancy grids: cells indexed ``[y, x]`` (row, column) with a metric frame.

A grid is immutable: its arrays are read-only copies and its fields frozen.
Planners hang search state and transforms on the grid (``_cache``); because
nothing can change under them, a plan always reflects the grid as it is.
Changes go through methods that return a new grid (:meth:`OccupancyGrid.with_blocked`,
:meth:`~OccupancyGrid.with_origin`, ...), which starts with an empty cache.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Optional, Tuple

import numpy as np

from ..errors import ParameterError
from ..limits import MAX_COORDINATE, MIN_LENGTH, check_coordinate, check_length, finite_number, float_array, shown

#: Largest number of cells navlab builds a grid of (a map image, a ``.map``,
#: a maze): 10⁸ cells is a 10 km × 10 km site at 1 m, or 500 m × 500 m at
#: 5 cm. At that size a map loads in about 0.65 GB and one A* search adds
#: 5 bytes per cell of state, as Dijkstra and JPS (6 where both A* and JPS ran; 0.88 and 0.84 GB
#: peaks measured, docs/grid.md).
#: Larger inputs are refused, with one line, before they are decoded or allocated.
MAX_CELLS = 100_000_000


def _read_only(values: Any, dtype, name: str) -> np.ndarray:
    """A C-contiguous read-only copy (a caller's later edits cannot reach it,
    and ``flags.writeable = True`` on it raises)."""
    try:
        out = np.array(values, dtype=dtype, order="C", copy=True)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be an array of {np.dtype(dtype).name}: {exc}") from None
    out.flags.writeable = False
    return out.view()  # a view of a read-only base can never be made writeable again


def _mask(values: Any, name: str) -> np.ndarray:
    """:func:`_read_only` of a true/false array: booleans, or numbers that are all 0 or 1 (numpy
    casts any non-zero to True: 0.5, NaN and the string '0' were silently blocked cells)."""
    try:
        given = np.asarray(values)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name} must be an array of bool: {exc}") from None
    if given.size > MAX_CELLS:  # before any copy (a broadcast view of 4e10 cells was copied first: API attack)
        raise ParameterError(f"{name} has {given.size} cells, more than the {MAX_CELLS:.0e} navlab supports")
    if given.dtype != bool:
        if given.dtype.kind not in "iuf":
            raise ParameterError(f"{name} must be an array of true/false (or 0/1) per cell, got dtype {given.dtype}")
        odd = np.flatnonzero((given != 0) & (given != 1))  # (a 0-d array too: its one element)
        if odd.size:
            at = np.unravel_index(int(odd[0]), given.shape)
            raise ParameterError(f"{name} must be true/false (or 0/1) per cell, got {given[at].item()!r} at index "
                                 f"{tuple(int(i) for i in at)}")
    return _read_only(given, bool, name)


@dataclass(frozen=True, eq=False)
class OccupancyGrid:
    """A 2D occupancy grid (immutable).

    Attributes
    ----------
    blocked : ndarray of bool, shape (H, W), read-only
        Occupied cells, indexed ``[y, x]``.
    resolution : float
        Metres per cell, in [MIN_LENGTH, MAX_COORDINATE] (:mod:`navlab.limits`).
    origin : tuple (x, y, yaw)
        World pose of the outer corner of cell (0, 0), as in ROS map_server
        (m, m, rad); x and y within ±MAX_COORDINATE.
    unknown : ndarray of bool, read-only
        Cells of unknown occupancy (kept from the map; planners treat them as
        blocked unless asked to allow them). All False when not given.
    name : str
    probability : ndarray of float32, read-only, optional
        Occupancy probability in [0, 1] per cell (NaN where unknown), kept
        from maps read in ``scale`` or ``raw`` mode. Planners do not use it:
        cells below certain occupancy are passable, as in Nav2's static
        costmap layer with its defaults; it is there for a cost layer.

    Examples
    --------
    >>> g = OccupancyGrid(np.zeros((3, 4), bool), resolution=0.5)
    >>> g2 = g.with_blocked(g.blocked | (np.arange(4) == 2))   # a wall in column 2
    >>> bool(g.blocked[0, 2]), bool(g2.blocked[0, 2])
    (False, True)
    """

    blocked: np.ndarray
    resolution: float = 1.0
    origin: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    unknown: Optional[np.ndarray] = None
    name: str = "grid"
    probability: Optional[np.ndarray] = None
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)
    #: built with no unknown cells (``unknown=None``): known all False without reading it
    _no_unknown: bool = field(default=False, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        put = object.__setattr__  # frozen: fields are set once, here
        blocked = _mask(self.blocked, "blocked")
        if blocked.ndim != 2 or 0 in blocked.shape:
            raise ParameterError(f"blocked must be a non-empty 2D array, got shape {blocked.shape}")
        put(self, "blocked", blocked)
        resolution = finite_number("resolution", self.resolution)
        if not MIN_LENGTH <= resolution <= MAX_COORDINATE:
            raise ParameterError(f"resolution must be between {MIN_LENGTH:g} and {MAX_COORDINATE:g} m per cell, "
                                 f"got {self.resolution!r}")
        put(self, "resolution", resolution)
        try:
            origin = tuple(self.origin)
        except TypeError:
            raise ParameterError(f"origin must be (x, y, yaw), got {self.origin!r}") from None
        if len(origin) == 2:
            origin = origin + (0.0,)
        if len(origin) != 3:
            raise ParameterError(f"origin must be (x, y, yaw), got {self.origin!r}")
        x = check_coordinate("origin x", origin[0])
        y = check_coordinate("origin y", origin[1])
        yaw = finite_number("origin yaw", origin[2])
        put(self, "origin", (x, y, yaw))
        put(self, "_no_unknown", self.unknown is None)
        unknown = np.zeros(blocked.shape, bool) if self.unknown is None else self.unknown
        unknown = _mask(unknown, "unknown")
        if unknown.shape != blocked.shape:
            raise ParameterError(f"unknown has shape {unknown.shape}, blocked {blocked.shape}")
        put(self, "unknown", unknown)
        if self.probability is not None:
            prob = _read_only(self.probability, np.float32, "probability")
            if prob.shape != blocked.shape:
                raise ParameterError(f"probability has shape {prob.shape}, blocked {blocked.shape}")
            if np.any((prob < 0) | (prob > 1)):
                raise ParameterError("probability must lie in [0, 1] (NaN for unknown)")
            put(self, "probability", prob)
        put(self, "name", str(self.name))

    def __reduce__(self):
        # rebuilt through the constructor: read-only arrays, and no cache carried along
        return (_rebuild, (self.blocked, self.resolution, self.origin, None if self._no_unknown else self.unknown,
                           self.name, self.probability))

    # -- new grids from this one ------------------------------------------------
    def replace(self, **changes: Any) -> "OccupancyGrid":
        """A new grid with some fields changed (validated like the constructor)."""
        if self._no_unknown and "unknown" not in changes and np.shape(changes.get("blocked", self.blocked)) == \
                self.blocked.shape:
            # still none: the new grid knows it without reading its zeros (a blocked of another shape is refused
            # against the unknown cells, as on a grid given them)
            changes["unknown"] = None
        return dataclasses.replace(self, **changes)

    def with_blocked(self, blocked: np.ndarray) -> "OccupancyGrid":
        """The same grid with ``blocked`` replaced (e.g. ``g.with_blocked(g.blocked | wall)``)."""
        return self.replace(blocked=blocked)

    def with_unknown(self, unknown: np.ndarray) -> "OccupancyGrid":
        """The same grid with ``unknown`` replaced: a boolean array of ``blocked``'s shape (True: cells of
        unknown occupancy, which planners treat as blocked unless asked to allow them), or None for none."""
        return self.replace(unknown=unknown)

    def with_origin(self, origin) -> "OccupancyGrid":
        """The same grid with ``origin`` replaced: the world pose (x, y[, yaw]) of the outer corner of cell
        (0, 0), in m and rad, as in ROS map_server."""
        return self.replace(origin=origin)

    # -- geometry ---------------------------------------------------------------
    @property
    def height(self) -> int:
        return self.blocked.shape[0]

    @property
    def width(self) -> int:
        return self.blocked.shape[1]

    def passable(self, allow_unknown: bool = False) -> np.ndarray:
        """Bool array of cells a planner may enter."""
        free = ~self.blocked
        return free if allow_unknown else free & ~self.unknown

    def _rotation(self) -> np.ndarray:
        c, s = math.cos(self.origin[2]), math.sin(self.origin[2])
        return np.array([[c, -s], [s, c]])

    def cell_to_world(self, cells) -> np.ndarray:
        """World coordinates (m) of cell centres; ``cells`` is (N, 2) of (x, y)."""
        try:  # (text or a wrong shape raised numpy's own TypeError or ValueError: API attack, session 29)
            if self.origin[2] == 0.0:
                # the common unrotated map in two array operations: numpy's
                # per-call overhead was a quarter of a query on den312d
                if "centre_offset" not in self._cache:
                    self._cache["centre_offset"] = np.asarray(self.origin[:2]) + 0.5 * self.resolution
                out = np.multiply(cells, self.resolution, dtype=float)
                out += self._cache["centre_offset"]
                return out
            local = (np.asarray(cells, dtype=float) + 0.5) * self.resolution
            return local @ self._rotation().T + np.asarray(self.origin[:2])
        except (TypeError, ValueError):
            raise ParameterError(f"cells: expected (x, y) numbers or an (N, 2) array, got {shown(cells)}") from None

    def world_to_cell(self, xy) -> np.ndarray:
        """Integer cells (x, y) containing world points (may lie outside the grid).

        Points must be finite (a NaN or infinite coordinate has no cell).
        """
        p = float_array(xy)  # ('ab': numpy's "could not convert string to float")
        if p.ndim not in (1, 2) or p.shape[-1] != 2:
            raise ParameterError(f"world points: expected (x, y) numbers or an (N, 2) array, got {shown(xy)}")
        if not np.all(np.isfinite(p)):
            raise ParameterError(f"world points must be finite, got {p.tolist()}")
        local = (p - np.asarray(self.origin[:2])) @ self._rotation()
        return np.floor(local / self.resolution).astype(np.int64)

    def contains(self, cells) -> np.ndarray:
        c = np.atleast_2d(np.asarray(cells))
        return (c[:, 0] >= 0) & (c[:, 0] < self.width) & (c[:, 1] >= 0) & (c[:, 1] < self.height)

    def inflate(self, radius: float) -> "OccupancyGrid":
        """A copy with every cell whose centre lies within ``radius`` metres of a
        blocked cell's centre also blocked (Euclidean distance transform)."""
        from scipy.ndimage import distance_transform_edt

        radius = check_length("inflation radius", radius)  # a finite, non-negative number within 1e7 m
        if radius == 0 or not self.blocked.any():
            return self
        dist = distance_transform_edt(~self.blocked) * self.resolution
        return self.replace(blocked=dist <= radius + 1e-12, name=f"{self.name} (inflated {radius} m)")


def check_grid(grid: Any, name: str = "grid") -> OccupancyGrid:
    """``grid`` if it is an :class:`OccupancyGrid`, else the error a planner gives for it, naming ``name``
    (an array of cells is the usual mistake: it has no resolution or origin to plan in)."""
    if not isinstance(grid, OccupancyGrid):
        raise ParameterError(f"{name} must be an OccupancyGrid (navlab.grid.OccupancyGrid(blocked, resolution=...)), "
                             f"got {type(grid).__name__}")
    return grid


def _rebuild(blocked, resolution, origin, unknown, name, probability) -> OccupancyGrid:
    return OccupancyGrid(blocked, resolution, origin, unknown, name, probability)
