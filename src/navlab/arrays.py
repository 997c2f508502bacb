"""Arrays that grow by copying into a larger one (tree nodes, simulation logs):
memory follows what was actually produced, not the largest it could be."""

from __future__ import annotations

from typing import Any

import numpy as np


def grown(array: np.ndarray, rows: int, fill: Any = 0) -> np.ndarray:
    """``array`` copied into the first rows of a new array of ``rows`` rows
    (same dtype and row shape), the rest set to ``fill``."""
    out = np.full((rows,) + array.shape[1:], fill, dtype=array.dtype)
    out[: len(array)] = array
    return out
