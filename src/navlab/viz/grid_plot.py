"""Drawing occupancy grids and grid paths."""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from .plot import _pyplot, finish_figure


def draw_grid(ax, grid) -> None:
    """The occupancy grid in world coordinates (blocked black, unknown grey)."""
    res = grid.resolution
    x0, y0 = grid.origin[0], grid.origin[1]
    extent = (x0, x0 + grid.width * res, y0, y0 + grid.height * res)
    image = np.where(grid.blocked, 0.0, np.where(grid.unknown, 0.6, 1.0))
    ax.imshow(image, cmap="gray", vmin=0, vmax=1, origin="lower", extent=extent, interpolation="nearest")


def plot_grid_plan(grid, result, out: Optional[str] = None, raw_cells: Optional[np.ndarray] = None,
                   expanded: Optional[np.ndarray] = None, title: Optional[str] = None,
                   start: Optional[Sequence[float]] = None, goal: Optional[Sequence[float]] = None):
    """The grid (world frame), optional expanded cells, raw and smoothed paths.

    ``start`` and ``goal`` (metres) are drawn whether or not there is a path
    (default: the path's ends), so a failed plan still shows what was asked.
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    draw_grid(ax, grid)
    if expanded is not None and len(expanded):
        pts = grid.cell_to_world(expanded)
        ax.plot(pts[:, 0], pts[:, 1], ",", color="tab:cyan", alpha=0.5, label="expanded")
    if raw_cells is not None and len(raw_cells):
        raw = grid.cell_to_world(raw_cells)
        ax.plot(raw[:, 0], raw[:, 1], "-", color="tab:blue", lw=1.2, label="raw path")
    if len(result.path):
        ax.plot(result.path[:, 0], result.path[:, 1], "-", color="tab:orange", lw=2.2,
                label=f"path ({result.cost:.3f} m)")
        start = result.path[0] if start is None else start
        goal = result.path[-1] if goal is None else goal
    if start is not None:
        ax.plot(*np.asarray(start, float)[:2], "o", color="tab:green", ms=8, label="start")
    if goal is not None:
        ax.plot(*np.asarray(goal, float)[:2], "*", color="tab:red", ms=13, label="goal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title or f"{grid.name}: {result.params.get('algorithm')} — {result.status.name}")
    if ax.get_legend_handles_labels()[0]:  # no legend (and no matplotlib warning) when nothing is labelled
        ax.legend(loc="best", fontsize=8)
    return finish_figure(fig, out)
