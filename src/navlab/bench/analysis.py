"""From rows to findings: per-cell summaries, comparisons within each world,
the seed's side-by-side tables and the verdict on each stated claim."""

from __future__ import annotations

from collections import defaultdict
from typing import Any, Dict, List

from .stats import ALPHA, cell_summary, compare, holm, magnitude, metric_values, pairwise

METRICS = ("cost", "time_s")


def group_of(row: Dict[str, Any]) -> str:
    """A row's group within its world: planner and sampler."""
    return f"{row['planner']} / {row['sampler']}"


def by_world(rows: List[Dict[str, Any]]) -> Dict[str, Dict[str, List[Dict[str, Any]]]]:
    """rows[world][group] in first-seen order."""
    out: Dict[str, Dict[str, List[Dict[str, Any]]]] = defaultdict(lambda: defaultdict(list))
    for row in rows:
        out[row["world"]][group_of(row)].append(row)
    return {w: dict(g) for w, g in out.items()}


def summarize(rows: List[Dict[str, Any]]) -> Dict[str, Any]:
    """Everything a report needs, as JSON-ready data."""
    worlds = by_world(rows)
    cells = []
    for world, groups in worlds.items():
        for group, members in groups.items():
            cells.append({"world": world, "group": group, "cell_id": members[0]["cell_id"],
                          **cell_summary(members)})
    comparisons = {world: {m: pairwise(groups, m) for m in METRICS} for world, groups in worlds.items()}
    return {"cells": cells, "comparisons": comparisons}


def _matches(group: str, name: str) -> bool:
    planner, sampler = group.split(" / ", 1)
    return name in (group, planner, sampler)


def judge_claims(rows: List[Dict[str, Any]], claims: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    """For each claim and world: 'confirmed' (the 'lower' group is lower,
    Mann–Whitney significant after Holm over the comparisons in that world),
    'contradicted' (significantly the other way) or 'not shown'."""
    verdicts = []
    for world, groups in by_world(rows).items():
        tests = []
        for claim in claims:
            lows = claim["lower"] if isinstance(claim["lower"], list) else [claim["lower"]]
            highs = claim["higher"] if isinstance(claim["higher"], list) else [claim["higher"]]
            for low in lows:
                for high in highs:
                    ga = next((g for g in groups if _matches(g, low)), None)
                    gb = next((g for g in groups if _matches(g, high)), None)
                    if ga is None or gb is None:
                        continue
                    tests.append((claim, low, high, compare(metric_values(groups[ga], claim["metric"]),
                                                            metric_values(groups[gb], claim["metric"]))))
        for (claim, low, high, test), p in zip(tests, holm([t[3]["p"] for t in tests])):
            delta = test["delta"]
            if p is not None and p < ALPHA and delta is not None:
                verdict = "confirmed" if delta < 0 else "contradicted"
            else:
                verdict = "not shown"
            verdicts.append({"world": world, "claim": claim["text"], "metric": claim["metric"], "lower": low,
                             "higher": high, "verdict": verdict, "p_holm": p, "delta": delta,
                             "magnitude": magnitude(delta), "median_lower": test["median_a"],
                             "median_higher": test["median_b"], "n": [test["n_a"], test["n_b"]]})
    return verdicts


def overall_verdicts(verdicts: List[Dict[str, Any]]) -> Dict[str, str]:
    """One line per claim over all worlds: confirmed everywhere, nowhere, or where."""
    out: Dict[str, List[str]] = defaultdict(list)
    for v in verdicts:
        out[v["claim"]].append(v)
    lines = {}
    for claim, vs in out.items():
        confirmed = sorted({v["world"] for v in vs if v["verdict"] == "confirmed"})
        contradicted = sorted({v["world"] for v in vs if v["verdict"] == "contradicted"})
        worlds = sorted({v["world"] for v in vs})
        if len(confirmed) == len(worlds) and all(v["verdict"] == "confirmed" for v in vs):
            lines[claim] = "confirmed in every world"
        elif contradicted:
            lines[claim] = (f"contradicted in {', '.join(contradicted)}"
                            + (f"; confirmed in {', '.join(confirmed)}" if confirmed else ""))
        elif confirmed:
            lines[claim] = f"confirmed in {', '.join(confirmed)} only; not shown elsewhere"
        else:
            lines[claim] = "not shown in any world"
    return lines


def side_by_side(groups: Dict[str, List[Dict[str, Any]]], a: str, b: str) -> List[List[Any]]:
    """The seed's per-trial layout: trial, cost and time of ``a``, then of
    ``b``, with mean and min rows (costs of failed trials shown as '-')."""
    ra = sorted(groups[a], key=lambda r: r["trial"])
    rb = sorted(groups[b], key=lambda r: r["trial"])
    table = []
    for i in range(max(len(ra), len(rb))):
        row: List[Any] = [i + 1]
        for side in (ra, rb):
            r = side[i] if i < len(side) else {}
            row += [r.get("cost") if r.get("success") else None, r.get("time_s")]
        table.append(row)
    for label, fn in (("mean", lambda v: sum(v) / len(v)), ("min", min)):
        row = [label]
        for side in (ra, rb):
            for metric in ("cost", "time_s"):
                vals = metric_values(side, metric)
                row.append(fn(vals) if vals else None)
        table.append(row)
    return table
