"""Distances to a path, for tracking errors and replanning."""

from __future__ import annotations

import numpy as np


def distance_to_polyline(points: np.ndarray, path: np.ndarray) -> np.ndarray:
    """Distance of each point to the nearest segment of a polyline."""
    a, d = path[:-1], np.diff(path, axis=0)
    rel = points[:, None, :] - a[None, :, :]
    length2 = np.maximum((d * d).sum(axis=1), 1e-300)
    u = np.clip((rel * d[None]).sum(axis=2) / length2, 0.0, 1.0)
    gap = rel - u[..., None] * d[None]
    return np.sqrt((gap * gap).sum(axis=2).min(axis=1))
