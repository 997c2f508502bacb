"""Checking grid planner settings before anything is built.

Settings arrive from Python calls, ``--param`` flags and experiment files,
so any YAML value can turn up (``heuristic: 0``, ``connectivity: [1]``,
``connectivity: .inf``, ``resolution: 1e-300``); each is checked here once,
with one message naming the setting, instead of failing later inside numpy
or ``int()``.
"""

from __future__ import annotations

import math
from typing import Any, Dict

from ..errors import ParameterError
from ..limits import MAX_COORDINATE, MIN_LENGTH, check_flag, check_weight, is_finite_real, shown


def _name(key: str, value: Any, valid) -> str:
    if not isinstance(value, str) or value not in valid:
        from ..registry import suggest

        raise ParameterError(f"{key} must be one of {', '.join(valid)}; got {value!r}.{suggest(value, valid)}"
                             .rstrip("."))
    return value


def _number(key: str, value: Any) -> float:
    if not is_finite_real(value):  # (Python's or numpy's: np.float32(0.1) was 'not a finite number')
        raise ParameterError(f"{key} must be a finite number, got {shown(value)}")
    return float(value)


def check_grid_settings(params: Dict[str, Any]) -> Dict[str, Any]:
    """``params`` with every grid setting it has checked (values unchanged
    but for integral floats of ``connectivity``); unknown keys pass through
    (the caller reports them). Raises ``ParameterError`` naming the setting."""
    from .planner import GRID_ALGORITHMS, HEURISTICS, check_connectivity, check_jps_connectivity

    out = dict(params)
    if "heuristic" in out:
        _name("heuristic", out["heuristic"], HEURISTICS.names())
    if "algorithm" in out:
        _name("algorithm", out["algorithm"], GRID_ALGORITHMS.names())
    if "connectivity" in out:
        out["connectivity"] = check_connectivity(out["connectivity"])
    check_jps_connectivity(out.get("algorithm", ""), out.get("connectivity", 8))
    for key in ("smooth", "allow_unknown"):
        if key in out:
            out[key] = check_flag(key, out[key])
    if "weight" in out:
        check_weight(out["weight"])  # (A*'s own rule: navlab.grid.plan and Hybrid A* take the same values)
    if "resolution" in out and out["resolution"] is not None:
        r = _number("resolution", out["resolution"])
        if not MIN_LENGTH <= r <= MAX_COORDINATE:
            raise ParameterError(f"resolution must be between {MIN_LENGTH:g} and {MAX_COORDINATE:g} m per cell, "
                                 f"got {out['resolution']!r}")
    if "smooth_method" in out:
        _name("smooth_method", out["smooth_method"], ["bresenham", "supercover"])
    return out
