"""Robot footprints: a disc or a polygon (convex or not) in body coordinates.

The body frame has x forward and y to the left; a pose ``(x, y, θ)`` places
the footprint in the world by rotating its vertices by θ and moving them to
(x, y). Nav2 and move_base describe a robot the same way (``footprint:
[[x, y], ...]`` or ``robot_radius``), and so does this class:
:meth:`Footprint.from_value` reads either form.

The footprint is immutable and compared by content, so caches may hang on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Optional, Tuple

import numpy as np

from ..errors import NavlabError
from ..limits import MAX_COORDINATE, is_finite_real, shown

#: the most vertices a footprint may have (real ones have 4–20)
MAX_VERTICES = 1000


class FootprintError(NavlabError):
    """A footprint that cannot describe a robot; the message names the field."""


@dataclass(frozen=True)
class Footprint:
    """A robot's shape in its body frame: ``radius`` for a disc, else ``points``.

    Build one with :meth:`disc`, :meth:`polygon` or :meth:`from_value`.
    Vertices are stored counter-clockwise; the robot's origin (its centre of
    rotation) must lie inside the shape or on its outline.
    """

    points: Optional[Tuple[Tuple[float, float], ...]] = None
    radius: Optional[float] = None

    def __post_init__(self) -> None:
        if (self.points is None) == (self.radius is None):
            raise FootprintError("footprint: give either points (a polygon) or a radius (a disc)")
        if self.radius is not None:
            r = self.radius
            if not is_finite_real(r) or not 0 < r <= MAX_COORDINATE:  # (10**400: OverflowError until session 18)
                raise FootprintError(f"footprint radius must be a positive number of metres, at most "
                                     f"{MAX_COORDINATE:g}, got {shown(r)}")
            object.__setattr__(self, "radius", float(r))
            return
        object.__setattr__(self, "points", _checked_polygon(self.points))

    # -- construction ---------------------------------------------------------
    @classmethod
    def disc(cls, radius: float) -> "Footprint":
        """A round robot of ``radius`` metres centred on its origin."""
        return cls(radius=radius)

    @classmethod
    def polygon(cls, points: Any) -> "Footprint":
        """A polygon with body-frame vertices ``[[x, y], ...]`` (metres), either winding."""
        return cls(points=points)

    @classmethod
    def from_value(cls, value: Any, field: str = "footprint") -> "Footprint":
        """A footprint from a number (a disc's radius), a list of ``[x, y]`` vertices,
        a ``{radius: R}`` / ``{points: [...]}`` mapping, or a Footprint."""
        if isinstance(value, Footprint):
            return value
        try:
            if isinstance(value, dict):
                unknown = set(value) - {"radius", "points"}
                if unknown:
                    raise FootprintError(f"unknown key(s) {sorted(unknown)}; expected 'radius' or 'points'")
                return cls(points=value.get("points"), radius=value.get("radius"))
            if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
                return cls.disc(value)
            if isinstance(value, str):
                value = _parse_text(value)
            return cls.polygon(value)
        except FootprintError as exc:
            message = str(exc)
            prefix = "footprint"
            raise FootprintError(f"{field}{message[len(prefix):]}" if message.startswith(prefix)
                                 else f"{field}: {message}") from None

    # -- geometry -------------------------------------------------------------
    @property
    def is_disc(self) -> bool:
        return self.radius is not None

    @property
    def vertices(self) -> Optional[np.ndarray]:
        """(K, 2) body-frame vertices, counter-clockwise (read-only); None for a disc."""
        if self.points is None:
            return None
        out = np.array(self.points, dtype=float)
        out.flags.writeable = False
        return out

    @property
    def inscribed_radius(self) -> float:
        """The largest distance from the origin that is inside the footprint in every
        direction: the distance from the origin to the nearest edge (Nav2's
        ``inscribed_radius``)."""
        if self.radius is not None:
            return self.radius
        v = np.array(self.points)
        w = np.roll(v, -1, axis=0)
        d = w - v
        t = np.clip(np.einsum("ij,ij->i", -v, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
        return float(np.min(np.hypot(*(v + t[:, None] * d).T)))

    @property
    def circumscribed_radius(self) -> float:
        """The distance from the origin to the farthest vertex."""
        if self.radius is not None:
            return self.radius
        return float(np.max(np.hypot(*np.array(self.points).T)))

    @property
    def area(self) -> float:
        if self.radius is not None:
            return math.pi * self.radius ** 2
        x, y = np.array(self.points).T
        return float(0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))

    def outline(self, segments: int = 64) -> np.ndarray:
        """(K, 2) body-frame outline for drawing (a disc as a ``segments``-gon)."""
        if self.radius is None:
            return np.array(self.points, dtype=float)
        phi = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
        return self.radius * np.column_stack((np.cos(phi), np.sin(phi)))

    def at(self, pose) -> np.ndarray:
        """(K, 2) world vertices at ``pose`` (x, y, θ); a disc gives its drawing outline."""
        return self.at_many(np.asarray(pose, dtype=float).reshape(1, 3))[0]

    def at_many(self, poses) -> np.ndarray:
        """(N, K, 2) world vertices at each of ``poses`` (N, 3)."""
        poses = np.asarray(poses, dtype=float).reshape(-1, 3)
        body = self.outline()
        c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
        x = poses[:, :1] + c * body[:, 0] - s * body[:, 1]
        y = poses[:, 1:2] + s * body[:, 0] + c * body[:, 1]
        return np.stack((x, y), axis=-1)

    def padded(self, padding: float) -> "Footprint":
        """The footprint grown by ``padding`` metres (move_base's ``footprint_padding``:
        each vertex pushed ``padding`` further from the origin along both axes' signs)."""
        if not (is_finite_real(padding) and 0 <= padding <= MAX_COORDINATE):
            raise FootprintError(f"footprint_padding must be from 0 to {MAX_COORDINATE:g} m, got {shown(padding)}")
        if self.radius is not None:
            return Footprint.disc(self.radius + padding)
        v = np.array(self.points)
        return Footprint.polygon(v + np.sign(v) * padding)

    def to_value(self) -> Any:
        """The YAML form :meth:`from_value` reads back."""
        return self.radius if self.radius is not None else [list(p) for p in self.points]

    def describe(self) -> str:
        if self.radius is not None:
            return f"a disc of radius {self.radius:g} m"
        x, y = np.array(self.points).T
        return (f"a {len(self.points)}-gon of {x.max() - x.min():.3g} × {y.max() - y.min():.3g} m "
                f"(inscribed {self.inscribed_radius:.3g} m, circumscribed {self.circumscribed_radius:.3g} m)")


def _parse_text(text: str) -> Any:
    """``"[[x, y], ...]"`` (ROS parameter style) or a number, as YAML reads it (:func:`navlab.yamlio.load_value`)."""
    import yaml

    from ..yamlio import load_value

    try:
        return load_value(text)
    except (yaml.YAMLError, ValueError, RecursionError):
        raise FootprintError(f"footprint: cannot read {text[:60]!r}: expected [[x, y], ...] or a radius") from None


def _checked_polygon(points: Any) -> Tuple[Tuple[float, float], ...]:
    try:
        v = np.array(points, dtype=float)
    except (TypeError, ValueError, OverflowError):  # (OverflowError: a 400-digit vertex, until session 18)
        raise FootprintError(f"footprint points must be [[x, y], ...] numbers, got {shown(points, 60)}") from None
    if v.ndim != 2 or v.shape[1] != 2:
        raise FootprintError(f"footprint points must be [[x, y], ...] pairs, got shape {v.shape}")
    distinct = len(np.unique(v, axis=0)) if len(v) else 0
    if len(v) >= 3 and distinct < 3:
        raise FootprintError(f"footprint needs at least 3 distinct points, got {distinct} among its {len(v)}")
    if len(v) > 1 and np.array_equal(v[0], v[-1]):
        v = v[:-1]  # a closed ring: the last point repeats the first
    if len(v) < 3:
        raise FootprintError(f"footprint needs at least 3 points, got {len(v)}")
    if len(v) > MAX_VERTICES:
        raise FootprintError(f"footprint has {len(v)} points, more than the {MAX_VERTICES} supported")
    if not np.isfinite(v).all():
        raise FootprintError("footprint points must be finite numbers (got nan or inf)")
    if np.abs(v).max() > MAX_COORDINATE:
        raise FootprintError(f"footprint points must be within ±{MAX_COORDINATE:g} m")
    import shapely

    ring = shapely.LinearRing(v)
    polygon = shapely.Polygon(v)
    if shapely.Polygon(v).minimum_rotated_rectangle.area <= 0:
        raise FootprintError("footprint has no area (its points are collinear)")
    if not ring.is_simple:
        raise FootprintError("footprint is self-intersecting (its edges cross or repeat a vertex)")
    if not polygon.covers(shapely.Point(0.0, 0.0)):
        raise FootprintError("footprint does not contain the robot's origin (0, 0): give the vertices in the "
                             "body frame, centred on the point the robot turns about")
    if not ring.is_ccw:
        v = v[::-1]
    return tuple((float(x), float(y)) for x, y in v)
