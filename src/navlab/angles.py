"""Angle wrapping: the one rule every module that turns a heading uses."""

from __future__ import annotations

import math


def wrap_angle(angle: float) -> float:
    """``angle`` (rad) moved by whole turns into (−π, π].

    ``fmod`` keeps the result exact for angles near ±π (a subtraction of
    ``round(angle / 2π)`` turns does not), so a heading of π stays π.
    """
    a = math.fmod(angle + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi
