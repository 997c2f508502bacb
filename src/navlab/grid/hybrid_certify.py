"""Hybrid A*'s independent re-check of a path: the footprint polygon at every traced pose
against the blocked cells' squares, exactly, compiled.

The search's own checks read precomputed cell lists (:mod:`navlab.sampling.footprint_lattice`:
footprints grown by margins, quarter-turned, read through distance maps). This check shares
none of that, but it shares its per-pose test
(:func:`~navlab.world.footprint_collision.pose_grid_overlap`) with the search's exact re-check of
the poses those lists reject, at half that re-check's margin: a fault in that test would pass
both, which is why the tests hold it to shapely on its own as well as here. It places the outline
at each pose and tests it against every blocked cell (and
the ring of cells just outside the map) whose square can reach it, with the world's exact
polygon–rectangle and point–rectangle tests (:mod:`navlab.world.footprint_collision`, which the
simulator's footprint checks use: an edge of one meets an edge of the other, or one holds a
vertex of the other; touching counts). It answers as
:func:`~navlab.sampling.footprint_lattice.first_overlap` (shapely) does, which the tests check
it against, at about a hundredth of the cost on a small query (shapely builds a polygon per pose
and a box per cell).
"""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from ..jit import njit
from ..world.footprint_collision import pose_grid_overlap


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
    found, x, y = first_overlap_compiled(np.ascontiguousarray(blocked, dtype=np.bool_), float(res),
                                         np.ascontiguousarray(vertices, dtype=float).reshape(-1, 2), float(disc),
                                         np.ascontiguousarray(poses, dtype=float).reshape(-1, 3), float(grow))
    return (int(x), int(y)) if found else None


@njit(cache=True)
def first_overlap_compiled(blocked, res, vertices, disc, poses, grow):
    """:func:`first_overlap_exact`'s loop, callable from compiled code (the planner's final check): (found,
    x, y), the arrays as that function makes them."""
    outline = np.empty((vertices.shape[0], 2))
    box = np.empty((4, 2))  # polygon_rect_touch's scratch
    for p in range(poses.shape[0]):
        found, cx, cy = pose_grid_overlap(blocked, res, vertices, disc, poses[p, 0], poses[p, 1], poses[p, 2],
                                          grow, outline, box)
        if found:
            return True, cx, cy
    return False, 0, 0
