"""The Reeds–Shepp length alone, exactly as :mod:`navlab.sampling.reeds_shepp` computes it, faster.

Nearest-neighbour searches in SE(2) and the Hybrid A* heuristic need only the
length of the shortest Reeds–Shepp word (Reeds and Shepp, Pacific J. Math.
145(2), 1990), not its segments. :func:`length` evaluates the same closed
forms (the paper's 8.1–8.11, with the corrections OMPL's
``ReedsSheppStateSpace`` uses) under the same symmetries, with the same
floating-point operations in the same order, so every word's length is the
same double; it returns their minimum, which does not depend on the order
the words are tried in. It saves time in four ways:

- the CSC words (8.1, 8.2, the usual optimum away from the start) go first,
  so the best length found is small early;
- a word is not solved when a cheap lower bound on its length (from a
  squared norm instead of ``hypot``, and from the heading its arcs must
  turn) is no shorter than the best found; these bounds are lowered by a
  margin far above their rounding;
- a word is dropped as soon as a part of its length is no shorter than the
  best found: a length is a sum of non-negative terms added left to right,
  and rounding to nearest is monotone, so the sum of any of its terms (in
  the same order) is never above it; the part is usually one straight
  segment or one arc, known before the word's atan2 calls;
- no segment arrays are written, and an angle already in (−2π, 2π) is not
  passed through ``fmod`` (which would return it unchanged).

The result equals :func:`navlab.sampling.reeds_shepp.distances` bit for bit
(``tests/sampling/test_rs_length.py``).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit
from .curves import MAX_SEGMENTS, NOP
from .reeds_shepp import (_BACKWARDS, _KINDS, HALF_PI, PI, ZERO, _family, _local, _mod_pi, _shortest_into,
                          _tau_omega, _word_length, _write_word)

#: a lower bound is lowered by this relative and absolute margin before it may drop a word: it is
#: computed from cheap stand-ins (a squared norm instead of ``hypot``, no ``atan2``) whose rounding
#: must never lift it above the length as computed
_SAFE = 1e-9
#: a squared norm ``xi*xi + eta*eta`` is within this relative distance of ``hypot(xi, eta)**2``
_NORM = 1e-12
FRAMES = 8  # 4 symmetries (identity, timeflip, reflect, both) x (forwards, backwards)


@njit(cache=True)
def _frame(f, x, y, phi, sp, cp, xb, yb):
    """Frame ``f``'s pose (x, y, φ, sin φ) as reeds_shepp._shortest_into hands it to a family: timeflip
    negates x, reflect y, either (not both) φ; frames 4–7 are the goal's view of the start."""
    flip, reflect = f % 4 == 1 or f % 4 == 3, f % 4 >= 2
    negate = flip != reflect
    bx, by = (xb, yb) if f >= 4 else (x, y)
    return -bx if flip else bx, -by if reflect else by, -phi if negate else phi, -sp if negate else sp


@njit(cache=True)
def _mod_2pi(a):
    """A lower bound on the sum s >= 0 of two arcs in [0, π] that turn by ``a`` (mod 2π): ``a`` in
    [0, 2π), taken as 0 near 2π, where rounding may have wrapped a sum of almost 0."""
    m = a - 2.0 * PI * math.floor(a / (2.0 * PI))
    return m if m < 2.0 * PI - 1e-6 else 0.0


@njit(cache=True)
def _below(bound):
    """``bound`` lowered by the margin, so that rounding cannot lift it above the length as computed."""
    return bound * (1.0 - _SAFE) - _SAFE


@njit(cache=True)
def _word(k, x, y, phi, sp, cp, turn, best):
    """The shorter of ``best`` and family ``k``'s length at (x, y, φ): reeds_shepp._family's
    operations, without its segment array, stopping once a part of the sum (or a bound from the
    heading it must turn, ``turn`` = |φ| wrapped to [−π, π]) reaches ``best``."""
    if k == 0:  # 8.1: the straight segment is part of the sum
        xi, eta = x - sp, y - 1.0 + cp
        u = math.hypot(xi, eta)
        if u < best:
            t = math.atan2(eta, xi)
            if t >= -ZERO:
                v = _mod_pi(phi - t)
                if v >= -ZERO:
                    best = min(best, abs(t) + u + abs(v))
    elif k == 1:  # 8.2
        xi, eta = x + sp, y - 1.0 - cp
        rho2 = xi * xi + eta * eta
        if rho2 >= 4.0:
            u = math.sqrt(rho2 - 4.0)
            if u < best:
                t = _mod_pi(math.atan2(eta, xi) + math.atan2(2.0, u))
                if t >= -ZERO:
                    v = _mod_pi(t - phi)
                    if v >= -ZERO:
                        best = min(best, abs(t) + u + abs(v))
    elif k == 2:  # 8.3: the middle arc
        xi, eta = x - sp, y - 1.0 + cp
        rho = math.hypot(xi, eta)
        if rho <= 4.0:
            u = -2.0 * math.asin(0.25 * rho)
            # t >= 0 and t + |u| + v = φ (mod 2π): |t| + |v| >= |φ − |u|| (wrapped)
            if _below(-u + abs(_mod_pi(phi + u))) < best:
                t = _mod_pi(math.atan2(eta, xi) + 0.5 * u + PI)
                if t >= -ZERO and u <= ZERO:
                    v = _mod_pi(phi - t + u)
                    best = min(best, abs(t) + abs(u) + abs(v))
    elif k == 3 or k == 4:  # 8.7, 8.8: the two middle arcs
        xi, eta = x + sp, y - 1.0 - cp
        if k == 3:
            rho = 0.25 * (2.0 + math.hypot(xi, eta))
            ok = rho <= 1.0
            u = math.acos(rho) if ok else 0.0
            w = -u
        else:
            rho = (20.0 - xi * xi - eta * eta) / 16.0
            ok = 0.0 <= rho <= 1.0
            u = -math.acos(rho) if ok else 0.0
            ok = ok and u >= -HALF_PI
            w = u
        # 8.7: t >= 0 >= v and t − v = φ + 2u (mod 2π), in [0, 2π]; 8.8: t, v >= 0 and t − v = φ (mod 2π)
        if ok and _below(abs(u) + abs(w) + (_mod_2pi(phi + 2.0 * u) if k == 3 else turn)) < best:
            t, v = _tau_omega(u, w, xi, eta, phi)
            if t >= -ZERO and (v <= ZERO if k == 3 else v >= -ZERO):
                best = min(best, abs(t) + abs(u) + abs(w) + abs(v))
    elif k == 5:  # 8.9: the fixed π/2 arc and the straight segment
        xi, eta = x - sp, y - 1.0 + cp
        rho = math.hypot(xi, eta)
        if rho >= 2.0:
            r = math.sqrt(rho * rho - 4.0)
            u = 2.0 - r
            if u <= ZERO and HALF_PI + abs(u) < best:
                t = _mod_pi(math.atan2(eta, xi) + math.atan2(r, -2.0))
                if t >= -ZERO:
                    v = _mod_pi(phi - HALF_PI - t)
                    if v <= ZERO:
                        best = min(best, abs(t) + HALF_PI + abs(u) + abs(v))
    elif k == 6:  # 8.10
        xi, eta = x + sp, y - 1.0 - cp
        rho = math.hypot(-eta, xi)
        if rho >= 2.0:
            u = 2.0 - rho
            if u <= ZERO and HALF_PI + abs(u) < best:
                t = math.atan2(xi, -eta)
                if t >= -ZERO:
                    v = _mod_pi(t + HALF_PI - phi)
                    if v <= ZERO:
                        best = min(best, abs(t) + HALF_PI + abs(u) + abs(v))
    else:  # 8.11: two π/2 arcs and the straight segment
        xi, eta = x + sp, y - 1.0 - cp
        rho = math.hypot(xi, eta)
        if rho >= 2.0:
            u = 4.0 - math.sqrt(rho * rho - 4.0)
            if u <= ZERO and HALF_PI + abs(u) + HALF_PI < best:
                t = _mod_pi(math.atan2((4.0 - u) * xi - 2.0 * eta, -2.0 * xi + (u - 4.0) * eta))
                v = _mod_pi(t - phi)
                if t >= -ZERO and v >= -ZERO:
                    best = min(best, abs(t) + HALF_PI + abs(u) + HALF_PI + abs(v))
    return best


@njit(cache=True)
def _prebound(k, x, y, phi, sp, cp, turn):
    """A lower bound on family ``k``'s length at (x, y, φ) from cheap stand-ins (a squared norm for
    ``hypot``, no atan2), lowered by the margin; inf where as cheap a test shows it has no solution.
    ``lo2``/``hi2`` bracket the squared ``hypot`` the closed forms compute."""
    if k == 0 or k == 2 or k == 5:
        xi, eta = x - sp, y - 1.0 + cp
    else:
        xi, eta = x + sp, y - 1.0 - cp
    rho2 = xi * xi + eta * eta
    lo2, hi2 = rho2 * (1.0 - _NORM), rho2 * (1.0 + _NORM)
    if k == 0:
        # 8.1: t = atan2(eta, xi) >= 0 fails below the x axis; t, v in [0, π] turn by φ (mod 2π)
        if eta >= 0.0 or (xi > 0.0 and -eta <= 1e-12 * xi):
            return _below(math.sqrt(lo2) + _mod_2pi(phi))
    elif k == 1:
        # 8.2: its straight segment is computed from rho2 exactly so; t, v in [0, π] and t − v = φ (mod 2π)
        if rho2 >= 4.0:
            return _below(math.sqrt(rho2 - 4.0) + turn)
    elif k == 2:
        # 8.3 needs ρ <= 4; |u| = 2 asin(ρ/4) >= ρ/2 =: a; t >= 0 and t + |u| + v = φ (mod 2π), so the
        # length is at least |u| + |φ − |u|| (wrapped), which never decreases as |u| grows: at least its value at a
        if lo2 <= 16.0:
            a = 0.5 * math.sqrt(lo2)
            return _below(a + abs(_mod_pi(phi - a)))
    elif k == 5:
        # 8.9 needs u = 2 − sqrt(ρ² − 4) <= 0; t >= 0 >= v and t + v = φ − π/2 (mod 2π)
        if hi2 >= 7.9:
            return _below(HALF_PI + max(math.sqrt(max(lo2 - 4.0, 0.0)) - 2.0, 0.0) + abs(_mod_pi(phi - HALF_PI)))
    elif k == 6:
        # 8.10 needs u = 2 − ρ <= 0; t >= 0 >= v and t − v = φ − π/2 (mod 2π), in [0, 2π]
        if hi2 >= 3.9:
            return _below(HALF_PI + max(math.sqrt(lo2) - 2.0, 0.0) + _mod_2pi(phi - HALF_PI))
    elif k == 3:
        # CCCC: u = acos(z) >= sqrt(2 (1 − z)) (as cos θ >= 1 − θ²/2), two arcs of |u|, and the word turns
        # by φ. 8.7 needs ρ <= 2; z = (2 + ρ)/4
        if lo2 <= 4.0:
            return _below(max(2.0 * math.sqrt(max(0.5 * (2.0 - math.sqrt(hi2)), 0.0)), turn))
    elif k == 4:
        # 8.8 needs 0 <= z = (20 − ρ²)/16 <= 1; t, v >= 0 and t − v = φ (mod 2π)
        if hi2 >= 4.0 and lo2 <= 20.0:
            return _below(2.0 * math.sqrt(max(lo2 - 4.0, 0.0) / 8.0) + turn)
    else:
        # 8.11 needs u = 4 − sqrt(ρ² − 4) <= 0; t, v >= 0 and t − v = φ (mod 2π)
        if hi2 >= 19.9:
            return _below(PI + max(math.sqrt(max(lo2 - 4.0, 0.0)) - 4.0, 0.0) + turn)
    return math.inf


@njit(cache=True)
def _try(k, x, y, phi, sp, cp, turn, best):
    """The shorter of ``best`` and family ``k``'s length, solved only where :func:`_prebound` allows."""
    if _prebound(k, x, y, phi, sp, cp, turn) < best:
        best = _word(k, x, y, phi, sp, cp, turn, best)
    return best


@njit(cache=True)
def _csc(x, y, phi, sp, cp, turn, best):
    """8.1 and 8.2 at (x, y, φ); returns the shorter of ``best`` and their lengths."""
    for k in (0, 1):
        best = _try(k, x, y, phi, sp, cp, turn, best)
    return best


@njit(cache=True)
def _others(x, y, phi, sp, cp, turn, backwards, best):
    """The other families at (x, y, φ) (only 8.3, 8.9, 8.10 when ``backwards``); returns the shorter of
    ``best`` and their lengths."""
    for k in (2, 5, 6):
        best = _try(k, x, y, phi, sp, cp, turn, best)
    if backwards:
        return best
    for k in (3, 4, 7):
        best = _try(k, x, y, phi, sp, cp, turn, best)
    return best


@njit(cache=True)
def length_below(x: float, y: float, phi: float, cutoff: float) -> float:
    """The length of the shortest Reeds–Shepp word to the pose (x, y, φ), seen from the start and
    scaled by r, if it is below ``cutoff``, else inf: :func:`navlab.sampling.reeds_shepp.solve`'s
    length, bit for bit. A nearest-neighbour search passes its best distance so far: most candidates
    are then dropped by the cheap bounds alone.

    Branch and bound over the 44 word evaluations: the CSC words of the four symmetries first, then
    the others, each skipped when a cheap lower bound on its length is no shorter than the best found.

    References
    ----------
    Reeds, J. A. and Shepp, L. A., "Optimal paths for a car that goes both forwards and backwards",
    Pacific J. Math. 145(2), 1990, formulas 8.1–8.11.
    """
    cp, sp = math.cos(phi), math.sin(phi)
    xb, yb = x * cp + y * sp, x * sp - y * cp  # the goal's view of the start, for words read backwards
    turn = abs(_mod_pi(phi))  # every word turns the car by φ (mod 2π), by its arcs, at most 1 rad per r
    best = cutoff
    for f in range(4):
        fx, fy, fphi, fsp = _frame(f, x, y, phi, sp, cp, xb, yb)
        best = _csc(fx, fy, fphi, fsp, cp, turn, best)
    for f in range(FRAMES):
        fx, fy, fphi, fsp = _frame(f, x, y, phi, sp, cp, xb, yb)
        best = _others(fx, fy, fphi, fsp, cp, turn, f >= 4, best)
    return best if best < cutoff else math.inf


@njit(cache=True)
def word_below(x: float, y: float, phi: float, cutoff: float, seg: np.ndarray, kinds: np.ndarray,
               lengths: np.ndarray) -> float:
    """:func:`navlab.sampling.reeds_shepp._shortest_into` (the shortest word into ``kinds``, ``lengths``;
    its length) when that length is below ``cutoff``, else inf with the arrays untouched. The same word,
    bit for bit, also among ties: the words are tried in the full solver's order and a word replaces the
    best only when strictly shorter, but one that cannot beat the best found (at first the cutoff) is
    dropped by cheap bounds (:func:`_try`) before its segments are solved. A steering step
    that knows the length (from :func:`length_below`) passes it, widened, as the cutoff."""
    cp, sp = math.cos(phi), math.sin(phi)
    xb, yb = x * cp + y * sp, x * sp - y * cp  # as _shortest_into computes them
    turn = abs(_mod_pi(phi))
    best, found = cutoff, False
    for k in range(_KINDS.shape[0]):
        n = 0
        while n < MAX_SEGMENTS and _KINDS[k, n] != NOP:
            n += 1
        for backwards in range(2 if _BACKWARDS[k] else 1):
            for sym in range(4):
                fx, fy, fphi, fsp = _frame(sym + 4 * backwards, x, y, phi, sp, cp, xb, yb)
                if _try(k, fx, fy, fphi, fsp, cp, turn, best) >= best:
                    continue
                seg[:] = 0.0
                if not _family(k, fx, fy, fphi, fsp, cp, seg):
                    continue
                length = _word_length(seg, n)
                if length >= best:
                    continue
                best, found = length, True
                _write_word(k, n, backwards, sym == 1 or sym == 3, sym >= 2, seg, kinds, lengths)
    return best if found else math.inf


@njit(cache=True)
def word(x: float, y: float, phi: float, known: float, seg: np.ndarray, kinds: np.ndarray,
         lengths: np.ndarray) -> float:
    """:func:`navlab.sampling.reeds_shepp._shortest_into`, bit for bit, given ``known`` >= its length
    (e.g. :func:`length_below`'s, or inf): :func:`word_below` with ``known`` widened by 1e-9, and the
    full solver should rounding ever have put the length above that."""
    total = word_below(x, y, phi, known * (1.0 + 1e-9) + 1e-12, seg, kinds, lengths)
    if total == math.inf:
        total = _shortest_into(x, y, phi, seg, kinds, lengths)
    return total


@njit(cache=True)
def length(x: float, y: float, phi: float) -> float:
    """The length of the shortest Reeds–Shepp word to the pose (x, y, φ), seen from the start and
    scaled by r: :func:`navlab.sampling.reeds_shepp.solve`'s length, bit for bit
    (:func:`length_below` with no cutoff)."""
    return length_below(x, y, phi, math.inf)


@njit(cache=True)
def lengths(starts: np.ndarray, goals: np.ndarray, radius: float) -> np.ndarray:
    """Reeds–Shepp path lengths [m] from each ``starts[i]`` to ``goals[i]`` ((N, 3) poses):
    :func:`navlab.sampling.reeds_shepp.distances`, bit for bit."""
    n = starts.shape[0]
    out = np.empty(n)
    for i in range(n):
        x, y, phi = _local(starts[i, 0], starts[i, 1], starts[i, 2], goals[i, 0], goals[i, 1], goals[i, 2], radius)
        out[i] = length(x, y, phi) * radius
    return out


#: the tolerance under which :func:`same_side_above` treats an angle test as undecided
_UNDECIDED = 1e-9


@njit(cache=True)
def same_side_above(x: float, y: float, phi: float, backwards: bool) -> float:
    """An upper bound on the shortest path's length to the pose (x, y, φ), seen from the start and
    scaled by r: the shortest of the words L+S+L+ and R+S+R+ (a Dubins upper bound), and with
    ``backwards`` also L−S−L− and R−S−R− (a Reeds–Shepp one), each with arcs of any length —
    without an ``atan2``. Hybrid A*'s search needs its heuristic only against the next queue key,
    and this bound, at about a tenth of a Dubins solve, usually settles that comparison.

    For L+S+L+ the straight segment joins the two left-turn circles' centres, (0, 1) and
    (x − sin φ, y + cos φ), so its length is the distance p between them, and the two arcs turn t
    (the segment's direction, in [0, 2π)) and q = (φ − t) mod 2π, whose sum is m = φ mod 2π
    when t ≤ m and m + 2π when t > m. Which one is decided from the signs of the vectors' y
    components (their half-planes) and of their cross product; when either is within
    :data:`_UNDECIDED` of zero, m + 2π (never less than t + q) is taken. The other words are
    the same under Reeds and Shepp's symmetries (timeflip (−x, y, −φ), reflect (x, −y, −φ)).
    The value is computed in floating point: callers lift it by a margin far above its rounding
    before they rely on it being no shorter than a solver's length (Reeds–Shepp paper: Pacific J.
    Math. 145(2), 1990; Dubins: Amer. J. Math. 79(3), 1957)."""
    sp, cp = math.sin(phi), math.cos(phi)
    best = math.inf
    for f in range(4 if backwards else 2):
        flip, reflect = f % 2 == 1 if backwards else False, f >= 2 if backwards else f == 1
        fx = -x if flip else x
        fy = -y if reflect else y
        negate = flip != reflect
        s = -sp if negate else sp
        ph = -phi if negate else phi
        xi, eta = fx - s, fy - 1.0 + cp
        p = math.sqrt(xi * xi + eta * eta)
        m = ph - 2.0 * PI * math.floor(ph / (2.0 * PI))
        turn = m + 2.0 * PI
        cross = xi * s - eta * cp  # > 0: the goal heading lies counter-clockwise of the segment, by less than π
        if abs(eta) > _UNDECIDED * p and abs(s) > _UNDECIDED and abs(cross) > _UNDECIDED * p:
            upper_u, upper_w = eta > 0.0, s > 0.0  # direction in (0, π), not (π, 2π)
            if (upper_u == upper_w and cross > 0.0) or (upper_u and not upper_w):
                turn = m  # t < m
        best = min(best, p + turn)
    return best
