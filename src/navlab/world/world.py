"""The planning problem in a continuous 2D workspace."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Optional, Tuple

import numpy as np

from .shapes import Obstacle, _point

if TYPE_CHECKING:  # the grid package imports nothing from world; keep it that way at run time
    from ..grid.occupancy import OccupancyGrid


@dataclass(frozen=True)
class Bounds:
    """Axis-aligned workspace (and sampling) bounds in metres."""

    xmin: float
    xmax: float
    ymin: float
    ymax: float

    def __post_init__(self) -> None:
        vals = (self.xmin, self.xmax, self.ymin, self.ymax)
        if not all(math.isfinite(v) for v in vals):
            raise ValueError(f"bounds must be finite, got {vals}")
        if not (self.xmax > self.xmin and self.ymax > self.ymin):
            raise ValueError(f"bounds need max > min in x and y, got x=[{self.xmin}, {self.xmax}] y=[{self.ymin}, {self.ymax}]")

    @property
    def low(self) -> np.ndarray:
        return np.array([self.xmin, self.ymin])

    @property
    def high(self) -> np.ndarray:
        return np.array([self.xmax, self.ymax])

    @property
    def diagonal(self) -> float:
        """Length of the bounds' diagonal (OMPL's "maximum extent")."""
        return math.hypot(self.xmax - self.xmin, self.ymax - self.ymin)

    @property
    def area(self) -> float:
        return (self.xmax - self.xmin) * (self.ymax - self.ymin)

    def contains(self, points: np.ndarray) -> np.ndarray:
        p = np.atleast_2d(points)
        return (p[:, 0] >= self.xmin) & (p[:, 0] <= self.xmax) & (p[:, 1] >= self.ymin) & (p[:, 1] <= self.ymax)

    def as_array(self) -> np.ndarray:
        return np.array([self.xmin, self.xmax, self.ymin, self.ymax], dtype=float)


@dataclass(frozen=True)
class World:
    """A 2D planning problem: bounds, start, goal, robot radius and obstacles.

    Obstacles are inflated by ``robot_radius`` for every collision query, so a
    planner can treat the robot as a point.

    A world may also carry an ``occupancy`` grid (a ROS or Moving AI map): its
    occupied cells (and its unknown cells unless ``allow_unknown``) are square
    obstacles for the same checker, so every planner sees shapes and maps
    through one interface. ``bounds`` is then the map's extent
    (:meth:`from_grid` fills it in).
    """

    name: str
    bounds: Bounds
    start: Tuple[float, float]
    goal: Tuple[float, float]
    obstacles: Tuple[Obstacle, ...] = ()
    robot_radius: float = 0.0
    goal_tolerance: float = 0.0
    meta: Dict[str, Any] = field(default_factory=dict, compare=False)
    occupancy: Optional["OccupancyGrid"] = None
    allow_unknown: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", _point(self.start, "start"))
        object.__setattr__(self, "goal", _point(self.goal, "goal"))
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        for what in ("robot_radius", "goal_tolerance"):
            value = getattr(self, what)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"{what} must be a non-negative number of metres, got {value!r}")
            object.__setattr__(self, what, float(value))

    @classmethod
    def from_grid(cls, grid: "OccupancyGrid", start, goal, robot_radius: float = 0.0,
                  goal_tolerance: float = 0.0, allow_unknown: bool = False, name: Optional[str] = None) -> "World":
        """A world whose obstacles are the occupied cells of ``grid``; bounds are its extent.

        Parameters
        ----------
        grid : OccupancyGrid
        start, goal : (x, y)
            In metres, in the map frame.
        robot_radius, goal_tolerance : float
            Metres.
        allow_unknown : bool
            Treat unknown cells as free (default: as occupied).
        """
        ox, oy, yaw = grid.origin
        c, s = math.cos(yaw), math.sin(yaw)
        # the map's four outer corners, rotated about the origin by the map's yaw
        local = np.array([[0.0, 0.0], [grid.width, 0.0], [0.0, grid.height], [grid.width, grid.height]]) * grid.resolution
        corners = local @ np.array([[c, s], [-s, c]]) + (ox, oy)
        bounds = Bounds(float(corners[:, 0].min()), float(corners[:, 0].max()),
                        float(corners[:, 1].min()), float(corners[:, 1].max()))
        return cls(name=name or grid.name, bounds=bounds, start=start, goal=goal, robot_radius=robot_radius,
                   goal_tolerance=goal_tolerance, occupancy=grid, allow_unknown=allow_unknown)

    def checker(self):
        """A fresh :class:`~navlab.world.collision.CollisionChecker` (its own counters)."""
        from .collision import CollisionChecker

        return CollisionChecker(self)

    def with_query(self, start=None, goal=None) -> "World":
        """The same world with another start and/or goal."""
        from dataclasses import replace

        return replace(self, start=self.start if start is None else start,
                       goal=self.goal if goal is None else goal)

    def to_dict(self) -> Dict[str, Any]:
        """The YAML world-file form (see :func:`navlab.world.io.load_world`)."""
        return {
            "name": self.name,
            "bounds": {"x": [self.bounds.xmin, self.bounds.xmax], "y": [self.bounds.ymin, self.bounds.ymax]},
            "start": list(self.start),
            "goal": list(self.goal),
            "robot_radius": self.robot_radius,
            "goal_tolerance": self.goal_tolerance,
            "obstacles": [o.to_dict() for o in self.obstacles],
        }
