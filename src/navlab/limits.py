"""The numeric range navlab supports, in one place.

Geometry kernels square coordinates; near 1e154 those squares overflow and a
segment can pass straight through a circle. navlab therefore accepts only
finite coordinates and lengths within :data:`MAX_COORDINATE` metres (far
beyond any robot's workspace, and small enough that every squared distance
and every sum of them stays exact enough in float64), and positive lengths
(radii, resolutions, tolerances) of at least :data:`MIN_LENGTH`. Input is
checked against these at the boundary (world and map files, the CLI, the
``World`` constructor); kernels may rely on them.
"""

from __future__ import annotations

import math
from typing import Any

MAX_COORDINATE = 1.0e7  #: [m] largest |x| or |y| of any point, and largest length
MIN_LENGTH = 1.0e-9  #: [m] smallest positive length (radius, resolution, tolerance)


def check_coordinate(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite number within ±MAX_COORDINATE, else ValueError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        v = float(value)
    except OverflowError:
        raise ValueError(f"{name} is too large (|{name}| ≤ {MAX_COORDINATE:g} m)") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if abs(v) > MAX_COORDINATE:
        raise ValueError(f"{name} = {v:g} is out of range (|{name}| ≤ {MAX_COORDINATE:g} m)")
    return v


def check_length(name: str, value: Any, allow_zero: bool = True) -> float:
    """A non-negative (or positive) length within [MIN_LENGTH, MAX_COORDINATE], else ValueError naming ``name``."""
    v = check_coordinate(name, value)
    if v < 0 or (v == 0 and not allow_zero):
        raise ValueError(f"{name} must be {'non-negative' if allow_zero else 'positive'}, got {value!r}")
    if 0 < v < MIN_LENGTH:
        raise ValueError(f"{name} = {v:g} is below the smallest supported length {MIN_LENGTH:g} m")
    return v
