"""Reeds–Shepp paths: the shortest paths of a car that drives forward and in reverse.

Reeds and Shepp ("Optimal paths for a car that goes both forwards and
backwards", Pacific J. Math. 145(2), 1990) proved that the shortest path
between two poses at turning radius r is one of 48 words of at most five arcs
and straight segments, with at most two cusps. The paper gives closed forms
for nine base families (its formulas 8.1–8.11, in the goal's coordinates seen
from the start, scaled by r); every other word follows from three symmetries:

- *timeflip* (x, y, φ) → (−x, y, −φ): the same word driven in the other direction;
- *reflect* (x, y, φ) → (x, −y, −φ): left and right swapped;
- *backwards*: the word read from the goal to the start (for the CCC and
  CCSC families, whose reversal is not among the base forms).

navlab evaluates every base formula under every symmetry and keeps the
shortest. Two formulas have known misprints in the paper (8.3/8.4 and 8.11);
the corrected forms used here are the ones OMPL's ``ReedsSheppStateSpace``
also uses, and its lengths agree with OMPL's to 1e-9 relative on random pairs
(``tests/sampling/test_curves.py``).
"""

from __future__ import annotations

import math
from typing import Tuple

import numpy as np

from ..jit import njit
from .curves import LEFT, MAX_SEGMENTS, NOP, RIGHT, STRAIGHT, CurvePath, check_pose, check_turning_radius

PI = math.pi
HALF_PI = 0.5 * math.pi
#: a segment this far below 0 still counts as non-negative (rounding in the closed forms)
ZERO = 10.0 * np.finfo(np.float64).eps

#: the base families: their segment letters (padded with NOP) ...
_KINDS = np.array([
    [LEFT, STRAIGHT, LEFT, NOP, NOP],        # 8.1  L+ S+ L+
    [LEFT, STRAIGHT, RIGHT, NOP, NOP],       # 8.2  L+ S+ R+
    [LEFT, RIGHT, LEFT, NOP, NOP],           # 8.3  L+ R- L
    [LEFT, RIGHT, LEFT, RIGHT, NOP],         # 8.7  L+ R+u L-u R-
    [LEFT, RIGHT, LEFT, RIGHT, NOP],         # 8.8  L+ R-u L-u R+
    [LEFT, RIGHT, STRAIGHT, LEFT, NOP],      # 8.9  L+ R-π/2 S- L-
    [LEFT, RIGHT, STRAIGHT, RIGHT, NOP],     # 8.10 L+ R-π/2 S- R-
    [LEFT, RIGHT, STRAIGHT, LEFT, RIGHT],    # 8.11 L+ R-π/2 S- L-π/2 R+
], dtype=np.int64)
#: ... and which of them are also read backwards (CCC and CCSC)
_BACKWARDS = np.array([False, False, True, False, False, True, True, False])


@njit(cache=True, inline="always")
def _mod_pi(a: float) -> float:
    """``a`` in [−π, π]."""
    # fmod returns an ``a`` inside (−2π, 2π) unchanged, and most angles here are: skip the call
    v = a if -2.0 * PI < a < 2.0 * PI else np.fmod(a, 2.0 * PI)
    if v < -PI:
        v += 2.0 * PI
    elif v > PI:
        v -= 2.0 * PI
    return v


@njit(cache=True, inline="always")
def _tau_omega(u: float, v: float, xi: float, eta: float, phi: float) -> Tuple[float, float]:
    """The first and last arcs of the CCCC families (the paper's τ and ω)."""
    delta = _mod_pi(u - v)
    a = math.sin(u) - math.sin(delta)
    b = math.cos(u) - math.cos(delta) - 1.0
    t1 = math.atan2(eta * a - xi * b, xi * a + eta * b)
    t2 = 2.0 * (math.cos(delta) - math.cos(v) - math.cos(u)) + 3.0
    tau = _mod_pi(t1 + PI) if t2 < 0.0 else _mod_pi(t1)
    return tau, _mod_pi(tau - u + v - phi)


@njit(cache=True)
def _family(k: int, x: float, y: float, phi: float, sp: float, cp: float, out: np.ndarray) -> bool:
    """Segment lengths of base family ``k`` at (x, y, φ) into ``out``; False if it has no solution there.
    ``sp``, ``cp`` are sin φ and cos φ (the caller's, computed once for all 44 evaluations)."""
    if k == 0:  # 8.1
        u = math.hypot(x - sp, y - 1.0 + cp)
        t = math.atan2(y - 1.0 + cp, x - sp)
        v = _mod_pi(phi - t)
        out[0], out[1], out[2] = t, u, v
        return t >= -ZERO and v >= -ZERO
    if k == 1:  # 8.2
        xi, eta = x + sp, y - 1.0 - cp
        rho2 = xi * xi + eta * eta
        if rho2 < 4.0:
            return False
        u = math.sqrt(rho2 - 4.0)
        t = _mod_pi(math.atan2(eta, xi) + math.atan2(2.0, u))
        v = _mod_pi(t - phi)
        out[0], out[1], out[2] = t, u, v
        return t >= -ZERO and v >= -ZERO
    if k == 2:  # 8.3/8.4, corrected
        xi, eta = x - sp, y - 1.0 + cp
        rho = math.hypot(xi, eta)
        if rho > 4.0:
            return False
        u = -2.0 * math.asin(0.25 * rho)
        t = _mod_pi(math.atan2(eta, xi) + 0.5 * u + PI)
        v = _mod_pi(phi - t + u)
        out[0], out[1], out[2] = t, u, v
        return t >= -ZERO and u <= ZERO
    if k == 3:  # 8.7
        xi, eta = x + sp, y - 1.0 - cp
        rho = 0.25 * (2.0 + math.hypot(xi, eta))
        if rho > 1.0:
            return False
        u = math.acos(rho)
        t, v = _tau_omega(u, -u, xi, eta, phi)
        out[0], out[1], out[2], out[3] = t, u, -u, v
        return t >= -ZERO and v <= ZERO
    if k == 4:  # 8.8
        xi, eta = x + sp, y - 1.0 - cp
        rho = (20.0 - xi * xi - eta * eta) / 16.0
        if rho < 0.0 or rho > 1.0:
            return False
        u = -math.acos(rho)
        if u < -HALF_PI:
            return False
        t, v = _tau_omega(u, u, xi, eta, phi)
        out[0], out[1], out[2], out[3] = t, u, u, v
        return t >= -ZERO and v >= -ZERO
    if k == 5:  # 8.9
        xi, eta = x - sp, y - 1.0 + cp
        rho = math.hypot(xi, eta)
        if rho < 2.0:
            return False
        r = math.sqrt(rho * rho - 4.0)
        u = 2.0 - r
        t = _mod_pi(math.atan2(eta, xi) + math.atan2(r, -2.0))
        v = _mod_pi(phi - HALF_PI - t)
        out[0], out[1], out[2], out[3] = t, -HALF_PI, u, v
        return t >= -ZERO and u <= ZERO and v <= ZERO
    if k == 6:  # 8.10
        xi, eta = x + sp, y - 1.0 - cp
        rho = math.hypot(-eta, xi)
        if rho < 2.0:
            return False
        t = math.atan2(xi, -eta)
        u = 2.0 - rho
        v = _mod_pi(t + HALF_PI - phi)
        out[0], out[1], out[2], out[3] = t, -HALF_PI, u, v
        return t >= -ZERO and u <= ZERO and v <= ZERO
    # 8.11, corrected
    xi, eta = x + sp, y - 1.0 - cp
    rho = math.hypot(xi, eta)
    if rho < 2.0:
        return False
    u = 4.0 - math.sqrt(rho * rho - 4.0)
    if u > ZERO:
        return False
    t = _mod_pi(math.atan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta))
    v = _mod_pi(t - phi)
    out[0], out[1], out[2], out[3], out[4] = t, -HALF_PI, u, -HALF_PI, v
    return t >= -ZERO and v >= -ZERO


@njit(cache=True)
def solve(x: float, y: float, phi: float) -> Tuple[np.ndarray, np.ndarray]:
    """The shortest word to the pose (x, y, φ), seen from the start and scaled by r.

    Returns ``(kinds (5,), lengths (5,))``: segment codes (NOP-padded) and
    signed lengths in units of the turning radius.
    """
    best_kinds = np.zeros(MAX_SEGMENTS, dtype=np.int64)
    best_lengths = np.zeros(MAX_SEGMENTS)
    _shortest_into(x, y, phi, np.zeros(MAX_SEGMENTS), best_kinds, best_lengths)
    return best_kinds, best_lengths


@njit(cache=True)
def _shortest_into(x: float, y: float, phi: float, seg: np.ndarray, best_kinds: np.ndarray,
                   best_lengths: np.ndarray) -> float:
    """:func:`solve` writing into caller-owned arrays (no allocation per pair); returns the length."""
    best = math.inf
    cp, sp = math.cos(phi), math.sin(phi)
    xb, yb = x * cp + y * sp, x * sp - y * cp  # the goal's view of the start, for words read backwards
    for k in range(_KINDS.shape[0]):
        n = 0
        while n < MAX_SEGMENTS and _KINDS[k, n] != NOP:
            n += 1
        for backwards in range(2 if _BACKWARDS[k] else 1):
            bx, by = (xb, yb) if backwards else (x, y)
            for sym in range(4):  # identity, timeflip, reflect, both
                flip, reflect = sym == 1 or sym == 3, sym >= 2
                seg[:] = 0.0
                # sin is odd and cos even, exactly in floating point: the symmetries need no new trigonometry
                negate = flip != reflect
                if not _family(k, -bx if flip else bx, -by if reflect else by, -phi if negate else phi,
                               -sp if negate else sp, cp, seg):
                    continue
                length = _word_length(seg, n)
                if length >= best:
                    continue
                best = length
                _write_word(k, n, backwards, flip, reflect, seg, best_kinds, best_lengths)
    return best


@njit(cache=True, inline="always")
def _word_length(seg: np.ndarray, n: int) -> float:
    """The length of a family's first ``n`` segments, summed left to right (the order fixes the rounding)."""
    length = 0.0
    for i in range(n):
        length += abs(seg[i])
    return length


@njit(cache=True, inline="always")
def _write_word(k: int, n: int, backwards: int, flip: bool, reflect: bool, seg: np.ndarray, kinds: np.ndarray,
                lengths: np.ndarray) -> None:
    """Family ``k``'s ``n`` segments ``seg`` as a word of the original pose: read backwards, timeflipped
    (reversed lengths), reflected (left and right swapped) as the frame it was solved in says."""
    kinds[:] = NOP
    lengths[:] = 0.0
    for i in range(n):
        j = n - 1 - i if backwards else i
        kind = _KINDS[k, i]
        if reflect and kind != STRAIGHT:
            kind = RIGHT if kind == LEFT else LEFT
        kinds[j] = kind
        lengths[j] = -seg[i] if flip else seg[i]


@njit(cache=True)
def _local(x0: float, y0: float, th0: float, x1: float, y1: float, th1: float,
           radius: float) -> Tuple[float, float, float]:
    dx, dy = x1 - x0, y1 - y0
    c, s = math.cos(th0), math.sin(th0)
    return (c * dx + s * dy) / radius, (-s * dx + c * dy) / radius, th1 - th0


@njit(cache=True)
def distances(starts: np.ndarray, goals: np.ndarray, radius: float) -> np.ndarray:
    """Reeds–Shepp path lengths [m] from each ``starts[i]`` to ``goals[i]`` ((N, 3) poses)."""
    n = starts.shape[0]
    out = np.empty(n)
    seg, kinds, lengths = np.zeros(MAX_SEGMENTS), np.zeros(MAX_SEGMENTS, dtype=np.int64), np.zeros(MAX_SEGMENTS)
    for i in range(n):
        x, y, phi = _local(starts[i, 0], starts[i, 1], starts[i, 2], goals[i, 0], goals[i, 1], goals[i, 2], radius)
        out[i] = _shortest_into(x, y, phi, seg, kinds, lengths) * radius
    return out


def shortest(start, goal, turning_radius: float) -> CurvePath:
    """The shortest forward-and-reverse path from pose ``start`` to pose ``goal``.

    Parameters
    ----------
    start, goal : sequence of 3 floats
        ``(x, y, θ)`` [m, m, rad].
    turning_radius : float
        The smallest radius the robot can turn on [m], > 0.

    Returns
    -------
    CurvePath
        Its word (e.g. ``"LRSL"``), signed segment lengths [m] (negative in
        reverse: :attr:`~CurvePath.cusps` counts the changes) and
        :meth:`~CurvePath.sample`.
    """
    s = check_pose("start", start)
    g = check_pose("goal", goal)
    r = check_turning_radius(turning_radius)
    kinds, lengths = solve(*_local(*s, *g, r))
    return CurvePath.of_word(s, kinds, lengths * r, r)


def distance(start, goal, turning_radius: float) -> float:
    """The length [m] of :func:`shortest`."""
    return shortest(start, goal, turning_radius).length
