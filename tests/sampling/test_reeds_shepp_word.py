"""The Reeds–Shepp word found with a cutoff (reeds_shepp_length.word, word_below) against the full
solver (reeds_shepp._shortest_into, which evaluates all 44 word evaluations: the brute force)."""

import math

import numpy as np
import pytest

from navlab.sampling import reeds_shepp, reeds_shepp_length
from navlab.sampling.curves import MAX_SEGMENTS

from .test_rs_length import hard_pairs


def _full(p, q, radius):
    seg, kinds, lengths = np.zeros(MAX_SEGMENTS), np.zeros(MAX_SEGMENTS, dtype=np.int64), np.zeros(MAX_SEGMENTS)
    total = reeds_shepp._shortest_into(*reeds_shepp._local(*p, *q, radius), seg, kinds, lengths)
    return total, kinds, lengths


@pytest.mark.parametrize("span", [0.01, 0.5, 2.0, 5.0])
def test_the_word_given_its_length_is_the_full_solvers_bit_for_bit(span):
    a, b = hard_pairs(1500, seed=int(span * 100) + 7, span=span)  # 6 000 hard pairs over the four spans
    seg, kinds, lengths = np.zeros(MAX_SEGMENTS), np.zeros(MAX_SEGMENTS, dtype=np.int64), np.zeros(MAX_SEGMENTS)
    for p, q in zip(a, b):
        want, want_kinds, want_lengths = _full(p, q, 0.9)
        local = reeds_shepp._local(*p, *q, 0.9)
        for known in (reeds_shepp_length.length(*local), math.inf):
            kinds[:] = -7
            got = reeds_shepp_length.word(*local, known, seg, kinds, lengths)
            assert got == want
            np.testing.assert_array_equal(kinds, want_kinds)
            np.testing.assert_array_equal(lengths.view(np.int64), want_lengths.view(np.int64))


def test_below_the_cutoff_or_inf_and_untouched():
    a, b = hard_pairs(3000, seed=3, span=2.0)
    seg, kinds, lengths = np.zeros(MAX_SEGMENTS), np.zeros(MAX_SEGMENTS, dtype=np.int64), np.zeros(MAX_SEGMENTS)
    rng = np.random.default_rng(4)
    below = 0
    for p, q in zip(a, b):
        want, want_kinds, want_lengths = _full(p, q, 1.0)
        cutoff = want * rng.uniform(0.5, 1.5)
        kinds[:] = -7
        got = reeds_shepp_length.word_below(*reeds_shepp._local(*p, *q, 1.0), cutoff, seg, kinds, lengths)
        if want < cutoff:
            below += 1
            assert got == want
            np.testing.assert_array_equal(kinds, want_kinds)
        else:
            assert got == math.inf and np.all(kinds == -7)
    assert 1000 < below < 2000  # both branches were exercised
