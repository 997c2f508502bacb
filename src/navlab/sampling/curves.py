"""Paths of circular arcs and straight segments at a fixed turning radius.

The shortest paths of a car-like robot (Dubins 1957 forward only, Reeds and
Shepp 1990 forward and reverse) are words of at most five such segments. This
module holds what both share: the segment codes, the :class:`CurvePath` they
return, and tracing a word into poses at any spacing.

Conventions, as in both papers: lengths are in units of the turning radius
while a word is solved (:mod:`navlab.sampling.dubins`,
:mod:`navlab.sampling.reeds_shepp`) and in metres in a :class:`CurvePath`; a
negative segment length is driven in reverse; ``L`` turns counter-clockwise
(left) when driving forward, ``R`` clockwise, ``S`` is straight.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Tuple

import numpy as np

from ..angles import planned_heading, wrap_angle as _wrap
from ..errors import ParameterError
from ..jit import njit
from ..limits import check_coordinate, check_length

NOP, LEFT, STRAIGHT, RIGHT = 0, 1, 2, 3  #: segment codes in the compiled kernels
#: a segment code's letter in a word
LETTERS = {LEFT: "L", STRAIGHT: "S", RIGHT: "R"}
MAX_SEGMENTS = 5  #: the longest Reeds–Shepp word (CCSCC)
NEGLIGIBLE = 1e-12  #: a segment shorter than this many turning radii is rounding, not motion


def check_pose(name: str, pose, degrees_hint: bool = False) -> Tuple[float, float, float]:
    """``pose`` as three floats ``(x, y, θ)``, θ wrapped to [−π, π] (exactly: a heading
    already there is kept bit for bit); ParameterError naming ``name`` if it is not three
    finite numbers with x and y within navlab's coordinate range. Any finite heading
    is a heading, as for a ``World``'s start and goal (until session 16 this refused
    headings beyond ±1e7 rad, which ``navlab.plan`` wrapped). With ``degrees_hint`` (a
    planner's start and goal), one beyond ±2π warns (``navlab.angles.HeadingWarning``: most
    often degrees); the solvers' own callers pass headings such as θ + s/r, beyond a turn by
    design, and get no warning."""
    try:
        values = list(pose)
    except TypeError:
        raise ParameterError(f"{name} must be a pose (x, y, theta), got {pose!r}") from None
    if len(values) != 3:
        raise ParameterError(f"{name} must be a pose (x, y, theta) of 3 numbers, got {len(values)}")
    x = check_coordinate(f"{name} x", values[0])
    y = check_coordinate(f"{name} y", values[1])
    return x, y, planned_heading(f"{name} theta", values[2], degrees_hint)


def check_turning_radius(value) -> float:
    """A turning radius: a finite length of at least navlab's smallest length."""
    return check_length("turning_radius", value, allow_zero=False)


@njit(cache=True)
def advance(x: float, y: float, theta: float, kind: int, s: float, radius: float) -> Tuple[float, float, float]:
    """The pose after driving ``s`` metres (negative: in reverse) along one segment.

    Closed form: a left arc of radius r turns the heading by s/r
    counter-clockwise about the centre r to the left of the robot.
    """
    if kind == STRAIGHT:
        return x + s * math.cos(theta), y + s * math.sin(theta), theta
    if kind == LEFT:
        turn = s / radius
        return (x + radius * (math.sin(theta + turn) - math.sin(theta)),
                y - radius * (math.cos(theta + turn) - math.cos(theta)), theta + turn)
    if kind == RIGHT:
        turn = s / radius
        return (x - radius * (math.sin(theta - turn) - math.sin(theta)),
                y + radius * (math.cos(theta - turn) - math.cos(theta)), theta - turn)
    return x, y, theta


@njit(cache=True)
def word_poses(kinds: np.ndarray, lengths: np.ndarray, step: float) -> int:
    """How many poses :func:`trace_word` gives along the word at ``step`` (the start, then each segment cut
    into ⌈|length| / step⌉ pieces): what a trace would hold, before tracing it."""
    count = 1
    for i in range(kinds.shape[0]):
        if kinds[i] != NOP and lengths[i] != 0.0:
            count += max(1, int(math.ceil(abs(lengths[i]) / step)))
    return count


@njit(cache=True)
def trace_word(x: float, y: float, theta: float, kinds: np.ndarray, lengths: np.ndarray, radius: float,
               step: float) -> Tuple[np.ndarray, np.ndarray]:
    """Poses every ``step`` metres of arc length along a word, segment ends included.

    Returns ``(poses (M, 3), direction (M,))`` with direction +1 forward and −1
    in reverse for the motion *arriving* at each pose (the first pose takes the
    first segment's direction), so cusps show where the sign changes.
    """
    count = word_poses(kinds, lengths, step)
    poses = np.empty((count, 3))
    direction = np.empty(count, dtype=np.int8)
    poses[0, 0], poses[0, 1], poses[0, 2] = x, y, theta
    direction[0] = 1
    first = True
    k = 1
    for i in range(kinds.shape[0]):
        s_total = lengths[i]
        if kinds[i] == NOP or s_total == 0.0:
            continue
        sign = 1 if s_total > 0 else -1
        if first:
            direction[0] = sign
            first = False
        pieces = max(1, int(math.ceil(abs(s_total) / step)))
        for j in range(1, pieces + 1):
            # each pose from the segment's start, so rounding does not accumulate within it
            px, py, pt = advance(x, y, theta, kinds[i], s_total * j / pieces, radius)
            poses[k, 0], poses[k, 1], poses[k, 2] = px, py, pt
            direction[k] = sign
            k += 1
        x, y, theta = poses[k - 1, 0], poses[k - 1, 1], poses[k - 1, 2]
    return poses, direction


@dataclass(frozen=True)
class CurvePath:
    """A shortest path of a car-like robot: a word of arcs and straight segments.

    Attributes
    ----------
    start : tuple of float
        ``(x, y, θ)`` where the path begins [m, m, rad].
    word : str
        The segments' letters, e.g. ``"LSR"`` (L left arc, S straight, R right arc).
    segments : tuple of float
        Each segment's length in metres, negative when driven in reverse.
    turning_radius : float
        The arcs' radius [m].
    """

    start: Tuple[float, float, float]
    word: str
    segments: Tuple[float, ...]
    turning_radius: float

    @classmethod
    def of_word(cls, start, kinds: np.ndarray, lengths: np.ndarray, turning_radius: float) -> "CurvePath":
        """A path from a solver's segment codes and lengths [m]; padding and
        segments of no length (below :data:`NEGLIGIBLE` of the radius: rounding
        in the closed forms) are dropped, so the word names only what is driven."""
        used = [i for i in range(len(kinds))
                if int(kinds[i]) != NOP and abs(lengths[i]) > NEGLIGIBLE * turning_radius]
        return cls(start=tuple(start), word="".join(LETTERS[int(kinds[i])] for i in used),
                   segments=tuple(float(lengths[i]) for i in used), turning_radius=turning_radius)

    @property
    def length(self) -> float:
        """Total length driven, forward and reverse [m]."""
        return float(sum(abs(s) for s in self.segments))

    @property
    def cusps(self) -> int:
        """How many times the direction of travel changes."""
        signs = [s > 0 for s in self.segments if s != 0.0]
        return sum(a != b for a, b in zip(signs, signs[1:]))

    def _codes(self) -> Tuple[np.ndarray, np.ndarray]:
        codes = {v: k for k, v in LETTERS.items()}
        return (np.array([codes[c] for c in self.word], dtype=np.int64),
                np.array(self.segments, dtype=np.float64))

    @property
    def end(self) -> Tuple[float, float, float]:
        """The pose the path arrives at (θ wrapped to (−π, π])."""
        x, y, theta = self.start
        for kind, s in zip(*self._codes()):
            x, y, theta = advance(x, y, theta, int(kind), float(s), self.turning_radius)
        return x, y, _wrap(theta)

    def sample(self, step: float) -> Tuple[np.ndarray, np.ndarray]:
        """Poses at most ``step`` metres apart along the path, both ends included.

        Returns
        -------
        poses : (M, 3) ndarray
            ``(x, y, θ)``; θ is continuous along the path (not wrapped).
        direction : (M,) ndarray of int8
            +1 where the robot arrives driving forward, −1 in reverse.
        """
        step = check_length("step", step, allow_zero=False)
        kinds, lengths = self._codes()
        return trace_word(*self.start, kinds, lengths, self.turning_radius, step)


@njit(cache=True)
def _wrap_compiled(angle: float) -> float:
    """:func:`_wrap` for compiled code (numba has no ``math.fmod``;
    ``np.fmod`` is the same C ``fmod``, so the same value bit for bit: tested)."""
    a = np.fmod(angle + math.pi, 2.0 * math.pi)
    if a <= 0.0:
        a += 2.0 * math.pi
    return a - math.pi
