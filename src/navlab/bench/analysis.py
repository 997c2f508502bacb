"""From rows to findings: per-cell summaries, comparisons within each world,
the seed's side-by-side tables and the verdict on each stated claim.

Time verdicts that do not flip
------------------------------
Path costs and iteration counts are the same on every run (same seeds, same
work); times are not. A time verdict is therefore held to two tests:

1. *significant*: two-sided Mann–Whitney U, Holm-corrected over the claims
   (or pairs) of the world, p < 0.05 — the difference is not luck of the seeds;
2. *larger than the timing noise*: the ratio of the two groups' median times
   differs from 1 by more than ``max(MIN_TIME_EFFECT, NOISE_FACTOR × ε)`` on a
   log scale, where ε is the run-to-run noise the harness measures where the
   pair of cells ran: the first trials of every cell are run a second time late
   in the run (:data:`~navlab.bench.experiment.NOISE_REPEATS`; same seed, same
   work) and ε is the median of ``|log(t_repeat / t_first)|`` over the repeats
   of the two cells and of the other cells of their world (the pair's own four
   repeats alone let one disturbed repeat move the bar; CPU-time noise comes
   from the machine, which every cell of the run shares).

Only then is a time claim *confirmed* or *contradicted*; otherwise it is *not
shown* and the report says whether the difference was within the noise.

Verdicts only on solved trials
------------------------------
A planner that did not reach the goal has no path cost, and its time is the
time it took to give up: comparing it with a planner that succeeded says
nothing about either. Every cost and time comparison (claims and pairwise
tables) therefore uses only the trials that reached the goal, and on map
experiments with several queries per world only the queries both sides solved.
The per-cell cost and time statistics, the box plots and the seed's
side-by-side means follow the same rule (:func:`compared_rows`): on a map
experiment a cell's statistics are over the queries every cell of its world
that solved anything solved, so the cells are described on the same queries
(a cell that solved only the short query is not set beside one that also
solved the long one). Experiments without queries repeat one start and goal,
so there each cell is described over all its solved trials.
A verdict needs at least :data:`MIN_SOLVED` such trials on each side;
otherwise it is *not shown* with the counts ("not shown: boundary solved 0/20,
integration 20/20"). Every verdict carries both sides' success rates. The
floor keeps verdicts off the knife edge: the three runs in docs/bench.md are
the acceptance test. Trials are run interleaved across cells (trial 0 of every
cell, then trial 1, ...), so a load that changes during a run slows every cell
alike, and times are the thread's CPU time by default (``--time wall`` for wall
time).
"""

from __future__ import annotations

import math
from collections import Counter, defaultdict
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from .stats import ALPHA, cell_summary, compare, holm, magnitude, metric_values

#: a time ratio within a third of 1 is never a verdict: below what a shared machine keeps stable
MIN_TIME_EFFECT = math.log(4 / 3)
#: a time ratio must exceed this many times the measured timing noise ε
NOISE_FACTOR = 2.0
#: row fields behind ``--time``
TIME_FIELDS = {"cpu": "cpu_s", "wall": "wall_s"}
TIME_LABELS = {"cpu": "thread CPU time", "wall": "wall-clock time"}
#: claim and summary metrics that are times (judged with the noise rule)
TIME_METRICS = ("time", "time_s")
#: reasons listed per cell in the report
TOP_REASONS = 3
#: a cost or time verdict needs at least this many solved trials on each side
MIN_SOLVED = 5


def group_of(row: Dict[str, Any]) -> str:
    """A row's group within its world: planner, sampler and swept values."""
    swept = row.get("swept") or {}
    return " / ".join([row["planner"], row["sampler"]] + [f"{k}={v}" for k, v in sorted(swept.items())])


#: the any-angle reference path of map queries
REFERENCE_PLANNER = "theta_star"


def timed(rows: List[Dict[str, Any]], time: str = "cpu") -> List[Dict[str, Any]]:
    """Copies of ``rows`` with ``row["time"]``: the trial's CPU or wall time
    (the planner's own ``time_s`` for rows that have neither); and, for map
    queries, ``row["vs_theta"]``: the path's length over the Theta* path's on
    the same query (when the experiment runs ``theta_star``)."""
    field = TIME_FIELDS[time]
    reference = {_query_key(r): r["cost"] for r in rows
                 if r.get("planner_name") == REFERENCE_PLANNER and r.get("success") and r.get("query") is not None
                 and not r.get("repeat") and r.get("cost")}
    out = []
    for row in rows:
        value = row.get(field)
        new = {**row, "time": value if value is not None else row.get("time_s")}
        ref = reference.get(_query_key(row)) if row.get("query") is not None else None
        if ref and row.get("success") and row.get("cost") is not None:
            new["vs_theta"] = row["cost"] / ref
        out.append(new)
    return out


def _query_key(row: Dict[str, Any]) -> tuple:
    return row["world"], row.get("query"), tuple(sorted((row.get("swept") or {}).items()))


def by_world(rows: List[Dict[str, Any]]) -> Dict[str, Dict[str, List[Dict[str, Any]]]]:
    """rows[world][group] in first-seen order (repeats of a trial left out)."""
    out: Dict[str, Dict[str, List[Dict[str, Any]]]] = defaultdict(lambda: defaultdict(list))
    for row in rows:
        if not row.get("repeat"):
            out[row["world"]][group_of(row)].append(row)
    return {w: dict(g) for w, g in out.items()}


def failures(rows: List[Dict[str, Any]]) -> Dict[str, Any]:
    """Statuses with counts, and the most common reasons of the trials that did
    not succeed (the exception's last line for an ERROR)."""
    statuses = Counter(r.get("status", "?") for r in rows)
    reasons = Counter(f"{r.get('status')}: {r.get('reason') or 'no reason given'}"
                      for r in rows if not r.get("success"))
    return {"statuses": dict(statuses.most_common()), "reasons": reasons.most_common(TOP_REASONS)}


def timing_noise(rows: List[Dict[str, Any]]) -> Dict[str, List[float]]:
    """Per cell: ``|log(t_repeat / t_first)|`` of each repeated trial (rows
    with ``time`` set, see :func:`timed`)."""
    first = {(r["cell_id"], r["trial"]): r for r in rows if not r.get("repeat")}
    out: Dict[str, List[float]] = defaultdict(list)
    for r in rows:
        if not r.get("repeat"):
            continue
        f = first.get((r["cell_id"], r["trial"]))
        a, b = (f or {}).get("time"), r.get("time")
        if a and b and a > 0 and b > 0 and f.get("status") != "ERROR" and r.get("status") != "ERROR":
            out[r["cell_id"]].append(abs(math.log(b / a)))
    return dict(out)


def noise_threshold(noise: Dict[str, List[float]], cells: List[str]) -> Dict[str, Any]:
    """ε where a pair of cells ran (the median repeat noise of ``cells``: the
    pair and the other cells of its world) and the log-ratio a time difference
    must exceed."""
    values = [v for cell in dict.fromkeys(cells) for v in noise.get(cell, [])]
    eps = float(np.median(values)) if values else None
    return {"noise": eps, "threshold": max(MIN_TIME_EFFECT, NOISE_FACTOR * eps) if eps is not None else MIN_TIME_EFFECT}


def time_decision(test: Dict[str, Any], p: Optional[float], limit: Dict[str, Any]) -> Dict[str, Any]:
    """The noise-aware verdict on a time difference (see the module docstring):
    ``direction`` -1 (a lower), +1 (a higher) or 0 (not shown), and why."""
    ma, mb = test.get("median_a"), test.get("median_b")
    ratio = ma / mb if ma and mb and mb > 0 else None
    if p is None:
        return {"direction": 0, "ratio": ratio, "why": _too_few(test)}
    significant = p < ALPHA and test.get("delta") is not None
    big = ratio is not None and ratio > 0 and abs(math.log(ratio)) > limit["threshold"]
    if significant and big:
        return {"direction": -1 if ratio < 1 else 1, "ratio": ratio, "why": ""}
    why = ("significant, but within the timing noise" if significant else "not significant")
    return {"direction": 0, "ratio": ratio, "why": why}


def plain_decision(test: Dict[str, Any], p: Optional[float]) -> Dict[str, Any]:
    """Verdict on a metric without timing noise (cost, iterations)."""
    delta = test.get("delta")
    if p is None:
        return {"direction": 0, "ratio": None, "why": _too_few(test)}
    if p < ALPHA and delta is not None and delta != 0:
        return {"direction": -1 if delta < 0 else 1, "ratio": None, "why": ""}
    return {"direction": 0, "ratio": None, "why": "not significant"}


def _too_few(test: Dict[str, Any]) -> str:
    return f"too few trials to compare ({test.get('n_a', 0)} and {test.get('n_b', 0)} with a value)"


def solved_text(rows: List[Dict[str, Any]]) -> str:
    """``solved/ran`` of a group's trials (errors do not count as run)."""
    ran = sum(r.get("status") != "ERROR" for r in rows)
    return f"{sum(bool(r.get('success')) for r in rows)}/{ran}"


def compared_rows(groups: Dict[str, List[Dict[str, Any]]]
                  ) -> Tuple[Dict[str, List[Dict[str, Any]]], Optional[Dict[str, int]]]:
    """The rows a cost or time comparison of ``groups`` uses: each group's
    solved trials and, when the rows carry a map ``query``, only the queries
    every group that solved anything solved (a group that solved nothing has
    no rows and does not empty the others' comparison).

    Returns the rows per group and the scope: ``None`` without queries, else
    ``{"common": queries compared, "queries": queries run}``.
    """
    solved = {g: [r for r in rows if r.get("success")] for g, rows in groups.items()}
    queries = {r["query"] for rows in groups.values() for r in rows if r.get("query") is not None}
    if not queries:
        return solved, None
    # each trial is a different start and goal: costs over different queries measure the queries, not the cells
    sets = [{r.get("query") for r in rows} for rows in solved.values() if rows]
    common = set.intersection(*sets) if sets else set()
    return ({g: [r for r in rows if r.get("query") in common] for g, rows in solved.items()},
            {"common": len(common), "queries": len(queries)})


def scope_text(scope: Optional[Dict[str, int]]) -> str:
    """What a world's cost and time statistics are over, as the report and
    the box plots say it (see :func:`compared_rows`)."""
    if scope is None:
        return "cost and time of the trials that reached the goal"
    k = scope["common"]
    return (f"cost and time over the {k} quer{'y' if k == 1 else 'ies'} all cells solved "
            f"(of {scope['queries']})")


def judged_values(rows_a: List[Dict[str, Any]], rows_b: List[Dict[str, Any]],
                  metric: str) -> Tuple[List[float], List[float], str]:
    """The values a verdict on ``metric`` compares: solved trials only, and on
    map experiments only the queries both groups solved (:func:`compared_rows`);
    with a reason when a side has fewer than :data:`MIN_SOLVED` (then no
    verdict may be drawn)."""
    picked, _ = compared_rows({"a": rows_a, "b": rows_b})
    va = [r[metric] for r in picked["a"] if r.get(metric) is not None]
    vb = [r[metric] for r in picked["b"] if r.get(metric) is not None]
    short = ""
    if min(len(va), len(vb)) < MIN_SOLVED:
        short = (f"a cost or time verdict needs {MIN_SOLVED} solved trials on each side; "
                 f"solved: {solved_text(rows_a)} and {solved_text(rows_b)}")
    return va, vb, short


#: Worlds with more cells than this get no all-pairs comparison table (40 cells
#: are 780 pairs); the cells' own statistics and the claims are still there.
#: Comparisons one cares about in a larger sweep are stated as claims.
MAX_PAIRWISE_CELLS = 40


def summarize(rows: List[Dict[str, Any]], time: str = "cpu") -> Dict[str, Any]:
    """Everything a report needs, as JSON-ready data. Cells are keyed by
    world, planner, sampler and swept values; ``time`` picks CPU or wall time."""
    rows = timed(rows, time)
    noise = timing_noise(rows)
    worlds = by_world(rows)
    cells = []
    scopes = {}
    for world, groups in worlds.items():
        compared, scopes[world] = compared_rows(groups)
        for group, members in groups.items():
            first = members[0]
            cells.append({"world": world, "group": group, "cell_id": first["cell_id"], "planner": first["planner"],
                          "sampler": first["sampler"], "swept": dict(first.get("swept") or {}),
                          **cell_summary(members, compared[group]),
                          **failures(members),
                          "warmup_s": sum(r.get("warmup_s") or 0.0 for r in members),
                          "params_used": next((r["params_used"] for r in members if r.get("params_used")), {}),
                          "timing_noise": float(np.median(noise[first["cell_id"]])) if noise.get(first["cell_id"]) else None})
    # every pair of cells is n²/2 comparisons: bounded, or a 10 000-cell sweep's summary took 7.8 GB
    comparisons = {world: {m: pairwise_judged(groups, m, noise) if len(groups) <= MAX_PAIRWISE_CELLS else []
                           for m in ("cost", "time")}
                   for world, groups in worlds.items()}
    too_many = {world: len(groups) for world, groups in worlds.items() if len(groups) > MAX_PAIRWISE_CELLS}
    swept = sorted({k for c in cells for k in c["swept"]})
    return {"time": time, "time_label": TIME_LABELS[time], "swept": swept, "cells": cells,
            "comparisons": comparisons, "pairwise_skipped": too_many, "rule": rule_text(),
            "compared": {w: scope for w, scope in scopes.items() if scope is not None}}


def rule_text() -> str:
    return (f"a time difference counts only when Mann–Whitney (Holm) p < {ALPHA} and the ratio of median "
            f"times is beyond ×{math.exp(MIN_TIME_EFFECT):.2f} and beyond exp({NOISE_FACTOR:g}·ε), ε being the "
            "run-to-run timing noise measured by repeating trials of the two cells and of their world's others")


def pairwise_judged(groups: Dict[str, List[Dict[str, Any]]], metric: str,
                    noise: Dict[str, List[float]]) -> List[Dict[str, Any]]:
    """Every pair of groups compared on ``metric``, Holm over the pairs, with
    the noise rule for times."""
    names = list(groups)
    out = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            va, vb, short = judged_values(groups[a], groups[b], metric)
            test = compare(va, vb) if not short else {"n_a": len(va), "n_b": len(vb), "p": None, "delta": None,
                                                      "median_a": _median(va), "median_b": _median(vb)}
            out.append({"a": a, "b": b, "metric": metric, "short": short,
                        "solved": [solved_text(groups[a]), solved_text(groups[b])], **test})
    for row, p in zip(out, holm([r["p"] for r in out])):
        row["p_holm"] = p
        row["magnitude"] = magnitude(row["delta"])
        if row["short"]:
            decision = {"direction": 0, "why": row["short"]}
        elif metric in TIME_METRICS:
            limit = noise_threshold(noise, _world_cells(groups, row["a"], row["b"]))
            decision = time_decision(row, p, limit)
            row.update(noise=limit["noise"], threshold_ratio=math.exp(limit["threshold"]))
        else:
            decision = plain_decision(row, p)
        row["significant"] = decision["direction"] != 0
        row["direction"] = decision["direction"]
        row["why"] = decision["why"]
    return out


def _median(values: List[float]) -> Optional[float]:
    return float(np.median(values)) if values else None


def _world_cells(groups: Dict[str, List[Dict[str, Any]]], a: str, b: str) -> List[str]:
    """Cell ids of a pair first, then of the rest of its world."""
    return [groups[a][0]["cell_id"], groups[b][0]["cell_id"]] + [m[0]["cell_id"] for m in groups.values()]


def _matches(group: str, name: str) -> bool:
    return name == group or name in group.split(" / ")


def judge_claims(rows: List[Dict[str, Any]], claims: List[Dict[str, Any]], time: str = "cpu") -> List[Dict[str, Any]]:
    """For each claim and world: 'confirmed' (the 'lower' group is lower),
    'contradicted' (the other way) or 'not shown'. Mann–Whitney, Holm over the
    comparisons in that world; times must also beat the timing noise (see the
    module docstring). A claim names groups by planner, sampler or ``k=v``;
    with swept parameters it is judged within each swept combination."""
    rows = timed(rows, time)
    noise = timing_noise(rows)
    verdicts = []
    for world, groups in by_world(rows).items():
        tests = []
        for claim in claims:
            metric = "time" if claim["metric"] in TIME_METRICS else claim["metric"]
            lows = claim["lower"] if isinstance(claim["lower"], list) else [claim["lower"]]
            highs = claim["higher"] if isinstance(claim["higher"], list) else [claim["higher"]]
            for low in lows:
                for high in highs:
                    for ga in [g for g in groups if _matches(g, low)]:
                        for gb in _partners(ga, low, high, groups):
                            va, vb, short = judged_values(groups[ga], groups[gb], metric)
                            test = compare(va, vb) if not short else {
                                "n_a": len(va), "n_b": len(vb), "p": None, "delta": None,
                                "median_a": _median(va), "median_b": _median(vb)}
                            tests.append((claim, metric, low, high, ga, gb, {**test, "short": short}))
        for claim in claims:  # a claim with no pair of cells to compare here is said so, not left out (a
            # planner's own setting that no swept cell of the other side shares: review, session 23)
            if not any(t[0] is claim for t in tests):
                verdicts.append(_unpaired(world, claim))
        for (claim, metric, low, high, ga, gb, test), p in zip(tests, holm([t[-1]["p"] for t in tests])):
            if test["short"]:
                limit = {"noise": None, "threshold": None}
                decision = {"direction": 0, "ratio": None, "why": test["short"]}
            elif metric == "time":
                limit = noise_threshold(noise, _world_cells(groups, ga, gb))
                decision = time_decision(test, p, limit)
            else:
                limit = {"noise": None, "threshold": None}
                decision = plain_decision(test, p)
            verdict = {-1: "confirmed", 1: "contradicted", 0: "not shown"}[decision["direction"]]
            verdicts.append({"world": world, "claim": claim["text"], "metric": claim["metric"], "lower": low,
                             "higher": high, "group_lower": ga, "group_higher": gb, "verdict": verdict,
                             "why": decision["why"], "p_holm": p, "delta": test["delta"],
                             "magnitude": magnitude(test["delta"]), "ratio": decision["ratio"],
                             "noise": limit["noise"],
                             "threshold_ratio": math.exp(limit["threshold"]) if limit["threshold"] else None,
                             "median_lower": test["median_a"], "median_higher": test["median_b"],
                             "n": [test["n_a"], test["n_b"]],
                             "solved": [solved_text(groups[ga]), solved_text(groups[gb])]})
    return verdicts


def _unpaired(world: str, claim: Dict[str, Any]) -> Dict[str, Any]:
    """The verdict of a claim that found no pair of cells in ``world`` (:func:`_partners`): not shown."""
    return {"world": world, "claim": claim["text"], "metric": claim["metric"], "lower": _names(claim["lower"]),
            "higher": _names(claim["higher"]), "group_lower": None, "group_higher": None, "verdict": "not shown",
            "why": "no pair of cells alike in all but what the claim names (a setting one side fixes at a value "
                   "the other side's cells did not run with)",
            "p_holm": None, "delta": None, "magnitude": "-", "ratio": None, "noise": None, "threshold_ratio": None,
            "median_lower": None, "median_higher": None, "n": [0, 0], "solved": []}


def _names(side: Any) -> str:
    return ", ".join(side) if isinstance(side, list) else side


def _partners(ga: str, low: str, high: str, groups: Dict[str, List[Dict[str, Any]]]) -> List[str]:
    """The groups named ``high`` that differ from ``ga`` only where ``low`` and ``high`` differ: the same
    planner when comparing samplers and the reverse (a planner that draws no samples faces any sampler's
    cells), and the same value of every setting both groups' cells ran with, swept or their own. A setting
    one side does not take at all (a sweep that did not split its cells) does not part them: its one cell
    ran the same search for every value and faces each of the other's cells (a cell not split by a sweep had
    no partner, and the claim vanished from the report; review and attacks, session 23). The planner,
    sampler and settings are read from the groups' rows, not parsed from their labels."""
    a = groups[ga][0]
    out = []
    for g, rows in groups.items():
        if g == ga or not _matches(g, high):
            continue
        if ga == low and g == high:  # (two whole group labels)
            out.append(g)
            continue
        b = rows[0]
        # (a planner that draws no samples, "-", faces a tree planner whatever its sampler)
        if not all(x == y or x == low or y == high or "-" in (x, y)
                   for x, y in ((a["planner"], b["planner"]), (a["sampler"], b["sampler"]))):
            continue
        keys = set(a.get("swept") or {}) | set(b.get("swept") or {})
        if all(_alike(k, _setting(a, k), _setting(b, k), low, high) for k in keys):
            out.append(g)
    return out


def _setting(row: Dict[str, Any], key: str) -> Any:
    """The value of ``key`` a row's cell ran with: swept, else as its settings recorded it (its planner's or
    sampler's own, or shared), else None (a setting its planner does not take)."""
    swept = row.get("swept") or {}
    return swept[key] if key in swept else (row.get("params") or {}).get(key)


def _alike(key: str, va: Any, vb: Any, low: str, high: str) -> bool:
    """Whether two cells' values of ``key`` let them be compared: equal, one not taken, or the very values
    the claim compares (``key=va`` lower, ``key=vb`` higher)."""
    return va is None or vb is None or va == vb or (f"{key}={va}" == low and f"{key}={vb}" == high)


def overall_verdicts(verdicts: List[Dict[str, Any]]) -> Dict[str, str]:
    """One line per claim over all worlds: confirmed everywhere, nowhere, or where, naming every
    world once (a claim with two comparisons, "faster than integration and Gaussian", named a world
    twice) and saying of each world what it showed: confirmed, contradicted, not shown, or too few
    solved trials to judge (a line said "contradicted in squarefield" and nothing of the others)."""
    out: Dict[str, List[Dict[str, Any]]] = defaultdict(list)
    for v in verdicts:
        out[v["claim"]].append(v)
    lines = {}
    for claim, vs in out.items():
        # a claim on several comparisons names the groups of each (which one decided a world was not said),
        # by their cells' labels where one name faced several cells (the line said "contradicted in trap (6/6
        # vs 6/6 solved); confirmed in trap (6/6 vs 6/6 solved)": attack, session 23)
        cells = len({(v["world"], v.get("group_lower"), v.get("group_higher")) for v in vs}) > len(
            {(v["world"], v["lower"], v["higher"]) for v in vs})
        naming = "cells" if cells else "names" if len({(v["lower"], v["higher"]) for v in vs}) > 1 else ""
        confirmed = _where(vs, "confirmed", naming)
        contradicted = _where(vs, "contradicted", naming)
        few = [v for v in vs if v["verdict"] == "not shown" and v.get("solved") and _too_few_solved(v)]
        sides = ("group_lower", "group_higher") if naming == "cells" else ("lower", "higher")
        unsolved = _by_world((v["world"], f"{v[sides[0]]} solved {v['solved'][0]}, {v[sides[1]]} {v['solved'][1]}")
                             for v in few)
        judged = {v["world"] for v in vs if v["verdict"] in ("confirmed", "contradicted")}
        rest = sorted({v["world"] for v in vs} - judged - {v["world"] for v in few})
        if all(v["verdict"] == "confirmed" for v in vs):
            lines[claim] = f"confirmed in every world: {confirmed}"
            continue
        parts = []
        if contradicted:
            parts.append(f"contradicted in {contradicted}")
        if confirmed:
            # ("only" where the rest is not listed: by cells each comparison not shown is named: newcomer, s. 23)
            parts.append(f"confirmed in {confirmed}" + ("" if contradicted or naming == "cells" else " only"))
        if naming == "cells":  # each comparison not shown, named, even in a world another one decided
            shown_not = _where([v for v in vs if v not in few], "not shown", naming)
            if shown_not:
                parts.append(f"not shown in {shown_not}")
        elif rest:  # ("not shown in any of" every world, and then too few to judge in them, said it twice)
            parts.append(f"not shown in {'' if judged or unsolved else 'any of '}{', '.join(rest)}")
        if unsolved:
            # "not shown", as the report's per-world table says it (the line's own wording for it confused),
            # with the rule: "too few solved trials" read as a failure where 2 of 2 trials had solved (newcomer
            # run, session 20)
            parts.append(f"not shown in {unsolved}: a verdict needs {MIN_SOLVED} solved trials on each side")
        lines[claim] = "; ".join(parts)
    return lines


def _by_world(items) -> str:
    """``world (detail; detail), ...`` from (world, detail) pairs, each world once, in first-seen order."""
    details: Dict[str, List[str]] = {}
    for world, detail in items:
        seen = details.setdefault(world, [])
        if detail not in seen:  # two comparisons with the same counts say them once
            seen.append(detail)
    return ", ".join(f"{world} ({'; '.join(d)})" if any(d) else world for world, d in details.items())


def _where(verdicts: List[Dict[str, Any]], verdict: str, naming: str = "") -> str:
    """``world (solved a/n vs b/n), ...`` for the verdicts saying ``verdict``, each world once; with
    ``naming``, each comparison's names (``"names"``: ``boundary vs gaussian: 18/20 vs 20/20 solved``) or its
    cells' labels (``"cells"``) before its counts."""
    def detail(v: Dict[str, Any]) -> str:
        counts = f"{v['solved'][0]} vs {v['solved'][1]} solved" if v.get("solved") else ""
        if not naming:
            return counts
        sides = (v["group_lower"] or v["lower"], v["group_higher"] or v["higher"]) if naming == "cells" else \
            (v["lower"], v["higher"])
        return f"{sides[0]} vs {sides[1]}" + (f": {counts}" if counts else "")

    return _by_world((v["world"], detail(v)) for v in verdicts if v["verdict"] == verdict)


def _too_few_solved(verdict: Dict[str, Any]) -> bool:
    return "solved trials on each side" in (verdict.get("why") or "")


def reference_table(study: Dict[str, Any], summary: Dict[str, Any]) -> Optional[List[List[Any]]]:
    """The document's numbers beside ours: per reference entry and metric,
    [world, group, reading, metric, document value, our mean, our median, agrees].

    An entry may name its ``reading`` of the document (where the document says
    two things, e.g. a table and a conclusion that disagree). ``solved`` is the
    share of trials that found a path (a table of means over every trial
    implies 1.0); for it, ``agrees`` says whether our success rate is the
    document's (within 0.1). An entry naming a world or part the run does not have (a suite edited to
    fewer) is left out: its rows of "-" passed silently (newcomer run, session 21).
    """
    refs = study.get("reference") or []
    if not refs:
        return None
    table = []
    for ref in refs:
        cells = [c for c in summary["cells"] if c["world"] == ref["world"] and _matches(c["group"], ref["group"])]
        if not cells:  # a world or part this run left out (an edited suite): nothing of ours to put beside it
            continue
        for metric, value in ref.items():
            if metric in ("world", "group", "reading"):
                continue
            if metric == "solved":
                ours = cells[0].get("success_rate")
                agrees = None if ours is None else ("yes" if abs(ours - value) <= 0.1 else "no")
                table.append([ref["world"], cells[0]["group"], ref.get("reading", ""), metric, value, ours, ours,
                              agrees])
                continue
            key = "time" if metric in TIME_METRICS else metric
            ours = cells[0].get(key, {})
            table.append([ref["world"], cells[0]["group"], ref.get("reading", ""), metric, value, ours.get("mean"),
                          ours.get("median"), None])
    return table


def side_by_side(groups: Dict[str, List[Dict[str, Any]]], a: str, b: str) -> List[List[Any]]:
    """The seed's per-trial layout: trial, cost and time of ``a``, then of
    ``b`` (costs of failed trials shown as '-'), with mean and min rows over
    the trials :func:`compared_rows` picks for the pair (on maps, the queries
    both solved)."""
    ra = sorted(groups[a], key=lambda r: r["trial"])
    rb = sorted(groups[b], key=lambda r: r["trial"])
    picked, _ = compared_rows({"a": ra, "b": rb})
    table = []
    for i in range(max(len(ra), len(rb))):
        row: List[Any] = [i + 1]
        for side in (ra, rb):
            r = side[i] if i < len(side) else {}
            row += [r.get("cost") if r.get("success") else None, r.get("time")]
        table.append(row)
    for label, fn in (("mean", lambda v: sum(v) / len(v)), ("min", min)):
        row = [label]
        for side in (picked["a"], picked["b"]):
            for metric in ("cost", "time"):
                vals = metric_values(side, metric)
                row.append(fn(vals) if vals else None)
        table.append(row)
    return table
