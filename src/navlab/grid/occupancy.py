"""Occupancy grids: cells indexed ``[y, x]`` (row, column) with a metric frame."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np


@dataclass(eq=False)
class OccupancyGrid:
    """A 2D occupancy grid.

    Attributes
    ----------
    blocked : ndarray of bool, shape (H, W)
        Occupied cells, indexed ``[y, x]``.
    resolution : float
        Metres per cell.
    origin : tuple (x, y, yaw)
        World pose of the outer corner of cell (0, 0), as in ROS map_server.
    unknown : ndarray of bool, optional
        Cells of unknown occupancy (kept from the map; planners treat them as
        blocked unless asked to allow them).
    name : str
    """

    blocked: np.ndarray
    resolution: float = 1.0
    origin: Tuple[float, float, float] = (0.0, 0.0, 0.0)
    unknown: Optional[np.ndarray] = None
    name: str = "grid"
    _cache: dict = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        self.blocked = np.ascontiguousarray(np.asarray(self.blocked, dtype=bool))
        if self.blocked.ndim != 2 or 0 in self.blocked.shape:
            raise ValueError(f"blocked must be a non-empty 2D array, got shape {self.blocked.shape}")
        if not (isinstance(self.resolution, (int, float)) and self.resolution > 0 and math.isfinite(self.resolution)):
            raise ValueError(f"resolution must be a positive number of metres per cell, got {self.resolution!r}")
        self.resolution = float(self.resolution)
        origin = tuple(float(v) for v in self.origin)
        if len(origin) == 2:
            origin = origin + (0.0,)
        if len(origin) != 3:
            raise ValueError(f"origin must be (x, y, yaw), got {self.origin!r}")
        self.origin = origin
        if self.unknown is None:
            self.unknown = np.zeros_like(self.blocked)
        self.unknown = np.ascontiguousarray(np.asarray(self.unknown, dtype=bool))
        if self.unknown.shape != self.blocked.shape:
            raise ValueError("unknown and blocked differ in shape")

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

    def world_to_cell(self, xy) -> np.ndarray:
        """Integer cells (x, y) containing world points (may lie outside the grid)."""
        p = np.asarray(xy, dtype=float)
        local = (p - np.asarray(self.origin[:2])) @ self._rotation()
        return np.floor(local / self.resolution).astype(np.int64)

    def contains(self, cells) -> np.ndarray:
        c = np.atleast_2d(np.asarray(cells))
        return (c[:, 0] >= 0) & (c[:, 0] < self.width) & (c[:, 1] >= 0) & (c[:, 1] < self.height)

    def inflate(self, radius: float) -> "OccupancyGrid":
        """A copy with every cell whose centre lies within ``radius`` metres of a
        blocked cell's centre also blocked (Euclidean distance transform)."""
        from scipy.ndimage import distance_transform_edt

        if not (radius >= 0 and math.isfinite(radius)):
            raise ValueError(f"inflation radius must be a non-negative number of metres, got {radius!r}")
        if radius == 0 or not self.blocked.any():
            return OccupancyGrid(self.blocked.copy(), self.resolution, self.origin, self.unknown.copy(), self.name)
        dist = distance_transform_edt(~self.blocked) * self.resolution
        return OccupancyGrid(dist <= radius + 1e-12, self.resolution, self.origin, self.unknown.copy(),
                             f"{self.name} (inflated {radius} m)")
