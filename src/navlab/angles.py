"""Angle wrapping: the one rule every module that turns a heading uses."""

from __future__ import annotations

import math
from .errors import ParameterError


def wrap_angle(angle: float) -> float:
    """``angle`` (rad) moved by whole turns into (−π, π].

    ``fmod`` keeps the result exact for angles near ±π (a subtraction of
    ``round(angle / 2π)`` turns does not), so a heading of π stays π. For
    angles far beyond a turn the ``angle + π`` before it rounds (by up to half
    an ulp of ``angle``: 1e-8 rad at 1e8, all of it at 1e16); the start and goal
    poses a user gives are wrapped with ``math.remainder`` instead, which is
    exact at any size (:func:`finite_heading`'s callers).
    """
    a = math.fmod(angle + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi


def finite_heading(what: str, value) -> float:
    """``value`` [rad] as a float if it is a finite real number of any type (Python's, numpy's
    including ``longdouble``, an int that fits a float), else ParameterError naming ``what``."""
    import numbers

    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(f"{what} must be a finite heading in radians, got {value!r}")
    try:
        heading = float(value)
    except OverflowError:  # 10**400, Fraction(10**400, 3)
        heading = math.inf
    if math.isinf(heading) and abs(value) != math.inf:  # finite in its own type: np.longdouble('1e4000') too
        from .limits import digit_count  # (numpy's import only on this error's path)

        shown = f"an integer of {digit_count(value)} digits" if isinstance(value, numbers.Integral) else \
            "a number beyond float's range"
        raise ParameterError(f"{what} must be a finite heading in radians, got {shown}")
    if not math.isfinite(heading):
        raise ParameterError(f"{what} must be a finite heading in radians, got {value!r}")
    return heading


def planned_heading(what: str, value, degrees_hint: bool = True) -> float:
    """A heading given by a user, as planning takes it: :func:`finite_heading`, wrapped to [−π, π]
    by ``math.remainder`` (exact at any size; a heading already there is kept bit for bit), and with
    ``degrees_hint`` a :class:`HeadingWarning` when it lies beyond ±2π."""
    given = finite_heading(what, value)
    wrapped = math.remainder(given, 2.0 * math.pi)
    if degrees_hint:
        warn_beyond_a_turn(what, given, wrapped)
    return wrapped


class HeadingWarning(UserWarning):
    """A start or goal heading beyond ±2π rad: legal (headings wrap), but far more
    often degrees given where radians belong. ``warnings.filterwarnings("ignore",
    category=HeadingWarning)`` silences it; the ``navlab`` command prints it as a note."""


def warn_beyond_a_turn(what: str, value: float, wrapped: float) -> None:
    """Warn (:class:`HeadingWarning`) that heading ``what`` = ``value`` [rad], planned as
    ``wrapped``, lies beyond ±2π, with what it would be were it degrees."""
    if not abs(value) > 2.0 * math.pi:
        return
    import warnings

    # all the digits just past 2π, whose six (6.28319) would read as 2π itself
    shown = repr(float(value)) if abs(value) < 2.0 * math.pi * (1.0 + 1e-4) else f"{value:g}"
    degrees = f"{shown}° would be {math.radians(value):.4f} rad; " if abs(value) <= 360.0 else ""
    warnings.warn(f"{what} {shown} is beyond ±2π: headings are radians ({degrees}it is planned as {wrapped:.4f})",
                  HeadingWarning, stacklevel=_first_caller_outside())


def _first_caller_outside() -> int:
    """The ``stacklevel`` of the innermost caller outside navlab (and the standard library it
    calls through), so that a warning names the user's line (and Python's default filter shows
    it once per line of theirs, not once in all)."""
    import os
    import sys

    standard = os.path.dirname(os.__file__) + os.sep  # the standard library's (dataclasses.replace, functools, ...)

    def passed_through(frame) -> bool:  # by module name: a dataclass's generated __init__ has no file of its own
        name = frame.f_globals.get("__name__", "")
        return name == "navlab" or name.startswith("navlab.") or frame.f_code.co_filename.startswith(standard)

    frame, level = sys._getframe(2), 2  # level 1: warn_beyond_a_turn itself
    while frame is not None and passed_through(frame):
        frame, level = frame.f_back, level + 1
    return level
