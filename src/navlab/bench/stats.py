"""Summaries and comparisons of trial rows.

Costs and times are summarised over successful trials only (a failed trial
has no path length, and its time is the time it took to give up). Comparisons use the
two-sided Mann–Whitney U test (no normality assumed: planner costs are
skewed) with Cliff's delta as effect size, and Holm's correction across the
comparisons made within one environment.

References
----------
H. B. Mann, D. R. Whitney, "On a test of whether one of two random variables
is stochastically larger than the other", Ann. Math. Statist. 18(1), 1947.
N. Cliff, "Dominance statistics: ordinal analyses to answer ordinal
questions", Psychological Bulletin 114(3), 1993.
S. Holm, "A simple sequentially rejective multiple test procedure",
Scand. J. Statist. 6(2), 1979.
"""

from __future__ import annotations

import functools
import math
from typing import Any, Dict, List, Optional, Sequence

import numpy as np
from scipy import stats as sps

ALPHA = 0.05


def describe(values: Sequence[float]) -> Dict[str, Any]:
    """n, mean, median, min, max, sample std and the 95% t-interval of the mean (those two None from one value;
    the interval None where a value is NaN or infinite, which leaves the std NaN).

    The interval of a quantity that cannot be negative (every value ≥ 0: a length, a time, a count) stops
    at 0: from two costs of 1 and 30 m it read [−169, 200] m (newcomer, session 22).

    A summary describes nine metrics of every cell, and a sweep of 10 000 one-trial cells spent 7 s in
    numpy's per-call overhead on one-element arrays: one value is described without numpy (numpy's numbers:
    its sums start from +0.0, so the mean and median of -0.0 are 0.0), and the t quantile is computed once
    per sample size."""
    picked = [float(v) for v in values if v is not None]
    n = len(picked)
    if n == 0:
        return {"n": 0, "mean": None, "median": None, "min": None, "max": None, "std": None,
                "ci95": [None, None]}
    if n == 1:  # one value says nothing of the spread: no interval (it was a zero-width one: newcomer, session 22)
        v = picked[0]
        return {"n": 1, "mean": 0.0 + v, "median": 0.0 + v, "min": v, "max": v, "std": None, "ci95": [None, None]}
    x = np.asarray(picked)
    # inf - inf, or a sum past 1.8e308: NaN or inf, without numpy's RuntimeWarning on stderr (newcomer, s. 26)
    with np.errstate(invalid="ignore", over="ignore"):
        mean = float(np.mean(x))
        std = float(np.std(x, ddof=1))
        median = float(np.median(x))
    if std > 0:
        half = _t975(n - 1) * std / math.sqrt(n)
        ci = [max(mean - half, 0.0) if x.min() >= 0 else mean - half, mean + half]
    elif std == 0:  # every value the same
        ci = [mean, mean]
    else:  # NaN: a value was NaN or infinite, so there is no interval (it read [inf, inf]: newcomer, session 26)
        ci = [None, None]
    return {"n": n, "mean": mean, "median": median, "min": float(np.min(x)),
            "max": float(np.max(x)), "std": std, "ci95": ci}


@functools.lru_cache(maxsize=256)
def _t975(dof: int) -> float:
    """The 97.5 % quantile of Student's t with ``dof`` degrees of freedom (a pure function of an int)."""
    return float(sps.t.ppf(0.975, dof))


#: metrics described over the trials that found a path only: a path metric has no
#: value otherwise, and a failed trial's time is the time it took to give up
SUCCESS_ONLY = ("cost", "first_solution_iteration", "vs_optimum", "vs_theta", "time", "cpu_s", "wall_s", "time_s")


def metric_values(rows: List[Dict[str, Any]], metric: str) -> List[float]:
    """``metric`` over the trials it means something for: path metrics over
    successful trials, the others over every trial that ran."""
    if metric in SUCCESS_ONLY:
        picked = [r.get(metric) for r in rows if r.get("success")]
    else:
        picked = [r.get(metric) for r in rows if r.get("status") != "ERROR"]
    return [v for v in picked if v is not None]


#: what a cell summary describes: ``time`` is the time the analysis uses
#: (CPU or wall, see :func:`navlab.bench.analysis.timed`); ``time_s`` is the
#: planner's own clock, ``cpu_s``/``wall_s`` the trial's
SUMMARY_METRICS = ("cost", "time", "cpu_s", "wall_s", "time_s", "iterations", "first_solution_iteration",
                   "vs_optimum", "vs_theta")


def cell_summary(rows: List[Dict[str, Any]], compared: Optional[List[Dict[str, Any]]] = None) -> Dict[str, Any]:
    """Success rate and descriptions of cost, times and iterations for one cell.

    ``compared``: the rows the metrics that exist only for solved trials
    (:data:`SUCCESS_ONLY`) are described over, when not all of ``rows``' solved
    ones (on map experiments, the queries every cell solved:
    :func:`navlab.bench.analysis.compared_rows`); the counts and iterations are
    always over ``rows``."""
    ran = sum(r.get("status") != "ERROR" for r in rows)
    ok = sum(bool(r.get("success")) for r in rows)
    return {"trials": len(rows), "errors": len(rows) - ran, "successes": ok,
            "success_rate": ok / ran if ran else None,
            **{m: describe(metric_values(rows if compared is None or m not in SUCCESS_ONLY else compared, m))
               for m in SUMMARY_METRICS}}


def cliffs_delta(a: Sequence[float], b: Sequence[float]) -> float:
    """P(A > B) − P(A < B) over all pairs: −1 when every a is below every b."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if not len(a) or not len(b):
        return float("nan")
    u = sps.mannwhitneyu(a, b, alternative="two-sided").statistic  # U of a: #(a > b) + #ties/2
    return float(2.0 * u / (len(a) * len(b)) - 1.0)


def compare(a: Sequence[float], b: Sequence[float]) -> Dict[str, Any]:
    """Mann–Whitney U (two-sided) of samples a and b, with Cliff's delta."""
    a = [v for v in a if v is not None]
    b = [v for v in b if v is not None]
    out: Dict[str, Any] = {"n_a": len(a), "n_b": len(b),
                           "median_a": float(np.median(a)) if a else None,
                           "median_b": float(np.median(b)) if b else None}
    if len(a) < 2 or len(b) < 2:
        return out | {"u": None, "p": None, "delta": None}
    test = sps.mannwhitneyu(a, b, alternative="two-sided")
    p = float(test.pvalue)
    return out | {"u": float(test.statistic), "p": p if math.isfinite(p) else 1.0, "delta": cliffs_delta(a, b)}


def holm(pvalues: Sequence[Optional[float]]) -> List[Optional[float]]:
    """Holm–Bonferroni adjusted p-values (None stays None)."""
    idx = [i for i, p in enumerate(pvalues) if p is not None]
    order = sorted(idx, key=lambda i: pvalues[i])
    m = len(order)
    adjusted: List[Optional[float]] = [None] * len(pvalues)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * pvalues[i]))
        adjusted[i] = running
    return adjusted


def magnitude(delta: Optional[float]) -> str:
    """Romano et al.'s thresholds for |Cliff's delta|."""
    if delta is None or not math.isfinite(delta):
        return "n/a"
    d = abs(delta)
    return "negligible" if d < 0.147 else "small" if d < 0.33 else "medium" if d < 0.474 else "large"


def pairwise(groups: Dict[str, List[Dict[str, Any]]], metric: str) -> List[Dict[str, Any]]:
    """Every pair of groups (e.g. samplers within one world) compared on
    ``metric`` (over the trials :func:`metric_values` picks),
    with Holm-adjusted p-values."""
    names = list(groups)
    out = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            out.append({"a": a, "b": b, "metric": metric,
                        **compare(metric_values(groups[a], metric), metric_values(groups[b], metric))})
    for row, p in zip(out, holm([r["p"] for r in out])):
        row["p_holm"] = p
        row["significant"] = p is not None and p < ALPHA
        row["magnitude"] = magnitude(row["delta"])
    return out
