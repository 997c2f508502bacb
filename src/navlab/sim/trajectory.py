"""A run's true trajectory as a CSV table (``navlab sim --trajectory``)."""

from __future__ import annotations

import io

import numpy as np

from ..atomic import write_text_atomic


def trajectory_csv(result) -> str:
    """``t,x,y,theta`` (s, m, m, rad), one row per recorded step, the start first."""
    table = np.column_stack((result.t, result.true_poses))
    out = io.StringIO()
    out.write("t,x,y,theta\n")
    np.savetxt(out, table, delimiter=",", fmt="%.9g")
    return out.getvalue()


def write_trajectory_csv(result, path) -> None:
    """Write :func:`trajectory_csv` to ``path`` atomically (a killed run leaves no half file)."""
    write_text_atomic(path, trajectory_csv(result))
