"""The checker interface through which planners and samplers see a world.

Modelled on OMPL's state validity checker and motion validator: planners ask
whether points and segments are valid and never touch geometry themselves.
The checker counts what it is asked so benchmarks can report collision checks.
Shapes and occupancy maps go through the same checker and the same packed
geometry (see :mod:`navlab.world.geometry`).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError
from . import geometry as _geo

#: [cells] how far past a surface cell's far side a boundary sampler's ray reaches
_MAP_REACH_CELLS = 2.5


def _as_points(points) -> np.ndarray:
    arr = np.ascontiguousarray(np.asarray(points, dtype=float))
    if arr.ndim == 1:
        arr = arr.reshape(1, -1)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ParameterError(f"expected points of shape (N, 2), got {np.shape(points)}")
    return arr


class CollisionChecker:
    """Exact point/segment validity against a world's inflated obstacles.

    Parameters
    ----------
    world : World
        Obstacles, robot radius (the inflation), bounds, and optionally an
        occupancy grid whose occupied cells (and unknown cells unless
        ``world.allow_unknown``) are closed square obstacles.

    Attributes
    ----------
    point_checks, segment_checks : int
        How many points / segments have been checked (one per array row).
    calls : int
        How many query calls were made.
    """

    def __init__(self, world) -> None:
        self.world = world
        self.geometry = _geo.pack_geometry(world.obstacles, world.robot_radius, world.bounds.as_array(),
                                           getattr(world, "occupancy", None),
                                           bool(getattr(world, "allow_unknown", False)))
        self._surface = None  # the map's surface cells for interior draws, found on first use
        self.point_checks = 0
        self.segment_checks = 0
        self.calls = 0

    @property
    def checks(self) -> int:
        """Points plus segments checked so far."""
        return self.point_checks + self.segment_checks

    def points_free(self, points) -> np.ndarray:
        """Bool array: each point is inside the bounds and clear of obstacles."""
        p = _as_points(points)
        self.calls += 1
        self.point_checks += len(p)
        return _geo.points_free_batch(p, self.geometry)

    def segments_free(self, a, b) -> np.ndarray:
        """Bool array: each segment ``a[i] → b[i]`` keeps clearance everywhere."""
        pa, pb = _as_points(a), _as_points(b)
        if pa.shape != pb.shape:
            raise ParameterError(f"segment ends differ in shape: {pa.shape} vs {pb.shape}")
        self.calls += 1
        self.segment_checks += len(pa)
        return _geo.segments_free_batch(pa, pb, self.geometry)

    def clearance(self, points) -> np.ndarray:
        """Distance from each point to the nearest obstacle surface (not counted)."""
        return _geo.clearance_batch(_as_points(points), self.geometry)

    def path_free(self, path) -> bool:
        """Whether every edge of a polyline is valid (one call)."""
        p = _as_points(path)
        if len(p) == 1:
            return bool(self.points_free(p)[0])
        return bool(np.all(self.segments_free(p[:-1], p[1:])))

    def add_counts(self, points: int = 0, segments: int = 0) -> None:
        """Record checks made by a compiled loop that used :attr:`geometry`."""
        self.point_checks += int(points)
        self.segment_checks += int(segments)
        self.calls += 1

    # -- what surface samplers need, for shapes and maps alike -------------
    def _map_surface(self):
        """Flat indices of the map's surface cells, cumulative weights (their
        free 4-neighbour edges) and the map's surface length in metres."""
        if self._surface is None:
            params, cells, _ = self.geometry[5]
            if cells.size == 0:
                self._surface = (np.empty(0, np.int64), np.empty(0), 0.0)
            else:
                blocked = cells < _geo.FIRST_FREE
                free = ~blocked
                edges = np.zeros(cells.shape, dtype=np.int64)
                edges[1:, :] += free[:-1, :]
                edges[:-1, :] += free[1:, :]
                edges[:, 1:] += free[:, :-1]
                edges[:, :-1] += free[:, 1:]
                edges[free] = 0
                idx = np.flatnonzero(edges)
                weights = edges.ravel()[idx].astype(float)
                self._surface = (idx, np.cumsum(weights), float(weights.sum()) * params[_geo.P_RES])
        return self._surface

    @property
    def has_obstacles(self) -> bool:
        """Whether the world has any obstacle surface (shapes or blocked map cells)."""
        return bool(self.world.obstacles) or self._map_surface()[2] > 0

    def interior_points(self, rng: np.random.Generator, n: int):
        """``n`` points inside obstacles, picked in proportion to surface length.

        Each comes with a *reach*: a length along which a ray from the point
        leaves the inflated obstacle it is in (it may enter another, which a
        caller checks). Shapes are weighted by their inflated perimeter; a
        map's blocked region by its surface length, each surface cell by its
        free edges, the point uniform inside the cell.

        Returns
        -------
        points : ndarray (n, 2)
        reach : ndarray (n,)
            Metres. Both empty when the world has no obstacles.
        """
        obstacles = self.world.obstacles
        r = self.world.robot_radius
        idx, cum, map_length = self._map_surface()
        weights = [o.perimeter(r) for o in obstacles] + ([map_length] if map_length > 0 else [])
        if not weights or n <= 0:
            return np.empty((0, 2)), np.empty(0)
        w = np.asarray(weights)
        which = rng.choice(len(w), size=n, p=w / w.sum())
        points = np.empty((n, 2))
        reach = np.empty(n)
        on_map = which == len(obstacles)
        for row in np.flatnonzero(~on_map):  # one draw per pick, in pick order
            shape = obstacles[which[row]]
            points[row] = shape.interior_points(rng, 1)[0]
            reach[row] = _shape_reach(shape, r)
        m = int(on_map.sum())
        if m:
            params, cells, _ = self.geometry[5]
            flat = idx[np.minimum(np.searchsorted(cum, rng.random(m) * cum[-1], side="right"), len(idx) - 1)]
            j, i = np.divmod(flat, cells.shape[1])
            # strictly inside the cell's square
            local = (np.column_stack((i, j)) + 0.0005 + 0.999 * rng.random((m, 2))) * params[_geo.P_RES]
            c, s = params[_geo.P_COS], params[_geo.P_SIN]
            points[on_map, 0] = params[_geo.P_OX] + local[:, 0] * c - local[:, 1] * s
            points[on_map, 1] = params[_geo.P_OY] + local[:, 0] * s + local[:, 1] * c
            reach[on_map] = r + _MAP_REACH_CELLS * params[_geo.P_RES]
        return points, reach


def _shape_reach(obstacle, inflate: float) -> float:
    """A length that takes any interior point outside the inflated shape."""
    x0, y0, x1, y1 = obstacle.bbox()
    return math.hypot(x1 - x0, y1 - y0) + inflate + 1e-6
