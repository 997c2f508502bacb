"""What the ROS 2 nodes decide, without ROS: planning on request and driving
a controller from odometry. The nodes only translate messages and log.

Keeping the decisions here lets them be tested directly (every bad input the
nodes must survive) and keeps rclpy out of everything but the node shells.
Each class reports through ``log(level, text)`` with level one of
``"info"``, ``"warn"``, ``"error"``.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Dict, Optional, Tuple

import numpy as np

from ..control.base import REACHED, STALLED, Controller
from ..errors import ParameterError
from ..grid.occupancy import OccupancyGrid
from ..limits import check_flag
from ..planning import is_grid_planner, plan
from ..pose_queries import POSE_PLANNERS, is_pose_query
from ..result import Result
from ..world.world import World

Log = Callable[[str, str], None]
Twist = Tuple[float, float, float]
STOP: Twist = (0.0, 0.0, 0.0)


def _xy(p) -> str:
    """(x, y), or (x, y, θ rad) for a pose."""
    return f"({p[0]:.3f}, {p[1]:.3f}" + (f", {p[2]:.3f} rad)" if len(p) > 2 else ")")


def finite(values, what: str, log: Log) -> bool:
    """Whether every value is finite; if not, an error naming ``what``."""
    if np.all(np.isfinite(np.asarray(values, float))):
        return True
    log("error", f"ignoring {what} with non-finite values: not a finite position")
    return False


#: node-level defaults of the grid searches that differ from navlab.grid's
#: (seed 002's planner shortcuts its path along lines of sight)
GRID_DEFAULTS = {"smooth": True}


def plan_on_map(grid: OccupancyGrid, start, goal, algorithm: str, sampler: str, seed: int,
                robot_radius: float, allow_unknown: bool, params: Dict[str, Any]) -> Result:
    """:func:`navlab.plan` on a map: the occupied (and, unless
    ``allow_unknown``, unknown) cells are the obstacles, kept
    ``robot_radius`` away from the path. ``sampler`` goes to the tree
    planners only."""
    world = World.from_grid(grid, start, goal, robot_radius=robot_radius, allow_unknown=allow_unknown)
    extra = {"sampler": None} if algorithm in POSE_PLANNERS or is_grid_planner(algorithm) else {"sampler": sampler}
    return plan(world, planner=algorithm, seed=seed, **extra, **params)


#: what the node does instead of each of navlab.plan's own arguments, which a planner setting must not be
#: named after (a test holds this to plan's signature: 'source' was missed once)
_NOT_SETTINGS = {"source": "the node plans on /map", "planner": "the node's parameter is 'algorithm'",
                 "sampler": "the node's parameter is 'sampler'", "seed": "the node's parameter is 'seed'",
                 "start": "the start is the latest /odom pose", "goal": "goals come on /goal_pose",
                 "robot_radius": "the node's parameter is 'inflation_radius' (robot radius + margin)"}


class GoalPlanner:
    """Plans a path from the latest pose to each goal on the latest map, with
    any registered planner: the grid searches (seed 002's A*, Dijkstra, JPS,
    Theta*) or the RRT family with any sampler (seeds 000, 001, 003).

    A goal that arrives before the map or the first pose is kept and planned
    as soon as both are known. A goal outside the map, in an obstacle or
    closer to one than ``inflation_radius`` gives an error and no path.
    Planning goes through :func:`navlab.plan` on
    :meth:`navlab.World.from_grid` of the received map.

    Parameters
    ----------
    log : callable
    algorithm : str
        Any registered planner (``navlab list``).
    sampler : str
        For the tree planners (a grid search takes only ``uniform``, the default).
    seed : int
        Every plan draws from a fresh generator with this seed: the same map,
        pose and goal give the same path.
    inflation_radius : float
        The clearance kept from obstacles (m): the robot's radius plus a
        margin for tracking.
    allow_unknown : bool
        Plan through cells of unknown occupancy.
    on_tree : callable, optional
        Called with ``(nodes, parent)`` after every plan of a tree planner
        (also a failed one): the search tree, for drawing.
    **params
        The planner's and sampler's settings, routed by name as in
        :func:`navlab.plan` (``max_iter``, ``expand_dis``, ``heuristic``,
        ``connectivity``, ...).

    Raises
    ------
    ParameterError
        An unknown algorithm, sampler or parameter (with a "did you mean"),
        or a bad value: found by planning once on a small empty map, which
        also compiles the planner's kernels before the first goal.
    """

    def __init__(self, log: Log, algorithm: str = "astar", sampler: str = "uniform", seed: int = 0,
                 inflation_radius: float = 0.175, allow_unknown: bool = False,
                 on_tree: Optional[Callable[[np.ndarray, np.ndarray], None]] = None, **params: Any) -> None:
        if not (inflation_radius >= 0 and math.isfinite(inflation_radius)):
            raise ParameterError(f"inflation_radius must be a non-negative number of metres, got {inflation_radius!r}")
        reserved = sorted(set(params) & set(_NOT_SETTINGS))  # (plan() got "multiple values": attack, session 21)
        if reserved:
            raise ParameterError(f"parameter '{reserved[0]}' is not a planner setting: {_NOT_SETTINGS[reserved[0]]}")
        hybrid = algorithm in POSE_PLANNERS
        self.tree_planner = not hybrid and not is_grid_planner(algorithm)  # unknown names: "did you mean"
        #: plans between poses (hybrid_astar, or a tree planner with motion dubins / reeds_shepp): the goal's and
        #: the odometry's headings are kept and the path's poses carry the planned headings
        self.poses = is_pose_query(algorithm, params)
        if hybrid:
            if sampler != "uniform":
                raise ParameterError(f"sampler '{sampler}' is for the tree planners; '{algorithm}' is a grid search")
        elif not self.tree_planner:
            if sampler != "uniform":
                raise ParameterError(f"sampler '{sampler}' is for the tree planners; '{algorithm}' is a grid search")
            params = {**GRID_DEFAULTS, **params}
        elif on_tree is not None:
            # the tree it publishes is the one the planner keeps: a keep_tree of the user's is checked, and false
            # is refused (it was overwritten with true, and keep_tree:=1 or [1] passed unchecked: attack, s. 25)
            if "keep_tree" in params and not check_flag("keep_tree", params["keep_tree"]):
                raise ParameterError("keep_tree:=false: this node publishes the search tree on /plan_tree, which "
                                     "needs it kept; give publish_tree:=false with it")
            params["keep_tree"] = True
        self.log, self.on_tree = log, on_tree
        self.query = dict(algorithm=algorithm, sampler=sampler, seed=seed, allow_unknown=allow_unknown,
                          params=params)
        self.inflation_radius = float(inflation_radius)
        self.grid: Optional[OccupancyGrid] = None
        self.inflated: Optional[OccupancyGrid] = None
        self.pose: Optional[np.ndarray] = None
        self.pending: Optional[np.ndarray] = None
        self._check_settings()

    def _check_settings(self) -> None:
        """Plan once on a 2 m × 2 m empty map: bad names and values raise
        here, at start-up, and the kernels are compiled before the first goal."""
        q = dict(self.query)
        params = dict(q.pop("params"))
        limit = params.get("max_iter")
        if self.tree_planner and not self.poses and (limit is None or (type(limit) is int and limit > 64)):
            params["max_iter"] = 64  # a short run (a bad value stays, for the planner to refuse)
        empty = OccupancyGrid(np.zeros((20, 20), bool), 0.1, (0.0, 0.0, 0.0))
        try:
            plan_on_map(empty, (0.5, 0.5), (1.5, 1.5), robot_radius=0.0, params=params, **q)
        except (TypeError, OverflowError) as exc:  # a parameter of the wrong kind (ROS parameters are typed loosely)
            raise ParameterError(f"bad setting for {q['algorithm']}: {exc}") from None

    def set_map(self, grid: OccupancyGrid) -> Optional[np.ndarray]:
        self.grid, self.inflated = grid, grid.inflate(self.inflation_radius)
        self.log("info", f"map {grid.width}x{grid.height} cells at {grid.resolution:g} m")
        return self._plan_pending()

    def set_pose(self, pose) -> Optional[np.ndarray]:
        if not finite(pose, "a pose", self.log):
            return None
        self.pose = np.asarray(pose, float)[:3 if self.poses else 2]
        return self._plan_pending()

    def set_goal(self, goal) -> Optional[np.ndarray]:
        """Plan to ``goal`` — (x, y), or (x, y, θ) whose heading a pose planner keeps."""
        goal = np.asarray(goal, float)[:3 if self.poses else 2]
        if not finite(goal, "a goal", self.log):
            return None
        if self.grid is None or self.pose is None:
            self.pending = goal
            missing = "a map" if self.grid is None else "the robot's pose on /odom"
            self.log("info", f"goal {_xy(goal)} kept until {missing} arrives")
            return None
        self.pending = None
        return self.plan(self.pose, goal)

    def _plan_pending(self) -> Optional[np.ndarray]:
        if self.pending is None or self.grid is None or self.pose is None:
            return None
        goal, self.pending = self.pending, None
        self.log("info", f"planning the kept goal {_xy(goal)}")
        return self.plan(self.pose, goal)

    def _where_blocked(self, p) -> Optional[str]:
        """Why the robot cannot stand at p, or None."""
        grid = self.grid
        cell = grid.world_to_cell(np.asarray(p, float)[None, :2])[0]
        if not grid.contains(cell)[0]:
            ox, oy = grid.origin[:2]
            return (f"is outside the map ({grid.width * grid.resolution:g} x {grid.height * grid.resolution:g} m "
                    f"from ({ox:g}, {oy:g}))")
        x, y = int(cell[0]), int(cell[1])
        if grid.blocked[y, x]:
            return "is in an obstacle"
        if grid.unknown[y, x] and not self.query["allow_unknown"]:
            return "is in unknown space (set allow_unknown to plan through it)"
        if self.inflated.blocked[y, x] and not self.poses:  # a pose planner checks the footprint itself
            return f"is closer to an obstacle than the inflation radius {self.inflation_radius:g} m"
        return None

    def plan(self, start, goal) -> Optional[np.ndarray]:
        """The path from start to goal as (N, 2) world points — (N, 3) poses for a pose
        planner — or None (logged)."""
        for label, p in (("start", start), ("goal", goal)):
            why = self._where_blocked(p)
            if why is not None:
                self.log("error", f"no path: the {label} {_xy(p)} {why}")
                return None
        start, goal = tuple(map(float, start)), tuple(map(float, goal))
        try:
            result = plan_on_map(self.grid, start, goal, robot_radius=self.inflation_radius, **self.query)
        except (ValueError, TypeError, OverflowError, MemoryError) as exc:  # a setting this map cannot take
            self.log("error", f"no path from {_xy(start)} to {_xy(goal)}: {type(exc).__name__}: {exc}")
            return None
        if self.on_tree is not None and self.tree_planner and result.tree is not None:
            self.on_tree(result.tree["nodes"], result.tree["parent"])
        what = self.query["algorithm"]
        if not result.success:
            self.log("error", f"no path from {_xy(start)} to {_xy(goal)} ({what}): {result.status.name} {result.reason}")
            return None
        path = np.array(result.path, float)
        length = float(np.sum(np.linalg.norm(np.diff(path[:, :2], axis=0), axis=1)))
        self.log("info", f"path from {_xy(start)} to {_xy(goal)} ({what}): {len(path)} poses, "
                         f"{length:.2f} m, {result.stats['time_s'] * 1000:.1f} ms")
        return path


class Drive:
    """Runs a controller on the odometry stream until its goal is reached.

    It commands nothing until given a target; it returns a stop when the
    controller reports the goal reached or a stall, and when odometry has
    been silent for ``odom_timeout`` seconds (then again on every watchdog
    tick until odometry returns, in case a stop is lost).
    """

    def __init__(self, controller: Controller, log: Log, odom_timeout: float = 0.5) -> None:
        if not (odom_timeout > 0 and math.isfinite(odom_timeout)):
            raise ParameterError(f"odom_timeout must be a positive number of seconds, got {odom_timeout!r}")
        self.controller, self.log, self.odom_timeout = controller, log, float(odom_timeout)
        self.active = False
        self.last_odom: Optional[float] = None
        self.odom_lost = False

    def set_target(self, goal, path=None) -> Optional[Twist]:
        """Start driving to ``goal`` (along ``path`` for path followers). An
        empty path stops the robot."""
        if not finite(goal if path is None else path, "a goal" if path is None else "a path", self.log):
            return None
        if path is not None and len(path) == 0:
            was_active, self.active = self.active, False
            self.log("warn", "empty path: stopping")
            return STOP if was_active else None
        self.controller.reset(goal, path)
        self.active = True
        what = f"a {len(path)}-pose path" if path is not None else "the goal"
        self.log("info", f"following {what} to {_xy(goal)}")
        return None

    def heard(self, now: float) -> None:
        """Note that odometry arrived at monotonic time ``now`` (for the watchdog) without
        commanding anything: for a node that runs its controller at a lower rate than /odom."""
        self.last_odom = now
        if self.odom_lost:
            self.odom_lost = False
            self.log("info", "odometry is back")

    def on_odom(self, t: float, pose, now: float, points=None) -> Optional[Twist]:
        """The command for a new pose (None when idle). ``t`` is the pose's
        time stamp (for stall detection), ``now`` a monotonic clock."""
        self.heard(now)
        if not self.active:
            return None
        command = self.controller.command(t, pose, points)
        if command.status == REACHED:
            self.active = False
            self.log("info", f"goal reached at {_xy(pose)}")
            return STOP
        if command.status == STALLED:
            self.active = False
            self.log("warn", f"no progress towards the goal from {_xy(pose)}: stopping")
            return STOP
        return (command.vx, command.vy, command.omega)

    def hold(self, now: float) -> Optional[Twist]:
        """A new pose arrived but the controller cannot run (a sensor it
        needs is missing): stand still while driving."""
        self.heard(now)
        return STOP if self.active else None

    def watchdog(self, now: float) -> Optional[Twist]:
        """A stop while odometry is overdue during a drive."""
        if not self.active or self.last_odom is None or now - self.last_odom <= self.odom_timeout:
            return None
        if not self.odom_lost:
            self.odom_lost = True
            self.log("warn", f"no odometry for {now - self.last_odom:.2f} s (timeout {self.odom_timeout:g} s): "
                             "stopping the robot")
        return STOP
