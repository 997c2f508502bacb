"""Hybrid A*'s independent re-check of a path: the footprint polygon at every traced pose
against the blocked cells' squares, exactly, compiled.

The search's own checks read precomputed cell lists (:mod:`navlab.sampling.footprint_lattice`:
footprints grown by margins, quarter-turned, read through distance maps). This check shares
none of that: it places the outline at each pose and tests it against every blocked cell (and
the ring of cells just outside the map) whose square can reach it, with the world's exact
polygon–rectangle and point–rectangle tests (:mod:`navlab.world.footprint_collision`, which the
simulator's footprint checks use: an edge of one meets an edge of the other, or one holds a
vertex of the other; touching counts). It answers as
:func:`~navlab.sampling.footprint_lattice.first_overlap` (shapely) does, which the tests check
it against, at about a hundredth of the cost on a small query (shapely builds a polygon per pose
and a box per cell).
"""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np
from numba import njit

from ..world.footprint_collision import polygon_rect_touch
from ..world.geometry import point_rect_dist2

#: [cells] every cell's square is widened by this fraction of a cell on each side, so rounding in the
#: test can only report an overlap that is not there (within 1e-9 cells), never miss one
SLACK = 1e-9


def first_overlap_exact(blocked: np.ndarray, res: float, vertices: np.ndarray, disc: float, poses: np.ndarray,
                        grow: float) -> Optional[Tuple[int, int]]:
    """The first cell (x, y) the footprint at any of ``poses`` (grid frame, (N, 3)) overlaps with
    the blocked cells' squares grown by ``grow`` [m] on every side; None when it overlaps none.
    Outside the map counts, as the cell just beyond the edge; the first pose's lowest cell (row
    by row) is named, as :func:`~navlab.sampling.footprint_lattice.first_overlap` names it. A
    footprint wholly beyond that ring of cells names the ring cell nearest its pose.

    ``vertices`` (K, 2) the outline in body coordinates [m], or none and ``disc`` [m] a disc's
    radius (0: a point). A disc here is exact, where shapely's is a 64-gon inside it, so a disc
    is judged a little more strictly."""
    found, x, y = _first_overlap(np.ascontiguousarray(blocked, dtype=np.bool_), float(res),
                                 np.ascontiguousarray(vertices, dtype=float).reshape(-1, 2), float(disc),
                                 np.ascontiguousarray(poses, dtype=float).reshape(-1, 3), float(grow))
    return (int(x), int(y)) if found else None


@njit(cache=True)
def _first_overlap(blocked, res, vertices, disc, poses, grow):
    """:func:`first_overlap_exact`'s loop: (found, x, y)."""
    h, w = blocked.shape
    k = vertices.shape[0]
    outline = np.empty((k, 2))
    box = np.empty((4, 2))  # polygon_rect_touch's scratch
    slack = SLACK * res
    for p in range(poses.shape[0]):
        x, y = poses[p, 0], poses[p, 1]
        if k:
            c, s = math.cos(poses[p, 2]), math.sin(poses[p, 2])
            for i in range(k):
                outline[i, 0] = x + c * vertices[i, 0] - s * vertices[i, 1]
                outline[i, 1] = y + s * vertices[i, 0] + c * vertices[i, 1]
            x0, x1 = outline[:, 0].min(), outline[:, 0].max()
            y0, y1 = outline[:, 1].min(), outline[:, 1].max()
        else:
            x0, x1, y0, y1 = x - disc, x + disc, y - disc, y + disc
        # cell i's grown square [i·res − grow, (i+1)·res + grow] can meet [x0, x1] only for
        # (x0 − grow)/res − 1 ≤ i ≤ (x1 + grow)/res; one more cell each way, tested exactly, costs nothing
        lo_x = max(-1, int(math.floor((x0 - grow) / res)) - 1)
        hi_x = min(w, int(math.floor((x1 + grow) / res)) + 1)
        lo_y = max(-1, int(math.floor((y0 - grow) / res)) - 1)
        hi_y = min(h, int(math.floor((y1 + grow) / res)) + 1)
        for cy in range(lo_y, hi_y + 1):
            for cx in range(lo_x, hi_x + 1):
                if 0 <= cx < w and 0 <= cy < h and not blocked[cy, cx]:
                    continue
                bx0, by0 = cx * res - grow - slack, cy * res - grow - slack
                bx1, by1 = (cx + 1) * res + grow + slack, (cy + 1) * res + grow + slack
                if polygon_rect_touch(outline, bx0, by0, bx1, by1, box) if k else \
                        point_rect_dist2(x, y, bx0, by0, bx1, by1) <= disc * disc:
                    return True, cx, cy
        # none of the ring's squares met: the footprint leaves the map only by lying wholly beyond
        # them (the map is a rectangle, so the outline's extremes tell); name the nearest ring cell
        if x0 <= grow + slack or y0 <= grow + slack or x1 >= w * res - grow - slack or y1 >= h * res - grow - slack:
            return True, min(max(int(math.floor(x / res)), -1), w), min(max(int(math.floor(y / res)), -1), h)
    return False, 0, 0
