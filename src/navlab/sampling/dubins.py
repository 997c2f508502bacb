"""Dubins paths: the shortest forward-only paths at a bounded curvature.

Dubins (1957) showed that the shortest path between two poses of a car that
only drives forward with turning radius r is one of six words: CSC (LSL, RSR,
LSR, RSL) or CCC (RLR, LRL), C an arc of radius r and S a straight segment.
Each word's three lengths have a closed form in the goal's coordinates seen
from the start, scaled by r (Shkel and Lumelsky, "Classification of the Dubins
set", Robotics and Autonomous Systems 34, 2001): with d the scaled distance and
α, β the start and goal headings measured from the line joining them. navlab
solves all six and keeps the shortest, so no classification table is needed.

Lengths agree with OMPL's ``DubinsStateSpace`` to 1e-9 relative on random pairs
(``tests/sampling/test_curves.py``).
"""

from __future__ import annotations

import math
from typing import Tuple

import numpy as np

from ..jit import njit
from .curves import LEFT, RIGHT, STRAIGHT, CurvePath, check_pose, check_turning_radius

TWO_PI = 2.0 * math.pi
#: an angle this close below 0 or 2π is 0: rounding, not a loop around the circle
ANGLE_SNAP = 1e-9

#: the six words, in the order the kernel numbers them
WORDS = np.array([[LEFT, STRAIGHT, LEFT], [RIGHT, STRAIGHT, RIGHT], [LEFT, STRAIGHT, RIGHT],
                  [RIGHT, STRAIGHT, LEFT], [RIGHT, LEFT, RIGHT], [LEFT, RIGHT, LEFT]], dtype=np.int64)


@njit(cache=True, inline="always")
def _mod2pi(a: float) -> float:
    """``a`` in [0, 2π), with values within ANGLE_SNAP of a full turn taken as 0."""
    m = a - TWO_PI * math.floor(a / TWO_PI)
    return 0.0 if m < ANGLE_SNAP or m > TWO_PI - ANGLE_SNAP else m


@njit(cache=True, inline="always")
def _centres_apart(d: float) -> float:
    """The squared distance between a CSC word's two same-side circle centres (LSL, RSR) at or below
    which their direction is rounding noise: the goal lies on the start's circle, and the word is one
    arc. The squared distance is a sum of terms up to (1 + d)² whose rounding leaves about 1e-15 of
    that (a goal exactly on the circle gave 8.9e-16 at d = 1.5), so below (1e-7·(1 + d))² the straight
    part runs along the start heading (the first arc 0) rather than in the noise's direction, which
    made either arc a near-full turn (2π·r added to a single arc). The path then ends within 2e-7·(1 + d)
    turning radii of the goal, its heading exact."""
    return (1e-7 * (1.0 + d)) ** 2


@njit(cache=True)
def _word(k: int, d: float, alpha: float, beta: float, sa: float, ca: float, sb: float, cb: float, cab: float,
          best: float) -> Tuple[float, float, float]:
    """Word ``k``'s (t, p, q) in turning radii (:data:`WORDS` order), or (inf, 0, 0) where it does not
    exist or cannot be shorter than ``best``: a word's t + p + q is never below its p (rounding to
    nearest is monotone and t, q >= 0), so a CSC word whose straight part alone, or a CCC word whose
    middle arc (at least π), is no shorter than ``best`` is not finished (its atan2 and acos calls,
    most of a solve, are skipped)."""
    none = (math.inf, 0.0, 0.0)
    if k < 2:  # LSL, RSR
        if k == 0:
            sq = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb)
        else:
            sq = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa)
        if sq < -_centres_apart(d):  # (rounding can take a zero below 0)
            return none
        p = math.sqrt(max(sq, 0.0))
        if not p < best:
            return none
        if k == 0:
            theta = math.atan2(cb - ca, d + sa - sb) if sq > _centres_apart(d) else alpha
            return _mod2pi(theta - alpha), p, _mod2pi(beta - theta)
        theta = math.atan2(ca - cb, d - sa + sb) if sq > _centres_apart(d) else alpha
        return _mod2pi(alpha - theta), p, _mod2pi(theta - beta)
    if k < 4:  # LSR, RSL
        if k == 2:
            sq = -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb)
        else:
            sq = -2.0 + d * d + 2.0 * cab - 2.0 * d * (sa + sb)
        if sq < 0.0 or not math.sqrt(sq) < best:
            return none
        p = math.sqrt(sq)
        if k == 2:
            theta = math.atan2(-ca - cb, d + sa + sb) - math.atan2(-2.0, p)
            return _mod2pi(theta - alpha), p, _mod2pi(theta - beta)
        theta = math.atan2(ca + cb, d - sa - sb) - math.atan2(2.0, p)
        return _mod2pi(alpha - theta), p, _mod2pi(beta - theta)
    if not best > math.pi:  # a CCC word's middle arc is 2π - acos(c) >= π
        return none
    if k == 4:  # RLR
        c = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sa - sb)) / 8.0
        if abs(c) > 1.0:
            return none
        p = TWO_PI - math.acos(c)
        t = _mod2pi(alpha - math.atan2(ca - cb, d - sa + sb) + 0.5 * p)
        return t, p, _mod2pi(alpha - beta - t + p)
    c = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sb - sa)) / 8.0  # LRL
    if abs(c) > 1.0:
        return none
    p = TWO_PI - math.acos(c)
    t = _mod2pi(-alpha + math.atan2(cb - ca, d + sa - sb) + 0.5 * p)
    return t, p, _mod2pi(beta - alpha - t + p)


@njit(cache=True)
def solve(d: float, alpha: float, beta: float) -> Tuple[int, float, float, float]:
    """The shortest of the six words for scaled distance ``d`` and headings
    ``alpha``, ``beta`` (radians, from the start-to-goal line).

    Returns ``(word, t, p, q)``: the index into :data:`WORDS` and the three
    segment lengths in units of the turning radius (the first of equally short words).
    """
    sa, ca, sb, cb = math.sin(alpha), math.cos(alpha), math.sin(beta), math.cos(beta)
    cab = math.cos(alpha - beta)
    best, bt, bp, bq = -1, 0.0, 0.0, 0.0
    best_len = math.inf
    for word in range(6):
        t, p, q = _word(word, d, alpha, beta, sa, ca, sb, cb, cab, best_len)
        if t + p + q < best_len:
            best, bt, bp, bq, best_len = word, t, p, q, t + p + q
    return best, bt, bp, bq


@njit(cache=True)
def length(d: float, alpha: float, beta: float) -> float:
    """The shortest word's length (scaled by the turning radius) for ``d``, ``alpha``, ``beta``:
    :func:`solve`'s ``t + p + q`` bit for bit, without choosing the word (Hybrid A*'s heuristic and
    the SE(2) trees' nearest neighbours want only the length)."""
    sa, ca, sb, cb = math.sin(alpha), math.cos(alpha), math.sin(beta), math.cos(beta)
    cab = math.cos(alpha - beta)
    best = math.inf
    for word in range(6):
        t, p, q = _word(word, d, alpha, beta, sa, ca, sb, cb, cab, best)
        best = min(best, t + p + q)
    return best


@njit(cache=True)
def _normalised(x0: float, y0: float, th0: float, x1: float, y1: float, th1: float,
                radius: float) -> Tuple[float, float, float]:
    dx, dy = x1 - x0, y1 - y0
    d = math.sqrt(dx * dx + dy * dy) / radius
    theta = math.atan2(dy, dx) if d > 0.0 else 0.0
    return d, _mod2pi(th0 - theta), _mod2pi(th1 - theta)


@njit(cache=True)
def distances(starts: np.ndarray, goals: np.ndarray, radius: float) -> np.ndarray:
    """Dubins path lengths [m] from each ``starts[i]`` to ``goals[i]`` ((N, 3) poses)."""
    n = starts.shape[0]
    out = np.empty(n)
    for i in range(n):
        d, a, b = _normalised(starts[i, 0], starts[i, 1], starts[i, 2], goals[i, 0], goals[i, 1], goals[i, 2],
                              radius)
        _, t, p, q = solve(d, a, b)
        out[i] = (t + p + q) * radius
    return out


def shortest(start, goal, turning_radius: float) -> CurvePath:
    """The shortest forward-only path from pose ``start`` to pose ``goal``.

    Parameters
    ----------
    start, goal : sequence of 3 floats
        ``(x, y, θ)`` [m, m, rad].
    turning_radius : float
        The smallest radius the robot can turn on [m], > 0.

    Returns
    -------
    CurvePath
        Its word (e.g. ``"LSR"``), segment lengths [m] and :meth:`~CurvePath.sample`.
    """
    s = check_pose("start", start)
    g = check_pose("goal", goal)
    r = check_turning_radius(turning_radius)
    word, t, p, q = solve(*_normalised(*s, *g, r))
    return CurvePath.of_word(s, WORDS[word], np.array((t, p, q)) * r, r)


def distance(start, goal, turning_radius: float) -> float:
    """The length [m] of :func:`shortest`."""
    return shortest(start, goal, turning_radius).length
