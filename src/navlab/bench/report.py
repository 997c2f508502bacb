"""The benchmark report, as Markdown (``report.md``) and as one
self-contained HTML page (``report.html``, images embedded).

The report is built once as a list of blocks (heading, paragraph, table,
image) and rendered to both formats, so they always say the same thing.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

from .analysis import (MAX_PAIRWISE_CELLS, MIN_SOLVED, by_world, overall_verdicts, reference_table, scope_text,
                       side_by_side)

#: per-trial side-by-side tables (the seed's layout) in a world: the first cell beside this many others
MAX_SIDE_BY_SIDE = 8

Block = Tuple[str, Any]


def fmt(value: Any, digits: int = 3) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        if not math.isfinite(value):
            return "-"
        return f"{value:.{digits}g}" if abs(value) < 1e-3 and value != 0 else f"{value:.{digits}f}"
    return str(value)


def _changed_from_suite(experiment: Dict[str, Any]) -> str:
    """A line saying how this run differs from the built-in suite of its name, whose study it reports
    against ("" when it does not, or there is no such suite): a --show template edited to 2 trials of 200
    iterations was set beside the document's 20 of 5 000 without a word (newcomer run, session 21)."""
    from .experiment import ExperimentError, differences, load_experiment
    from .suites import SUITES, find_suite

    name = experiment.get("name", "")
    make = find_suite(name)
    suite = None if make is None else _built(make)
    title = (experiment.get("study") or {}).get("title")
    if make is None and title:  # a suite's --show template saved under another name keeps its study's title
        # (and was reported as the study without a word on what was changed: newcomer, session 21)
        built = ((n, _built(SUITES.get(n))) for n in SUITES.names())
        name, suite = next(((n, data) for n, data in built if ((data or {}).get("study") or {}).get("title") == title),
                           ("", None))
    if suite is None:
        return ""
    try:
        documented = load_experiment(suite, f"suite '{name}'").to_dict()
    except (ExperimentError, OSError):  # (its data gone since: nothing to compare with)
        return ""
    changed = differences(_labelled(experiment), _labelled(documented),
                          ignored=("description", "name", "claims", "study"), labels=("here", "in the suite"))
    if not changed:
        return ""
    # (a suite with no document to compare with, such as smoke, claimed "the document's numbers below" for a
    # table it does not have: newcomer run, session 22)
    tail = " The document's numbers below go with the suite's settings." if (documented.get("study") or {}).get(
        "reference") else ""
    return f"This run is not the suite '{name}' as it stands: {'; '.join(changed)}.{tail}"


def _compared(verdict: Dict[str, Any]) -> str:
    """What a claim's row compared: its names, and the cells' labels where they say more (a claim's rows
    against several cells were all "astar < rrt_star": newcomer, session 23)."""
    low, high = verdict.get("group_lower") or verdict["lower"], verdict.get("group_higher") or verdict["higher"]
    if (low, high) == (verdict["lower"], verdict["higher"]):
        return f"{low} < {high}"
    return f"{verdict['lower']} < {verdict['higher']}: {low} < {high}"


def _built(make) -> Optional[Dict[str, Any]]:
    """The experiment the suite ``make`` builds, or None when it cannot be built here (a suite on the Moving AI
    maps without them: building it raised, after every trial, and no report was written; review, session 23)."""
    from ..errors import NavlabError

    try:
        return make()
    except (NavlabError, OSError):  # (ExperimentError is a NavlabError)
        return None


def _labelled(experiment: Dict[str, Any]) -> Dict[str, Any]:
    """``experiment`` with its planners and samplers as their labels followed by their own settings
    (``rrt_star``, ``astar (weight=2)``), not as the dictionaries
    :meth:`~navlab.bench.experiment.Experiment.to_dict` writes (a report line read
    ``planners [{'name': 'astar', 'params': {}, 'label': 'astar'}] here``)."""
    def readable(part):
        if not isinstance(part, dict):
            return part
        own = part.get("params") or {}
        settings = ", ".join(f"{key}={value}" for key, value in sorted(own.items()))
        label = part.get("label") or part.get("name")
        return f"{label} ({settings})" if settings else label

    out = dict(experiment)
    for key in ("planners", "samplers"):
        if isinstance(out.get(key), list):
            out[key] = [readable(part) for part in out[key]]
    return out


def build(experiment: Dict[str, Any], rows: List[Dict[str, Any]], summary: Dict[str, Any],
          images: Dict[str, List[str]], elapsed_s: Optional[float], meta: Dict[str, Any]) -> List[Block]:
    """The report's blocks. ``images[world]`` lists image files (relative
    paths); ``rows`` are the trials (without the noise repeats) with ``time``
    set (:func:`~navlab.bench.analysis.timed`)."""
    blocks: List[Block] = [("h1", f"navlab bench: {experiment['name']}")]
    study = experiment.get("study") or {}
    if study.get("title"):
        blocks.append(("p", f"Reproduces {study['title']}."))
        changed = _changed_from_suite(experiment)
        if changed:
            blocks.append(("p", changed))
    if study.get("measured"):
        blocks.append(("p", "What was measured there: " + study["measured"]))
    if experiment.get("description"):
        blocks.append(("p", experiment["description"]))
    n_err = sum(r.get("status") == "ERROR" for r in rows)
    budget = ", ".join(f"{k}={v}" for k, v in experiment.get("budget", {}).items()) or "planner defaults"
    cells = summary["cells"]
    per_cell = sorted({c["trials"] for c in cells})
    blocks.append(("p", f"{len(rows)} trials ({n_err} errors) in {len(cells)} cells, "
                        f"{'/'.join(map(str, per_cell)) or 0} per cell, base seed {experiment['seed']}, budget "
                        f"{budget}. navlab {meta.get('version')} on {meta.get('cpu')} ({meta.get('cores')} cores)"
                        + (f"; wall time {elapsed_s:.1f} s." if elapsed_s is not None else ".")))
    blocks.append(("p", f"Times are the {summary.get('time_label', 'thread CPU time')} of each trial "
                        f"(`--time {'wall' if summary.get('time') == 'wall' else 'cpu'}`; "
                        f"`--time {'cpu' if summary.get('time') == 'wall' else 'wall'}` for the other), measured "
                        f"after each worker warmed its kernels: {fmt(summary.get('warmup_s'), 1)} s of compilation "
                        "and cache loading in all, not counted in any trial."
                        + (f" {summary['torn_lines']} torn line(s) were cut from results.jsonl "
                           "(kept in results.torn.jsonl)." if summary.get("torn_lines") else "")))

    swept = summary.get("swept") or []
    blocks.append(("h2", "Summary per cell"))
    compared = summary.get("compared") or {}
    blocks.append(("p", "Cost and time over the trials that reached the goal (a failed trial has no path, "
                        "and its time is the time it took to give up); iterations over every trial that ran. "
                        "CI: 95% t-interval of the mean." + (_compared_text(compared) if compared else "")))
    header = (["world", "planner", "sampler"] + swept
              + ["success", "cost mean", "cost 95% CI", "cost median", "cost min", "cost max", "cost std",
                 "time mean [s]", "time median [s]", "first solution it. (median)"])
    table = []
    for c in cells:
        cost, t = c["cost"], c["time"]
        ran = c["trials"] - c["errors"]
        table.append([c["world"], c["planner"], c["sampler"]] + [fmt(c["swept"].get(k)) for k in swept]
                     + [f"{c['successes']}/{ran}" + (f" ({c['errors']} err)" if c["errors"] else ""),
                        _no_cost(c, c["world"] in compared) or fmt(cost["mean"]),
                        f"[{fmt(cost['ci95'][0])}, {fmt(cost['ci95'][1])}]",
                        fmt(cost["median"]), fmt(cost["min"]), fmt(cost["max"]), fmt(cost["std"]),
                        fmt(t["mean"], 4), fmt(t["median"], 4), fmt(c["first_solution_iteration"]["median"], 0)])
    blocks.append(("table", (header, table)))

    if any(c.get("params_used") for c in cells):
        blocks.append(("h2", "Parameters each cell used"))
        blocks.append(("p", "What the planner ran with, derived values included (a default that depends on the "
                            "world, such as expand_dis, is shown as computed); every row of results.jsonl holds "
                            "them under params_used, and results.csv as columns."))
        blocks.append(("table", (["world", "cell", "parameters"],
                                 [[c["world"], c["group"], ", ".join(f"{k}={fmt(v, 4)}"
                                                                     for k, v in sorted(c["params_used"].items()))]
                                  for c in cells])))

    if any(c.get("vs_optimum", {}).get("n") or c.get("vs_theta", {}).get("n") for c in cells):
        blocks.append(("h2", "Path length against the optimum and against Theta*"))
        blocks.append(("p", "Per map query: the path's length over the stored Moving AI optimum (8-connected "
                            "octile length, corners not cut: any-angle paths can be shorter, below 1) and over the "
                            "Theta* path's on the same query; over the successful trials, on the queries all "
                            "cells of the world solved as in the summary per cell."))
        blocks.append(("table", (["world", "cell", "success", "÷ optimum (median)", "÷ optimum (mean)",
                                  "÷ optimum (max)", "÷ Theta* (median)", "÷ Theta* (max)", "time median [s]"],
                                 [[c["world"], c["group"], f"{c['successes']}/{c['trials'] - c['errors']}",
                                   fmt(c["vs_optimum"]["median"], 4), fmt(c["vs_optimum"]["mean"], 4),
                                   fmt(c["vs_optimum"]["max"], 4), fmt(c["vs_theta"]["median"], 4),
                                   fmt(c["vs_theta"]["max"], 4), fmt(c["time"]["median"], 4)] for c in cells])))

    failed = [c for c in cells if c["successes"] < c["trials"]]
    if failed:
        blocks.append(("h2", "Trials that did not succeed"))
        blocks.append(("p", "Statuses per cell, and the most common reasons (an ERROR's reason is the last "
                            "line of its exception; results.jsonl holds the whole traceback)."))
        blocks.append(("table", (["world", "cell", "statuses", "most common reasons"],
                                 [[c["world"], c["group"], ", ".join(f"{k} {v}" for k, v in c["statuses"].items()),
                                   "; ".join(f"{reason} (×{n})" for reason, n in c["reasons"])] for c in failed])))

    ref = reference_table(study, summary)
    if ref:
        blocks.append(("h2", "The document's numbers beside ours"))
        blocks.append(("p", "The document's value (its mean unless stated) beside our mean and median over "
                            "the cell's solved trials (on maps, the queries all cells solved). The worlds are "
                            "navlab's reconstructions (the document gives their names and pictures, not their "
                            "geometry), so costs are comparable in "
                            "order of magnitude only; times are not comparable in size (different software "
                            "and machines), only in order. Where the document says two things (a reading), "
                            "the 'solved' rows say which one our run agrees with; a success rate agrees "
                            "within 0.1 of the document's."))
        blocks.append(("table", (["world", "cell", "reading", "metric", "document", "ours (mean)", "ours (median)",
                                  "agrees"],
                                 [[r[0], r[1], r[2] or "-", r[3], fmt(r[4]), fmt(r[5], 4), fmt(r[6], 4),
                                   r[7] or "-"] for r in ref])))

    verdicts = summary.get("claims") or []
    if verdicts:
        blocks.append(("h2", "The claims, tested"))
        blocks.append(("p", "Each claim per world, over the trials that reached the goal (on maps, the queries "
                            "both sides solved); a verdict needs at least " + str(MIN_SOLVED) + " solved trials on "
                            "each side, else it is 'not shown' with the counts. Mann–Whitney U (two-sided), "
                            "Holm-corrected over the claims tested in that world, α = 0.05; δ is Cliff's delta of "
                            "the first group against the second (negative: the first is lower). For times, "
                            + summary.get("rule", "") + "; the ratio is median (lower) / median (higher)."))
        blocks.append(("table", (["claim", "overall"], [[k, v] for k, v in overall_verdicts(verdicts).items()])))
        blocks.append(("table", (["world", "claim", "solved (lower, higher)", "verdict", "median (lower)",
                                  "median (higher)", "ratio", "needed (noise ε)", "δ", "p (Holm)"],
                                 [[v["world"], f"{v['claim']} ({_compared(v)})",
                                   ", ".join(v.get("solved") or []),
                                   v["verdict"] + (f" ({v['why']})" if v.get("why") and v["verdict"] == "not shown"
                                                   else ""),
                                   fmt(v["median_lower"], 4), fmt(v["median_higher"], 4), fmt(v.get("ratio"), 3),
                                   (f"×{v['threshold_ratio']:.2f} (ε {fmt(v.get('noise'), 3)})"
                                    if v.get("threshold_ratio") else "-"),
                                   f"{fmt(v['delta'], 2)} ({v['magnitude']})", fmt(v["p_holm"], 3)]
                                  for v in verdicts])))

    worlds = by_world(rows)
    for world, groups in worlds.items():
        blocks.append(("h2", f"World: {world}"))
        for image in images.get(world, []):
            blocks.append(("img", image))
        if world in compared:
            blocks.append(("p", f"Summary per cell and box plots: {scope_text(compared[world])}."))
        skipped = (summary.get("pairwise_skipped") or {}).get(world)
        if skipped:
            blocks.append(("p", f"{skipped} cells in this world: pairwise comparisons are made only up to "
                                f"{MAX_PAIRWISE_CELLS} cells ({MAX_PAIRWISE_CELLS * (MAX_PAIRWISE_CELLS - 1) // 2} "
                                "pairs); state the comparisons you care about as claims."))
        for metric in ("cost", "time"):
            comps = summary["comparisons"][world][metric]
            if not comps:
                continue
            blocks.append(("h3", f"Pairwise comparisons of {'path cost' if metric == 'cost' else 'time'}"))
            blocks.append(("table", (["A", "B", "solved A, B", "median A", "median B", "δ (A vs B)", "p",
                                      "p (Holm)", "verdict"],
                                     [[c["a"], c["b"], ", ".join(c.get("solved") or []),
                                       fmt(c["median_a"], 4), fmt(c["median_b"], 4),
                                       f"{fmt(c['delta'], 2)} ({c['magnitude']})", fmt(c["p"], 3),
                                       fmt(c["p_holm"], 3), _verdict(c)] for c in comps])))
        names = list(groups)
        for other in names[1:MAX_SIDE_BY_SIDE + 1]:  # the seed's layout: a handful of tables, not one per cell
            blocks.append(("h3", f"Per trial: {names[0]} beside {other} (the seed's layout"
                                 + ("; mean and min over the queries both solved)" if world in compared else ")")))
            body = side_by_side(groups, names[0], other)
            blocks.append(("table", (["trial", f"{names[0]} cost [m]", "time [s]", f"{other} cost [m]", "time [s]"],
                                     [[r[0]] + [fmt(v, 3 if i % 2 == 0 else 4) for i, v in enumerate(r[1:])]
                                      for r in body])))
    return blocks


def _compared_text(compared: Dict[str, Dict[str, int]]) -> str:
    """The summary's caption on a map experiment: which queries each world's
    cost and time are over (see :func:`~navlab.bench.analysis.compared_rows`)."""
    return (" On maps the trials run different queries (start and goal), so a world's cost, time and first "
            "solution statistics (and the ratios to the optimum and to Theta* below) are over the queries every "
            "cell of that world solved (a cell that solved nothing set aside): the same queries for every cell. "
            "The success column counts all trials. "
            + "; ".join(f"{world}: {scope_text(scope)}" for world, scope in compared.items()) + ".")


def _no_cost(c: Dict[str, Any], on_queries: bool) -> str:
    """Why a cell's cost mean is empty, or ''."""
    if not c["successes"]:
        return "no path in any trial"
    return "no query all cells solved" if on_queries and not c["cost"]["n"] else ""


def _verdict(c: Dict[str, Any]) -> str:
    if not c["significant"]:
        return "no difference shown" + (f" ({c['why']})" if c.get("why") else "")
    return f"{c['a'] if c['direction'] < 0 else c['b']} lower"


def to_markdown(blocks: Sequence[Block]) -> str:
    out = []
    for kind, value in blocks:
        if kind in ("h1", "h2", "h3"):
            out.append("#" * int(kind[1]) + " " + value)
        elif kind == "p":
            out.append(value)
        elif kind == "img":
            out.append(f"![{Path(value).stem}]({value})")
        elif kind == "table":
            header, body = value
            lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            lines += ["| " + " | ".join(str(c).replace("|", "\\|") for c in row) + " |" for row in body]
            out.append("\n".join(lines))
    return "\n\n".join(out) + "\n"


CSS = ("body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
       "table{border-collapse:collapse;margin:1em 0;font-size:13px}td,th{border:1px solid #ccc;padding:3px 7px;"
       "text-align:right}th{background:#f3f3f3}td:first-child,td:nth-child(2){text-align:left}"
       "img{max-width:100%;display:block;margin:1em 0}")


def to_html(blocks: Sequence[Block], folder: Path) -> str:
    """A single page: images are read from ``folder`` and embedded as data URIs."""
    title = next((v for k, v in blocks if k == "h1"), "navlab bench")
    out = ["<!DOCTYPE html>", "<html lang=\"en\"><head><meta charset=\"utf-8\">",
           f"<title>{html.escape(title)}</title><style>{CSS}</style></head><body>"]
    for kind, value in blocks:
        if kind in ("h1", "h2", "h3", "p"):
            out.append(f"<{kind}>{html.escape(value)}</{kind}>")
        elif kind == "img":
            data = base64.b64encode((folder / value).read_bytes()).decode("ascii")
            out.append(f"<img alt=\"{html.escape(Path(value).stem)}\" src=\"data:image/png;base64,{data}\">")
        elif kind == "table":
            header, body = value
            out.append("<table><thead><tr>" + "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
                       + "</tr></thead><tbody>")
            out += ["<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in body]
            out.append("</tbody></table>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"
