"""Moving obstacles: how an obstacle moves over time.

An obstacle in a world file may carry a ``motion``; its shape as written is
its geometry at t = 0 (what planners see: they plan against the t = 0
positions), and the simulator translates it (never rotates it) as time goes
on. Three kinds::

    motion: {velocity: [vx, vy], at_bounds: reflect}     # or at_bounds: stop
    motion: {waypoints: [[3, 4], [3, 1]], speed: 0.4, loop: true}
    motion: {between: [[3, 4], [3, 1]], speed: 0.4}       # back and forth

- ``velocity`` (m/s): a constant velocity. At the world's bounds the shape
  either *reflects* (the velocity component normal to the wall flips; the
  default) or *stops* there for good. The shape's bounding box is what
  touches the bounds.
- ``waypoints`` with ``speed`` (m/s): the shape's reference point (its
  bounding-box centre) goes from where it is drawn to each waypoint in turn
  at constant speed; with ``loop: true`` (the default) it returns from the
  last to the first and repeats, with ``loop: false`` it stops at the last.
- ``between: [a, b]`` with ``speed``: from where it is drawn to ``a``, then
  back and forth between ``a`` and ``b``.

Within one simulation step an obstacle is taken to move on a straight line
(exact for ``velocity``; a waypoint corner is cut by at most speed·dt).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, replace
from typing import Any, Dict, Optional, Tuple

import numpy as np

from ..errors import NavlabError, ParameterError
from ..limits import check_coordinate
from ..registry import suggest

Point = Tuple[float, float]
AT_BOUNDS = ("reflect", "stop")


class MotionFormatError(NavlabError):
    """A ``motion`` entry is malformed; ``field`` names the key (``motion.speed``)."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field


def _vector(value: Any, field: str) -> Point:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise MotionFormatError(field, f"expected two numbers [x, y], got {value!r}")
    try:
        return (check_coordinate(field, value[0]), check_coordinate(field, value[1]))
    except ValueError as exc:
        raise MotionFormatError(field, str(exc)) from None


def _speed(value: Any, field: str = "motion.speed") -> float:
    try:
        v = check_coordinate(field, value)
    except ValueError as exc:
        raise MotionFormatError(field, str(exc)) from None
    if not v > 0:
        raise MotionFormatError(field, f"must be a positive number of m/s, got {value!r}")
    return v


@dataclass(frozen=True)
class ConstantVelocity:
    """Constant velocity (m/s); ``at_bounds`` is ``reflect`` or ``stop``."""

    velocity: Point
    at_bounds: str = "reflect"

    def __post_init__(self) -> None:
        vx, vy = _vector(list(self.velocity) if isinstance(self.velocity, tuple) else self.velocity,
                         "motion.velocity")
        if vx == 0 and vy == 0:
            raise MotionFormatError("motion.velocity", "is zero: an obstacle that does not move needs no motion")
        if self.at_bounds not in AT_BOUNDS:
            raise MotionFormatError("motion.at_bounds", f"expected reflect or stop, got {self.at_bounds!r}."
                                    + suggest(str(self.at_bounds), list(AT_BOUNDS)))
        object.__setattr__(self, "velocity", (vx, vy))

    def to_dict(self) -> Dict[str, Any]:
        return {"velocity": list(self.velocity), "at_bounds": self.at_bounds}


@dataclass(frozen=True)
class WaypointMotion:
    """Waypoints visited at ``speed`` (m/s); ``loop`` returns to the first."""

    waypoints: Tuple[Point, ...]
    speed: float
    loop: bool = True
    back_and_forth: bool = False  #: written as ``between: [a, b]``

    def __post_init__(self) -> None:
        key = "motion.between" if self.back_and_forth else "motion.waypoints"
        if not isinstance(self.waypoints, (list, tuple)) or len(self.waypoints) < 2:
            raise MotionFormatError(key, f"needs at least two points, got {self.waypoints!r}")
        pts = tuple(_vector(list(p) if isinstance(p, tuple) else p, f"{key}[{i}]")
                    for i, p in enumerate(self.waypoints))
        if self.back_and_forth and len(pts) != 2:
            raise MotionFormatError(key, f"expected exactly two points [a, b], got {len(pts)}")
        if all(p == pts[0] for p in pts):
            raise MotionFormatError(key, "all points are the same: the obstacle would not move")
        if not isinstance(self.loop, (bool, np.bool_)):  # (numpy's bool, as check_flag takes it)
            raise MotionFormatError("motion.loop", f"expected true or false, got {self.loop!r}")
        object.__setattr__(self, "loop", bool(self.loop))
        object.__setattr__(self, "waypoints", pts)
        object.__setattr__(self, "speed", _speed(self.speed))

    def to_dict(self) -> Dict[str, Any]:
        if self.back_and_forth:
            return {"between": [list(p) for p in self.waypoints], "speed": self.speed}
        return {"waypoints": [list(p) for p in self.waypoints], "speed": self.speed, "loop": self.loop}


Motion = ConstantVelocity | WaypointMotion
_KEYS = {"velocity": {"velocity", "at_bounds"}, "waypoints": {"waypoints", "speed", "loop"},
         "between": {"between", "speed"}}


def parse_motion(raw: Any) -> Motion:
    """A motion from its world-file mapping; :class:`MotionFormatError` names the bad key."""
    if not isinstance(raw, dict):
        raise MotionFormatError("motion", f"expected a mapping (velocity, waypoints or between), got {raw!r}")
    kinds = [k for k in _KEYS if k in raw]
    if len(kinds) != 1:
        raise MotionFormatError("motion", "give exactly one of velocity, waypoints or between"
                                + (f" (got {', '.join(kinds)})" if kinds else ""))
    kind = kinds[0]
    extra = sorted(set(raw) - _KEYS[kind])
    if extra:
        valid = sorted(_KEYS[kind])
        raise MotionFormatError(f"motion.{extra[0]}", f"not a field of a {kind} motion; valid: "
                                f"{', '.join(valid)}." + suggest(str(extra[0]), valid))
    if kind == "velocity":
        return ConstantVelocity(raw["velocity"], raw.get("at_bounds", "reflect"))
    if "speed" not in raw:
        raise MotionFormatError("motion.speed", "missing (required with waypoints or between)")
    if kind == "waypoints":
        return WaypointMotion(raw["waypoints"], raw["speed"], raw.get("loop", True))
    return WaypointMotion(raw["between"], raw["speed"], True, back_and_forth=True)


def with_motion(shape, raw: Optional[Any]):
    """``shape`` carrying the motion parsed from ``raw`` (unchanged when None)."""
    return shape if raw is None else replace(shape, motion=parse_motion(raw))


def translated(shape, dx: float, dy: float):
    """The shape moved by (dx, dy), without its motion (for drawing and clearances)."""
    from .shapes import Circle, Rectangle

    if isinstance(shape, Circle):
        return Circle((shape.center[0] + dx, shape.center[1] + dy), shape.radius)
    if isinstance(shape, Rectangle):
        return Rectangle((shape.min[0] + dx, shape.min[1] + dy), (shape.max[0] + dx, shape.max[1] + dy))
    return type(shape)(tuple((x + dx, y + dy) for x, y in shape.points))


class Track:
    """Where one moving shape is: ``offset(t)`` is its displacement (m) from
    its t = 0 geometry. Built for a shape in given bounds by :func:`track`."""

    def offset(self, t: float) -> Point:
        raise NotImplementedError


class _VelocityTrack(Track):
    def __init__(self, motion: ConstantVelocity, bbox, bounds, index: int) -> None:
        self.v = motion.velocity
        self.reflect = motion.at_bounds == "reflect"
        lo = (bbox[0], bbox[1])
        size = (bbox[2] - bbox[0], bbox[3] - bbox[1])
        low_limit = (bounds.xmin, bounds.ymin)
        high_limit = (bounds.xmax - size[0], bounds.ymax - size[1])
        for axis in range(2):
            if self.v[axis] != 0 and not low_limit[axis] <= lo[axis] <= high_limit[axis]:
                raise ParameterError(f"obstacle {index}: field 'motion.velocity': the shape must lie inside the "
                                     f"bounds at t = 0 to {motion.at_bounds} at them")
        self.lo, self.low, self.high = lo, low_limit, high_limit
        if not self.reflect:  # the first time any axis reaches its limit
            times = [((high_limit[a] if self.v[a] > 0 else low_limit[a]) - lo[a]) / self.v[a]
                     for a in range(2) if self.v[a] != 0]
            self.t_stop = min(times)

    def offset(self, t: float) -> Point:
        if not self.reflect:
            s = min(t, self.t_stop)
            return (self.v[0] * s, self.v[1] * s)
        out = []
        for a in range(2):
            width = self.high[a] - self.low[a]
            free = self.lo[a] + self.v[a] * t
            if self.v[a] == 0 or width <= 0:
                out.append(0.0)
                continue
            # unfold the bounces: a triangle wave of period 2·width
            u = math.fmod(free - self.low[a], 2.0 * width)
            if u < 0:
                u += 2.0 * width
            pos = self.low[a] + (u if u <= width else 2.0 * width - u)
            out.append(pos - self.lo[a])
        return (out[0], out[1])


class _WaypointTrack(Track):
    def __init__(self, motion: WaypointMotion, bbox) -> None:
        ref = ((bbox[0] + bbox[2]) / 2.0, (bbox[1] + bbox[3]) / 2.0)
        route = [ref, *motion.waypoints]
        if motion.loop:
            route.append(motion.waypoints[0])
        pts = np.asarray(route, float)
        seg = np.hypot(*np.diff(pts, axis=0).T)
        self.ref, self.pts, self.speed = ref, pts.tolist(), motion.speed
        self.cum = np.concatenate(([0.0], np.cumsum(seg))).tolist()
        self.lead = self.cum[1]  # from the drawn position to the first waypoint
        self.cycle = self.cum[-1] - self.lead if motion.loop else 0.0

    def offset(self, t: float) -> Point:
        s = self.speed * max(t, 0.0)
        if s > self.lead:
            if self.cycle > 0:
                s = self.lead + math.fmod(s - self.lead, self.cycle)
            else:
                s = min(s, self.cum[-1])
        i = min(max(bisect.bisect_right(self.cum, s) - 1, 0), len(self.cum) - 2)
        length = self.cum[i + 1] - self.cum[i]
        f = (s - self.cum[i]) / length if length > 0 else 0.0
        a, b = self.pts[i], self.pts[i + 1]
        return (a[0] + f * (b[0] - a[0]) - self.ref[0], a[1] + f * (b[1] - a[1]) - self.ref[1])


def track(shape, bounds, index: int = 0) -> Track:
    """The track of a shape with a motion inside ``bounds`` (``index`` names it in errors)."""
    if isinstance(shape.motion, ConstantVelocity):
        return _VelocityTrack(shape.motion, shape.bbox(), bounds, index)
    return _WaypointTrack(shape.motion, shape.bbox())
