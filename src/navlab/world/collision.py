"""The checker interface through which planners and samplers see a world.

Modelled on OMPL's state validity checker and motion validator: planners ask
whether points and segments are valid and never touch geometry themselves.
The checker counts what it is asked so benchmarks can report collision checks.
"""

from __future__ import annotations

import numpy as np

from . import geometry as _geo


def _as_points(points) -> np.ndarray:
    arr = np.ascontiguousarray(np.asarray(points, dtype=float))
    if arr.ndim == 1:
        arr = arr.reshape(1, -1)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"expected points of shape (N, 2), got {np.shape(points)}")
    return arr


class CollisionChecker:
    """Exact point/segment validity against a world's inflated obstacles.

    Parameters
    ----------
    world : World
        Obstacles, robot radius (the inflation) and bounds.

    Attributes
    ----------
    point_checks, segment_checks : int
        How many points / segments have been checked (one per array row).
    calls : int
        How many query calls were made.
    """

    def __init__(self, world) -> None:
        self.world = world
        self.geometry = _geo.pack_geometry(world.obstacles, world.robot_radius, world.bounds.as_array())
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
            raise ValueError(f"segment ends differ in shape: {pa.shape} vs {pb.shape}")
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
