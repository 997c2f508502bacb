"""Benchmark figures: cost and time box plots, convergence curves and one
example tree per cell, each world on one figure. A group is a cell: planner,
sampler and swept values. Every figure is saved through
:func:`.save.save_figure` (whole or not at all)."""

from __future__ import annotations

from typing import Any, Dict, List, Sequence, Tuple

import numpy as np

from .plot import _pyplot, draw_path, draw_tree, draw_world
from .legend import place_legend
from .save import save_figure

Rows = List[Dict[str, Any]]
#: PNG compression: level 1 writes several times faster than the default and
#: the files stay small (flat colours)
PNG = {"compress_level": 1}


def _save(fig, out: str, dpi: int) -> None:
    save_figure(fig, out, dpi=dpi, pil_kwargs=PNG)


def box_plots(world: str, groups: Dict[str, Rows], out: str, compared: Dict[str, Rows], scope: str,
              time_label: str = "time [s]") -> None:
    """Cost and time (``row["time"]``, else the planner's ``time_s``) per group,
    over ``compared[group]``: the rows the verdicts compare
    (:func:`navlab.bench.analysis.compared_rows`: each group's solved trials,
    on map experiments only the queries every cell solved), which ``scope``
    says in the title (:func:`navlab.bench.analysis.scope_text`). Each box is labelled with its group's
    solved/ran count over all its trials, and a group that solved nothing is
    marked "no path in any trial" where its box would stand."""
    plt = _pyplot()
    names = list(groups)
    time_key = "time" if any("time" in r for g in groups.values() for r in g) else "time_s"
    fig, axes = plt.subplots(1, 2, figsize=(4 + 1.3 * len(names), 4.4))
    solved = [sum(bool(r.get("success")) for r in groups[g]) for g in names]
    ran = [sum(r.get("status") != "ERROR" for r in groups[g]) for g in names]
    labels = [f"{n.replace(' / ', chr(10))}\nsolved {k}/{m}" for n, k, m in zip(names, solved, ran)]
    for ax, metric, unit in ((axes[0], "cost", "path cost [m]"), (axes[1], time_key, time_label)):
        data = [[r[metric] for r in compared[g] if r.get(metric) is not None and r.get("success")] for g in names]
        ax.boxplot([d if d else [np.nan] for d in data], showmeans=True)
        ax.set_xticks(range(1, len(names) + 1), labels, fontsize=8)
        ax.set_ylabel(unit)
        ax.set_xlabel("cell (solved trials only)")
        ax.grid(axis="y", alpha=0.3)
        for i, (d, k) in enumerate(zip(data, solved)):
            if not d:  # say so where the box would be, rather than leave a silent gap
                ax.text(i + 1, 0.5, "no query all\ncells solved" if k else "no path in\nany trial",
                        transform=ax.get_xaxis_transform(), ha="center", va="center", fontsize=8, color="#b00",
                        rotation=90)
    fig.suptitle(f"{world}: {scope}")
    # fixed margins: tight_layout costs more than drawing the figure
    fig.subplots_adjust(left=0.08, right=0.98, bottom=0.27, top=0.9, wspace=0.25)
    _save(fig, out, 100)
    plt.close(fig)


def convergence(groups: Dict[str, Rows]) -> Dict[str, Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Per group: iterations, and the 25th, 50th and 75th percentile of the
    best cost so far over trials (a trial without a solution yet counts as
    infinitely long, so the median appears once half the trials have one)."""
    out = {}
    for name, rows in groups.items():
        traces = [r["trace"] for r in rows if r.get("trace")]
        if not traces:
            continue
        its = np.asarray(traces[0]["iteration"], dtype=float)
        same = [t for t in traces if t["iteration"] == traces[0]["iteration"]]
        costs = np.array([[np.inf if c is None else c for c in t["cost"]] for t in same])
        # No interpolation: between a cost and inf it would give nan.
        q25, q50, q75 = np.percentile(costs, [25, 50, 75], axis=0, method="higher")
        out[name] = (its, q25, q50, q75)
    return out


def convergence_plot(world: str, groups: Dict[str, Rows], out: str) -> bool:
    curves = convergence(groups)
    if not curves:
        return False
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for name, (its, q25, q50, q75) in curves.items():
        shown = np.isfinite(q50)
        if not shown.any():
            continue
        line, = ax.plot(its[shown], q50[shown], label=name, lw=1.6)
        band = np.isfinite(q75)
        if band.any():  # an empty band would spoil the axis limits
            ax.fill_between(its[band], q25[band], q75[band], color=line.get_color(), alpha=0.18, lw=0)
    ax.set_xscale("log")
    ax.set_xlabel("iteration")
    ax.set_ylabel("best path cost [m] (median, 25–75% band)")
    ax.set_title(f"{world}: convergence")
    ax.grid(alpha=0.3)
    fig.subplots_adjust(left=0.1, right=0.97, bottom=0.12, top=0.92)
    place_legend(ax)  # a corner clear of the curves, else outside
    _save(fig, out, 100)
    plt.close(fig)
    return True


def example_trees(world, examples: Sequence[Tuple[str, Dict[str, np.ndarray]]], out: str) -> None:
    """One panel per (title, tree): ``tree`` holds ``nodes``, ``parent`` and
    ``path``, drawn over the world."""
    plt = _pyplot()
    n = len(examples)
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 4.4 * rows), squeeze=False)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    for ax, (title, tree) in zip(axes.ravel(), examples):
        draw_world(ax, world, show_inflation=False)
        draw_tree(ax, np.asarray(tree["nodes"]), np.asarray(tree["parent"]), label=None)
        path = np.asarray(tree["path"], dtype=float)  # (N, 2) points or (N, 3) poses
        draw_path(ax, path.reshape(len(path), -1) if path.size else path.reshape(0, 2), label="path")
        ax.set_title(title, fontsize=9)
        ax.tick_params(labelsize=7)
        ax.xaxis.label.set_size(8)  # draw_world labels the axes in metres
        ax.yaxis.label.set_size(8)
    fig.subplots_adjust(left=0.06, right=0.99, bottom=0.08, top=0.93, wspace=0.2, hspace=0.3)
    _save(fig, out, 90)
    plt.close(fig)
