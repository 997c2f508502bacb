"""Obstacle shapes: circles, axis-aligned rectangles and simple polygons.

Shapes are immutable values in metres. A shape may carry a ``motion``
(:mod:`navlab.world.motion`): its geometry is then the one at t = 0, which
is what the packed geometry, and so every planner, sees. Collision queries never loop over
these objects; :mod:`navlab.world.geometry` packs them into flat arrays for
the compiled kernels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Dict, Optional, Tuple

import numpy as np
from ..errors import ParameterError
from ..limits import float_array, is_finite_real, shown

Point = Tuple[float, float]


def _motion_dict(shape, out: Dict[str, Any]) -> Dict[str, Any]:
    if shape.motion is not None:
        out["motion"] = shape.motion.to_dict()
    return out


def _point(value: Any, what: str) -> Point:
    arr = float_array(value)  # (text: numpy's own "could not convert string to float"; API attack)
    if arr.shape != (2,) or not np.all(np.isfinite(arr)):
        raise ParameterError(f"{what} must be two finite numbers [x, y], got {value!r}")
    return (float(arr[0]), float(arr[1]))


def _polygon_points(points: Any) -> Tuple[Point, ...]:
    pts = tuple(_point(p, "polygon point") for p in points)
    if len(pts) < 3:
        raise ParameterError(f"polygon needs at least 3 points, got {len(pts)}")
    return pts


@dataclass(frozen=True)
class Circle:
    """A disc with ``center`` (m) and ``radius`` (m)."""

    center: Point
    radius: float
    motion: Optional[Any] = None  #: a :mod:`navlab.world.motion` motion; the shape is its t = 0 geometry

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _point(self.center, "circle center"))
        if not (is_finite_real(self.radius) and self.radius > 0):  # (10**400: OverflowError until session 18)
            raise ParameterError(f"circle radius must be positive, got {shown(self.radius)}")
        object.__setattr__(self, "radius", float(self.radius))

    def bbox(self) -> Tuple[float, float, float, float]:
        (x, y), r = self.center, self.radius
        return (x - r, y - r, x + r, y + r)

    def perimeter(self, inflate: float = 0.0) -> float:
        return 2 * math.pi * (self.radius + inflate)

    def interior_points(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """``n`` points uniformly inside the disc."""
        rho = self.radius * np.sqrt(rng.random(n)) * 0.999
        phi = rng.random(n) * 2 * math.pi
        return np.column_stack((self.center[0] + rho * np.cos(phi), self.center[1] + rho * np.sin(phi)))

    def to_dict(self) -> Dict[str, Any]:
        return _motion_dict(self, {"type": "circle", "center": list(self.center), "radius": self.radius})


@dataclass(frozen=True)
class Rectangle:
    """An axis-aligned rectangle from corner ``min`` to corner ``max`` (m)."""

    min: Point
    max: Point
    motion: Optional[Any] = None  #: see :class:`Circle`

    def __post_init__(self) -> None:
        lo = _point(self.min, "rectangle min")
        hi = _point(self.max, "rectangle max")
        if not (hi[0] > lo[0] and hi[1] > lo[1]):
            raise ParameterError(f"rectangle max {hi} must exceed min {lo} in x and y")
        object.__setattr__(self, "min", lo)
        object.__setattr__(self, "max", hi)

    def bbox(self) -> Tuple[float, float, float, float]:
        return (self.min[0], self.min[1], self.max[0], self.max[1])

    def perimeter(self, inflate: float = 0.0) -> float:
        w, h = self.max[0] - self.min[0], self.max[1] - self.min[1]
        return 2 * (w + h) + 2 * math.pi * inflate

    def interior_points(self, rng: np.random.Generator, n: int) -> np.ndarray:
        lo, hi = np.array(self.min), np.array(self.max)
        centre, half = (lo + hi) / 2, (hi - lo) / 2 * 0.999
        return centre + (rng.random((n, 2)) * 2 - 1) * half

    def to_dict(self) -> Dict[str, Any]:
        return _motion_dict(self, {"type": "rectangle", "min": list(self.min), "max": list(self.max)})


@dataclass(frozen=True)
class Polygon:
    """A simple polygon given by its vertices (m), in either orientation."""

    points: Tuple[Point, ...]
    motion: Optional[Any] = None  #: see :class:`Circle`

    def __post_init__(self) -> None:
        pts = _polygon_points(self.points)
        import shapely  # here, not at the top: a built-in scene's polygons need none (see _known_simple)

        shape = shapely.Polygon(pts)
        if not shape.is_valid or shape.area <= 0:
            raise ParameterError(f"polygon {pts} is not simple (edges cross or it has no area)")
        object.__setattr__(self, "points", pts)

    @classmethod
    def _known_simple(cls, points, motion: Optional[Any] = None) -> "Polygon":
        """A polygon whose outline is a constant already proven simple, made without shapely.

        navlab's built-in scenes (:mod:`navlab.world.scenes`) hold fixed
        outlines; tests/world/test_world_validation.py checks every one of
        them with shapely, as the constructor would. Building them this way
        keeps shapely's import (~15 ms) out of ``navlab plan clutter``. The
        points are still read as the constructor reads them (two finite
        numbers each, at least three); a polygon from a file or a caller
        goes through the constructor, whose checks and messages are unchanged.
        """
        polygon = object.__new__(cls)
        object.__setattr__(polygon, "points", _polygon_points(points))
        object.__setattr__(polygon, "motion", motion)
        return polygon

    def bbox(self) -> Tuple[float, float, float, float]:
        a = np.asarray(self.points)
        return (a[:, 0].min(), a[:, 1].min(), a[:, 0].max(), a[:, 1].max())

    def perimeter(self, inflate: float = 0.0) -> float:
        a = np.asarray(self.points)
        edges = np.roll(a, -1, axis=0) - a
        return float(np.hypot(edges[:, 0], edges[:, 1]).sum()) + 2 * math.pi * inflate

    @cached_property
    def _triangles(self) -> Tuple[np.ndarray, np.ndarray]:
        """The polygon's triangles (k, 3, 2) and their area shares, computed once."""
        import shapely

        shape = shapely.Polygon(self.points)
        tris = [np.asarray(t.exterior.coords)[:3] for t in shapely.delaunay_triangles(shape).geoms]
        tris_arr = np.asarray([t for t in tris if shape.contains(shapely.Polygon(t).centroid)])
        v1 = tris_arr[:, 1] - tris_arr[:, 0]
        v2 = tris_arr[:, 2] - tris_arr[:, 0]
        areas = np.abs(v1[:, 0] * v2[:, 1] - v1[:, 1] * v2[:, 0])
        return tris_arr, areas / areas.sum()

    def interior_points(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """Uniform points inside the polygon via its triangulation."""
        tris_arr, shares = self._triangles
        v1 = tris_arr[:, 1] - tris_arr[:, 0]
        v2 = tris_arr[:, 2] - tris_arr[:, 0]
        pick = rng.choice(len(tris_arr), size=n, p=shares)
        u, v = rng.random(n), rng.random(n)
        flip = u + v > 1
        u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
        # Shrink toward the triangle's centroid so points are strictly inside.
        base = tris_arr[pick, 0] + u[:, None] * v1[pick] + v[:, None] * v2[pick]
        centroid = tris_arr[pick].mean(axis=1)
        return centroid + 0.999 * (base - centroid)

    def to_dict(self) -> Dict[str, Any]:
        return _motion_dict(self, {"type": "polygon", "points": [list(p) for p in self.points]})


Obstacle = Circle | Rectangle | Polygon
