"""The result every navlab planner returns (OMPL's PlannerStatus, as data)."""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any, Dict, Iterator, Optional

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


@dataclass(frozen=True, eq=False)
class Tree:
    """What a planner searched, kept for drawing (``Result.tree``).

    Tree planners (RRT family) fill ``nodes`` and ``parent``; grid planners
    fill ``raw_cells`` when they smoothed the path, and planners that
    rasterised a geometric world keep that ``raster``. Unused fields are
    ``None``.

    Attributes
    ----------
    nodes : ndarray (N, 2) or None
        Tree node positions, metres; (N, 3) poses (x, y, θ) for a tree planned between poses.
    parent : ndarray (N,) of int or None
        Each node's parent index, −1 for the root.
    raw_cells : ndarray (M, 2) of int or None
        A grid path's cells (x, y) before smoothing.
    raster : OccupancyGrid or None
        The grid a grid planner searched when the source was a geometric world.

    Notes
    -----
    Mapping access (``tree["nodes"]``, ``"nodes" in tree``, ``tree.get(...)``)
    is kept for code written when ``Result.tree`` was a dict; a field that is
    ``None`` is absent there.

    Examples
    --------
    >>> t = Tree(nodes=np.array([[0.0, 0.0], [1.0, 0.0]]), parent=np.array([-1, 0]))
    >>> t.edges().tolist()
    [[[0.0, 0.0], [1.0, 0.0]]]
    >>> len(t), "raw_cells" in t
    (2, False)
    """

    nodes: Optional[np.ndarray] = None
    parent: Optional[np.ndarray] = None
    raw_cells: Optional[np.ndarray] = None
    raster: Optional[Any] = None

    def __len__(self) -> int:
        """Number of tree nodes (0 for a grid planner's tree)."""
        return 0 if self.nodes is None else len(self.nodes)

    def __bool__(self) -> bool:
        """True when the tree holds anything (as the dict it replaces)."""
        return bool(self._present())

    def edges(self) -> np.ndarray:
        """Every parent–child edge as a segment: (E, 2, 2) of ((x0, y0), (x1, y1)), metres."""
        if self.nodes is None or self.parent is None:
            return np.empty((0, 2, 2))
        nodes, parent = np.asarray(self.nodes, float), np.asarray(self.parent)
        child = parent >= 0
        return np.stack((nodes[parent[child]], nodes[child]), axis=1)

    def with_raster(self, raster: Any) -> "Tree":
        """The same tree remembering the grid it was searched on."""
        return Tree(self.nodes, self.parent, self.raw_cells, raster)

    # -- mapping access (Result.tree was a dict) --------------------------------
    def _present(self) -> Dict[str, Any]:
        return {k: v for k, v in (("nodes", self.nodes), ("parent", self.parent),
                                  ("raw_cells", self.raw_cells), ("raster", self.raster)) if v is not None}

    def __getitem__(self, key: str) -> Any:
        try:
            return self._present()[key]
        except KeyError:
            raise KeyError(f"this tree has no {key!r} (it has: {', '.join(self._present()) or 'nothing'})") from None

    def __contains__(self, key: object) -> bool:
        return key in self._present()

    def __iter__(self) -> Iterator[str]:
        return iter(self._present())

    def get(self, key: str, default: Any = None) -> Any:
        return self._present().get(key, default)

    def keys(self):
        return self._present().keys()


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
    tree : Tree or None
        What the planner searched (tree nodes and parents, a grid path before
        smoothing), when kept for drawing: see :class:`Tree`.
    world : World or None
        What was planned in, when :func:`navlab.plan` made the result (so that
        ``navlab.viz.plot_plan(result)`` can draw it); not part of ``to_dict``.
    """

    status: Status
    path: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))
    cost: float = float("inf")
    stats: Dict[str, Any] = field(default_factory=dict)
    reason: str = ""
    tree: Optional[Tree] = None
    params: Dict[str, Any] = field(default_factory=dict)
    cells: Optional[np.ndarray] = None  #: grid planners: (N, 2) int cells (x, y)
    #: SE(2) planners: (N,) +1 where the robot arrives at the waypoint driving forward, −1 in reverse
    #: (their ``path`` is (N, 3) poses x, y, θ)
    direction: Optional[np.ndarray] = None
    world: Any = field(default=None, repr=False, compare=False)

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
