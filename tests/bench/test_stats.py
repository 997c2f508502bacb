"""Statistics against scipy and brute force on known inputs."""

import itertools
import warnings

import numpy as np
import pytest
from scipy import stats as sps

from navlab.bench.stats import cliffs_delta, compare, describe, holm, pairwise


def test_describe_matches_numpy_and_scipy():
    x = np.random.default_rng(1).normal(10, 2, 25)
    d = describe(list(x))
    assert d["mean"] == pytest.approx(x.mean()) and d["std"] == pytest.approx(x.std(ddof=1))
    lo, hi = sps.t.interval(0.95, len(x) - 1, loc=x.mean(), scale=sps.sem(x))
    assert d["ci95"] == pytest.approx([lo, hi])
    assert describe([None, None])["n"] == 0 and describe([3.0])["ci95"] == [None, None]  # one value: no interval
    assert describe([3.0, 3.0])["ci95"] == [3.0, 3.0]
    # a NaN or infinite value leaves no interval (it took the equal-values branch: [inf, inf]; newcomer, session 26)
    for odd in ([1.0, np.inf], [np.nan, 2.0, 3.0], [np.inf, np.inf], [-np.inf, 1.0]):
        assert describe(odd)["ci95"] == [None, None], odd


@pytest.mark.parametrize("n, odd", [(1, None), (2, None), (3, None), (8, None), (9, None), (25, None),
                                    (200, None), (1, np.nan), (4, np.nan), (5, np.inf), (6, -np.inf),
                                    (2, 1e308)])
def test_describe_gives_numpys_numbers_to_the_bit(n, odd):
    """(describe skips numpy for one value, and the summary of 10 000 one-trial cells took 7 s in numpy's
    per-call overhead; two or more values are numpy's own answers)"""
    x = np.random.default_rng(n).lognormal(2, 1, n)
    if odd is not None:
        x[n // 2] = odd
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning reaches a user (issue 22), even from inf - inf
        d = describe([*x, None])
    with np.errstate(over="ignore"):
        want = {"mean": np.mean(x), "median": np.median(x), "min": np.min(x), "max": np.max(x)}
    assert str({k: d[k] for k in want}) == str({k: float(v) for k, v in want.items()}) and d["n"] == n  # (nan)
    with np.errstate(invalid="ignore", over="ignore"):  # (numpy's own answers, for the reference)
        assert str(d["std"]) == str(float(np.std(x, ddof=1)) if n > 1 else None)
    if odd is None:  # (the sign of a zero too: review, session 26)
        for zeros in ([-0.0], [0.0, -0.0], [-0.0, 0.0], [0.0, -0.0, 1.0], [-0.0, -0.0], [-1.0, -0.0, 0.0]):
            z = describe(zeros)
            ref = {"mean": np.mean(zeros), "median": np.median(zeros), "min": np.min(zeros), "max": np.max(zeros)}
            assert str({k: z[k] for k in ref}) == str({k: float(v) for k, v in ref.items()}), zeros
    if n > 1 and odd is None:
        half = sps.t.ppf(0.975, n - 1) * np.std(x, ddof=1) / np.sqrt(n)
        assert d["ci95"] == pytest.approx([max(np.mean(x) - half, 0.0), np.mean(x) + half], rel=1e-12)


def test_the_interval_of_a_quantity_that_cannot_be_negative_stops_at_zero():
    """(two costs of 1 and 30 m gave [−169, 200] m: newcomer, session 22)"""
    lo, hi = sps.t.interval(0.95, 1, loc=15.5, scale=sps.sem([1.0, 30.0]))
    assert lo < -100
    assert describe([1.0, 30.0])["ci95"] == pytest.approx([0.0, hi])
    assert describe([-1.0, 30.0])["ci95"][0] < 0  # a quantity that was negative keeps its interval


def test_cliffs_delta_equals_the_pairwise_count():
    rng = np.random.default_rng(2)
    a, b = rng.integers(0, 6, 17).astype(float), rng.integers(1, 7, 13).astype(float)  # with ties
    brute = sum(np.sign(x - y) for x, y in itertools.product(a, b)) / (len(a) * len(b))
    assert cliffs_delta(a, b) == pytest.approx(brute)
    assert cliffs_delta([1, 2], [3, 4]) == -1.0


def test_compare_is_scipys_mann_whitney():
    a, b = [1.1, 2.3, 2.9, 4.0, 5.5], [3.2, 4.4, 6.1, 7.0, 8.8, 9.1]
    ref = sps.mannwhitneyu(a, b, alternative="two-sided")
    out = compare(a, b)
    assert out["u"] == ref.statistic and out["p"] == pytest.approx(ref.pvalue)
    assert compare([1.0], [2.0])["p"] is None


def test_holm_on_a_textbook_example():
    # Holm (1979) style: p = .01, .04, .03, .005 with m = 4
    assert holm([0.01, 0.04, 0.03, 0.005]) == pytest.approx([0.03, 0.06, 0.06, 0.02])
    assert holm([None, 0.2]) == [None, 0.2]


def test_pairwise_flags_a_clear_difference():
    rows = {"fast": [{"success": True, "cost": 1.0 + i * 0.01, "status": "EXACT"} for i in range(20)],
            "slow": [{"success": True, "cost": 2.0 + i * 0.01, "status": "EXACT"} for i in range(20)]}
    (c,) = pairwise(rows, "cost")
    assert c["significant"] and c["delta"] == -1.0 and c["magnitude"] == "large"
