"""The result every navlab planner returns (OMPL's PlannerStatus, as data)."""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any, Dict, Optional

import numpy as np


class Status(enum.Enum):
    """Outcome of a planning query; failure is a status, never ``None``."""

    EXACT = "exact"  #: the path reaches the goal (region)
    APPROXIMATE = "approximate"  #: the path ends at the node closest to the goal
    FAILED = "failed"  #: no path at all
    INVALID_START = "invalid_start"
    INVALID_GOAL = "invalid_goal"

    @property
    def success(self) -> bool:
        return self is Status.EXACT


@dataclass
class Result:
    """What a planner returns.

    Attributes
    ----------
    status : Status
    path : ndarray, shape (N, 2)
        Waypoints from start to goal in metres (empty when there is none).
    cost : float
        Path length in metres (``inf`` when there is no path).
    stats : dict
        Counters and timings (iterations, nodes, collision_checks, time_s, ...).
    reason : str
        Human-readable explanation for non-EXACT statuses.
    tree : optional
        The search tree (``nodes``, ``parent`` arrays) when asked for drawing.
    """

    status: Status
    path: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))
    cost: float = float("inf")
    stats: Dict[str, Any] = field(default_factory=dict)
    reason: str = ""
    tree: Optional[Any] = None
    params: Dict[str, Any] = field(default_factory=dict)
    cells: Optional[np.ndarray] = None  #: grid planners: (N, 2) int cells (x, y)
    #: SE(2) planners: (N,) +1 where the robot arrives at the waypoint driving forward, −1 in reverse
    #: (their ``path`` is (N, 3) poses x, y, θ)
    direction: Optional[np.ndarray] = None

    @property
    def success(self) -> bool:
        return self.status.success

    def to_dict(self) -> Dict[str, Any]:
        """JSON-ready view (numpy arrays become lists, ``inf`` becomes ``None``)."""
        stats = {k: _jsonable(v) for k, v in self.stats.items()}
        out = {
            "status": self.status.name,
            "reason": self.reason,
            "cost": _jsonable(self.cost),
            "path": self.path.tolist(),
            "stats": stats,
            "params": {k: _jsonable(v) for k, v in self.params.items()},
        }
        if self.cells is not None:
            out["cells"] = self.cells.tolist()
        if self.direction is not None:
            out["direction"] = self.direction.tolist()
        return out


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (np.floating, float)):
        v = float(value)
        return v if np.isfinite(v) else None
    if isinstance(value, np.integer):
        return int(value)
    return value
