"""The planning problem in a continuous 2D workspace."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Dict, Optional, Tuple

import numpy as np

from ..angles import planned_heading
from ..errors import ParameterError
from ..limits import check_coordinate, check_flag, check_length, plain_values
from .footprint import Footprint
from .shapes import Circle, Obstacle, Polygon, Rectangle

if TYPE_CHECKING:  # the grid package imports nothing from world; keep it that way at run time
    from ..grid.occupancy import OccupancyGrid


def _query_point(value: Any, what: str) -> Tuple[Tuple[float, float], Optional[float]]:
    """``value`` as an (x, y) pair of supported coordinates and the heading
    θ [rad] when it is a pose (x, y, θ) (else None); ParameterError naming ``what``."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") or len(value) not in (2, 3):
        raise ParameterError(f"{what} must be [x, y] in metres or a pose [x, y, theta] (rad), got {value!r}")
    point = (check_coordinate(f"{what} x", plain_values(value[0])), check_coordinate(f"{what} y", plain_values(value[1])))
    return point, (_heading(f"{what} theta", value[2]) if len(value) == 3 else None)


def _heading(what: str, value: Any) -> float:
    """A finite heading in radians, wrapped to [-π, π] (exactly: a heading already there is kept bit for bit);
    one beyond ±2π warns (``navlab.angles.HeadingWarning``: most often degrees)."""
    return planned_heading(what, value)


def _check_obstacle(k: int, obstacle: Any) -> None:
    """Every coordinate of an obstacle within the supported range (circle radii too)."""
    if not isinstance(obstacle, (Circle, Rectangle, Polygon)):
        raise ParameterError(f"obstacles[{k}] must be a Circle, Rectangle or Polygon, got {type(obstacle).__name__}")
    for v in obstacle.bbox():
        check_coordinate(f"obstacles[{k}] coordinate", float(v))
    if isinstance(obstacle, Circle):
        check_length(f"obstacles[{k}] radius", obstacle.radius, allow_zero=False)


@dataclass(frozen=True)
class Bounds:
    """Axis-aligned workspace (and sampling) bounds in metres."""

    xmin: float
    xmax: float
    ymin: float
    ymax: float

    def __post_init__(self) -> None:
        for what in ("xmin", "xmax", "ymin", "ymax"):
            object.__setattr__(self, what, check_coordinate(f"bounds.{what}", plain_values(getattr(self, what))))
        if not (self.xmax > self.xmin and self.ymax > self.ymin):
            raise ParameterError(f"bounds need max > min in x and y, got x=[{self.xmin}, {self.xmax}] y=[{self.ymin}, {self.ymax}]")

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

    def text(self) -> str:
        """``x=[0, 18] y=[0, 12]``: the bounds as the messages that name them write them."""
        return f"x=[{self.xmin:g}, {self.xmax:g}] y=[{self.ymin:g}, {self.ymax:g}]"


@dataclass(frozen=True)
class World:
    """A 2D planning problem: bounds, start, goal, robot radius and obstacles.

    Obstacles are inflated by ``robot_radius`` for every collision query, so a
    planner can treat the robot as a point.

    ``start`` and ``goal`` may be given as poses ``(x, y, θ)``: the point is
    kept in ``start``/``goal`` and the heading in ``start_heading`` /
    ``goal_heading`` (None: any heading; the heading-aware planners then take
    the direction from start to goal). ``footprint`` is the robot's outline
    for those planners (None: a disc of ``robot_radius``).

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
    start_heading: Optional[float] = None
    goal_heading: Optional[float] = None
    footprint: Optional[Footprint] = None

    def __post_init__(self) -> None:
        # Everything is checked against navlab.limits here, so the compiled
        # kernels never see a non-finite or overflowing number.
        if not isinstance(self.bounds, Bounds):
            raise ParameterError(f"bounds must be a Bounds, got {type(self.bounds).__name__}")
        for what in ("start", "goal"):
            point, heading = _query_point(getattr(self, what), what)
            object.__setattr__(self, what, point)
            if heading is not None:  # a pose given as start/goal wins over a separate heading
                object.__setattr__(self, f"{what}_heading", heading)
            elif getattr(self, f"{what}_heading") is not None:
                object.__setattr__(self, f"{what}_heading", _heading(f"{what}_heading", getattr(self, f"{what}_heading")))
        if self.footprint is not None and not isinstance(self.footprint, Footprint):
            object.__setattr__(self, "footprint", Footprint.from_value(self.footprint))
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        for k, obstacle in enumerate(self.obstacles):
            _check_obstacle(k, obstacle)
        for what in ("robot_radius", "goal_tolerance"):
            object.__setattr__(self, what, check_length(what, plain_values(getattr(self, what))))
        object.__setattr__(self, "allow_unknown", check_flag("allow_unknown", self.allow_unknown))
        if self.occupancy is not None:
            for what in ("blocked", "resolution", "origin"):
                if not hasattr(self.occupancy, what):
                    raise ParameterError(f"occupancy must be an OccupancyGrid, got {type(self.occupancy).__name__}")

    @classmethod
    def from_grid(cls, grid: "OccupancyGrid", start, goal, robot_radius: float = 0.0,
                  goal_tolerance: float = 0.0, allow_unknown: bool = False, name: Optional[str] = None,
                  where: Optional[str] = None) -> "World":
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
        where : str, optional
            How to name the map when its extent passes navlab's coordinate range (its file; default
            ``grid 'NAME'``): the error said only "bounds.xmax ... is out of range".
        """
        ox, oy, yaw = grid.origin
        c, s = math.cos(yaw), math.sin(yaw)
        # the map's four outer corners, rotated about the origin by the map's yaw
        local = np.array([[0.0, 0.0], [grid.width, 0.0], [0.0, grid.height], [grid.width, grid.height]]) * grid.resolution
        corners = local @ np.array([[c, s], [-s, c]]) + (ox, oy)
        try:
            bounds = Bounds(float(corners[:, 0].min()), float(corners[:, 0].max()),
                            float(corners[:, 1].min()), float(corners[:, 1].max()))
        except ParameterError as exc:
            raise ParameterError(f"{where or f'grid {grid.name!r}'}: {exc}") from None
        return cls(name=name or grid.name, bounds=bounds, start=start, goal=goal, robot_radius=robot_radius,
                   goal_tolerance=goal_tolerance, occupancy=grid, allow_unknown=allow_unknown)

    def checker(self):
        """A fresh :class:`~navlab.world.collision.CollisionChecker` (its own counters)."""
        from .collision import CollisionChecker

        return CollisionChecker(self)

    def describe_obstacle(self, index: int) -> str:
        """``obstacle 12 (circle 'unit_cylinder_12')``: its index, kind and, from SDF worlds, its model name."""
        shape = self.obstacles[index]
        names = self.meta.get("obstacle_names") if isinstance(self.meta, dict) else None
        name = f" {names[index]!r}" if names and index < len(names) else ""
        moving = "moving " if shape.motion is not None else ""
        return f"{moving}obstacle {index} ({type(shape).__name__.lower()}{name})"

    def with_query(self, start=None, goal=None) -> "World":
        """The same world with another start and/or goal."""
        from dataclasses import replace

        changes: Dict[str, Any] = {}
        for what, value in (("start", start), ("goal", goal)):
            # a new point drops the old heading unless it is a pose itself; the same point keeps it
            if value is not None and tuple(value) != tuple(getattr(self, what)):  # (3, 9) == (3.0, 9.0)
                changes[what], changes[f"{what}_heading"] = value, None
        return replace(self, **changes)

    def to_dict(self) -> Dict[str, Any]:
        """The YAML world-file form (see :func:`navlab.world.io.load_world`)."""
        return {
            "name": self.name,
            "bounds": {"x": [self.bounds.xmin, self.bounds.xmax], "y": [self.bounds.ymin, self.bounds.ymax]},
            "start": list(self.start) + ([self.start_heading] if self.start_heading is not None else []),
            "goal": list(self.goal) + ([self.goal_heading] if self.goal_heading is not None else []),
            "robot_radius": self.robot_radius,
            "goal_tolerance": self.goal_tolerance,
            "obstacles": [o.to_dict() for o in self.obstacles],
            **({"footprint": self.footprint.to_value()} if self.footprint is not None else {}),
            **({"turning_radius": self.meta["turning_radius"]}
               if isinstance(self.meta, dict) and self.meta.get("turning_radius") is not None else {}),
        }
