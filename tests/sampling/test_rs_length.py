"""The length-only Reeds–Shepp solver against the full one (which evaluates every one of the 44 word
evaluations and keeps the shortest: the brute force), against OMPL, and on hand-derived lengths."""

import math

import numpy as np
import pytest

from navlab.sampling import reeds_shepp, reeds_shepp_length


def hard_pairs(n, seed, span):
    """Random pose pairs, with the cases where words tie or degenerate over-represented: headings
    that differ by a multiple of π/2, equal positions, equal poses."""
    rng = np.random.default_rng(seed)
    a = np.column_stack([rng.uniform(-span, span, (n, 2)), rng.uniform(-4.0, 4.0, n)])
    b = np.column_stack([rng.uniform(-span, span, (n, 2)), rng.uniform(-4.0, 4.0, n)])
    quarter = rng.random(n) < 0.2
    b[quarter, 2] = a[quarter, 2] + rng.integers(-4, 5, quarter.sum()) * (math.pi / 2)
    same_place = rng.random(n) < 0.1
    b[same_place, :2] = a[same_place, :2]
    same_pose = rng.random(n) < 0.02
    b[same_pose] = a[same_pose]
    return a, b


@pytest.mark.parametrize("span", [0.01, 0.5, 2.0, 5.0, 100.0])
@pytest.mark.parametrize("radius", [0.5, 1.0, 2.3])
def test_bit_for_bit_equal_to_the_full_solver(span, radius):
    a, b = hard_pairs(20_000, seed=int(span * 100 + radius * 10), span=span)
    full = reeds_shepp.distances(a, b, radius)
    fast = reeds_shepp_length.lengths(a, b, radius)
    np.testing.assert_array_equal(fast.view(np.int64), full.view(np.int64))


def test_equal_to_the_path_length_of_shortest():
    a, b = hard_pairs(300, seed=11, span=3.0)
    fast = reeds_shepp_length.lengths(a, b, 0.7)
    ref = [reeds_shepp.distance(p, q, 0.7) for p, q in zip(a, b)]
    np.testing.assert_allclose(fast, ref, rtol=1e-12, atol=1e-12)


def test_equal_to_ompl():
    ob = pytest.importorskip("ompl.base")
    space = ob.ReedsSheppStateSpace(0.8)
    s1, s2 = space.allocState(), space.allocState()
    a, b = hard_pairs(3000, seed=5, span=4.0)
    ref = np.empty(len(a))
    for i in range(len(a)):
        s1.setX(a[i, 0]), s1.setY(a[i, 1]), s1.setYaw(a[i, 2])
        s2.setX(b[i, 0]), s2.setY(b[i, 1]), s2.setYaw(b[i, 2])
        ref[i] = space.distance(s1, s2)
    np.testing.assert_allclose(reeds_shepp_length.lengths(a, b, 0.8), ref, rtol=1e-9, atol=1e-12)


def test_hand_derived_lengths():
    length = reeds_shepp_length.length
    assert length(0.0, 0.0, 0.0) == pytest.approx(0.0, abs=1e-12)
    assert length(5.0, 0.0, 0.0) == pytest.approx(5.0, rel=1e-12)  # straight ahead
    assert length(-1.5, 0.0, 0.0) == pytest.approx(1.5, rel=1e-12)  # straight back
    assert length(0.0, 2.0, math.pi) == pytest.approx(math.pi, rel=1e-12)  # a left half turn, radius 1
    assert length(1.0, 1.0, math.pi / 2) == pytest.approx(math.pi / 2, rel=1e-12)  # a left quarter turn
    assert length(-1.0, 1.0, -math.pi / 2) == pytest.approx(math.pi / 2, rel=1e-12)  # the same in reverse


def test_below_a_cutoff_exact_and_above_it_inf():
    a, b = hard_pairs(20_000, seed=9, span=3.0)
    full = reeds_shepp.distances(a, b, 1.0)
    rng = np.random.default_rng(2)
    cutoff = full * rng.uniform(0.5, 1.5, len(full))
    cutoff[::7] = full[::7]  # a cutoff equal to the length is not below it
    below = np.array([reeds_shepp_length.length_below(*reeds_shepp._local(*p, *q, 1.0), c)
                      for p, q, c in zip(a, b, cutoff)])
    inside = full < cutoff
    np.testing.assert_array_equal(below[inside].view(np.int64), full[inside].view(np.int64))
    assert np.isinf(below[~inside]).all()
