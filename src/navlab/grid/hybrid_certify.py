"""Hybrid A*'s independent re-check of a path: the footprint polygon at every traced pose
against the blocked cells' squares, exactly, compiled.

The search's own checks read precomputed cell lists (:mod:`navlab.sampling.footprint_lattice`:
footprints grown by margins, quarter-turned, read through distance maps). This check shares
none of that: it places the outline at each pose and tests it against every blocked cell (and
the ring of cells just outside the map) whose square can reach it, with the exact
polygon–rectangle intersection test (an edge crosses the rectangle — Liang and Barsky's
clipping, "A new concept and method for line clipping", ACM TOG 3(1), 1984 — or the rectangle
lies inside the polygon, by the even–odd rule). It answers as
:func:`~navlab.sampling.footprint_lattice.first_overlap` (shapely) does, touching counting,
which the tests check it against, at about a hundredth of the cost on a small query
(shapely builds a polygon per pose and a box per cell).
"""

from __future__ import annotations

import math
from typing import Optional, Tuple

import numpy as np
from numba import njit

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
    wx, wy = np.empty(k), np.empty(k)
    slack = SLACK * res
    for p in range(poses.shape[0]):
        x, y = poses[p, 0], poses[p, 1]
        if k:
            c, s = math.cos(poses[p, 2]), math.sin(poses[p, 2])
            for i in range(k):
                wx[i] = x + c * vertices[i, 0] - s * vertices[i, 1]
                wy[i] = y + s * vertices[i, 0] + c * vertices[i, 1]
            x0, x1, y0, y1 = wx.min(), wx.max(), wy.min(), wy.max()
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
                if k:
                    hit = _polygon_meets_box(wx, wy, bx0, by0, bx1, by1)
                else:
                    ex = max(bx0 - x, 0.0, x - bx1)  # the centre's distance from the square, per axis
                    ey = max(by0 - y, 0.0, y - by1)
                    hit = ex * ex + ey * ey <= disc * disc
                if hit:
                    return True, cx, cy
        # none of the ring's squares met: the footprint leaves the map only by lying wholly beyond
        # them (the map is a rectangle, so the outline's extremes tell); name the nearest ring cell
        if x0 <= grow + slack or y0 <= grow + slack or x1 >= w * res - grow - slack or y1 >= h * res - grow - slack:
            return True, min(max(int(math.floor(x / res)), -1), w), min(max(int(math.floor(y / res)), -1), h)
    return False, 0, 0


@njit(cache=True)
def _polygon_meets_box(wx, wy, bx0, by0, bx1, by1) -> bool:
    """Whether the polygon (vertices ``wx``, ``wy``) and the closed rectangle meet: an edge meets the
    rectangle, or else (the boundaries apart) the rectangle lies inside the polygon, which its centre tells."""
    k = wx.shape[0]
    for i in range(k):
        j = i + 1 if i + 1 < k else 0
        if _segment_meets_box(wx[i], wy[i], wx[j], wy[j], bx0, by0, bx1, by1):
            return True
    return _inside(wx, wy, 0.5 * (bx0 + bx1), 0.5 * (by0 + by1))


@njit(cache=True)
def _segment_meets_box(ax, ay, bx, by, bx0, by0, bx1, by1) -> bool:
    """Liang–Barsky: whether the segment a–b meets the closed rectangle [bx0, bx1] × [by0, by1]."""
    dx, dy = bx - ax, by - ay
    t0, t1 = 0.0, 1.0
    for side in range(4):
        if side == 0:
            p, q = -dx, ax - bx0
        elif side == 1:
            p, q = dx, bx1 - ax
        elif side == 2:
            p, q = -dy, ay - by0
        else:
            p, q = dy, by1 - ay
        if p == 0.0:
            if q < 0.0:  # parallel to this side and outside it
                return False
        elif p < 0.0:
            t0 = max(t0, q / p)
        else:
            t1 = min(t1, q / p)
        if t0 > t1:
            return False
    return True


@njit(cache=True)
def _inside(wx, wy, px, py) -> bool:
    """Even–odd rule: whether (px, py) lies inside the polygon."""
    inside = False
    k = wx.shape[0]
    for i in range(k):
        j = i - 1 if i > 0 else k - 1
        if (wy[i] > py) != (wy[j] > py) and px < wx[i] + (py - wy[i]) * (wx[j] - wx[i]) / (wy[j] - wy[i]):
            inside = not inside
    return inside
