"""Drawing occupancy grids and grid paths."""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from .plot import cell_image, finish_plot, new_axes


def draw_grid(ax, grid) -> None:
    """The occupancy grid in world coordinates (blocked black, unknown grey),
    axes labelled in metres, equal aspect.

    A grid with more cells across than the axes have pixels is drawn in
    blocks of k × k cells, each as dark as its darkest cell, so a wall one
    cell thin stays visible (:func:`~navlab.viz.plot.cell_image`; a 3002²
    maze's walls showed as stripes, and its float image took 72 MB)."""
    res = grid.resolution
    x0, y0 = grid.origin[0], grid.origin[1]
    image, k = cell_image(ax, grid, free=255, unknown=153, blocked=0)
    h, w = image.shape  # (blocks of k cells: up to k - 1 cells past the map's far edges, cut off below)
    ax.imshow(image, cmap="gray", vmin=0, vmax=255, origin="lower", extent=(x0, x0 + w * k * res, y0,
                                                                             y0 + h * k * res),
              interpolation="nearest")
    ax.set_xlim(x0, x0 + grid.width * res)
    ax.set_ylim(y0, y0 + grid.height * res)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def plot_grid_plan(grid, result, out: Optional[str] = None, raw_cells: Optional[np.ndarray] = None,
                   expanded: Optional[np.ndarray] = None, title: Optional[str] = None,
                   start: Optional[Sequence[float]] = None, goal: Optional[Sequence[float]] = None, ax=None):
    """The grid (world frame), optional expanded cells, raw and smoothed paths.

    ``start`` and ``goal`` (metres) are drawn whether or not there is a path
    (default: the path's ends), so a failed plan still shows what was asked.
    ``raw_cells`` defaults to the path before smoothing (``result.tree.raw_cells``).
    With ``ax``, draws into those axes and returns them; otherwise returns a
    new figure (closed once written to ``out``), as :func:`navlab.viz.plot_plan`.
    """
    fig, ax, owned = new_axes(ax)
    if raw_cells is None and result.tree is not None:
        raw_cells = result.tree.get("raw_cells")
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
    ax.set_title(title or f"{grid.name}: {result.params.get('algorithm')} — {result.status.name}")
    return finish_plot(fig, ax, owned, out)
