"""Legends that never cover what a figure shows.

:func:`place_legend` puts the legend in the corner of the axes that covers
none of the drawn data — line vertices, tree edges, markers, obstacle
outlines — and outside the axes, on the right, when every corner would
cover something (or when the axes show a map image, which fills them).
"""

from __future__ import annotations

from typing import List

import numpy as np

CORNERS = ("upper left", "upper right", "lower left", "lower right")
#: ``gid`` of a world's bounds frame: the legend may sit over it (it is not data)
FRAME = "navlab-frame"


def _data_points(ax) -> np.ndarray:
    """Display coordinates of everything drawn on ``ax`` (vertices, segment
    ends and midpoints, patch outlines), as (N, 2)."""
    pts: List[np.ndarray] = []
    for line in ax.get_lines():
        if line.get_gid() == FRAME:
            continue
        xy = np.asarray(line.get_xydata(), dtype=float)
        if len(xy):
            pts.append(line.get_transform().transform(_densify(xy)))
    for collection in ax.collections:
        segments = getattr(collection, "get_segments", lambda: [])()
        for seg in segments:
            seg = np.asarray(seg, dtype=float)
            if len(seg):
                pts.append(collection.get_transform().transform(_densify(seg)))
        offsets = np.asarray(collection.get_offsets(), dtype=float)
        if not len(segments) and offsets.size:
            pts.append(collection.get_offset_transform().transform(offsets))
    for patch in ax.patches:
        verts = patch.get_path().vertices
        if len(verts):
            pts.append(patch.get_transform().transform(_densify(np.asarray(verts, float))))
    pts = [p[np.all(np.isfinite(p), axis=1)] for p in pts]
    return np.vstack(pts) if pts else np.empty((0, 2))


def _densify(xy: np.ndarray, per_segment: int = 8) -> np.ndarray:
    """Points along a polyline (a long edge crossing a corner counts there too)."""
    if len(xy) < 2:
        return xy
    t = np.linspace(0.0, 1.0, per_segment, endpoint=False)[None, :, None]
    inner = xy[:-1, None, :] + t * (xy[1:, None, :] - xy[:-1, None, :])
    return np.vstack((inner.reshape(-1, 2), xy[-1:]))


def place_legend(ax, fontsize: float = 8, **kwargs):
    """Add ``ax``'s legend where it covers no data; returns it (None when
    nothing is labelled).

    The corners are tried in the order of :data:`CORNERS`; the first whose
    legend box contains none of the drawn points wins. Otherwise, or on an
    image (a map fills the axes), the legend goes outside the axes on the
    right (``savefig(..., bbox_inches="tight")`` keeps it in the file).
    """
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    figure = ax.figure
    if not ax.images:
        ax.get_xlim(), ax.get_ylim()  # settle autoscaled limits and the
        ax.apply_aspect()             # equal-aspect box before measuring
        renderer = figure.canvas.get_renderer()
        points = _data_points(ax)
        for corner in CORNERS:
            legend = ax.legend(loc=corner, fontsize=fontsize, **kwargs)
            box = legend.get_window_extent(renderer).padded(2)
            inside = ((points[:, 0] >= box.x0) & (points[:, 0] <= box.x1)
                      & (points[:, 1] >= box.y0) & (points[:, 1] <= box.y1))
            if not inside.any():
                return legend
            legend.remove()
    return ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, fontsize=fontsize, **kwargs)
