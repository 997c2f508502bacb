"""What the ``local_planner`` node decides, without ROS: a costmap controller
(``dwa``, ``dwa_barn``, ``mppi``, ``rpp``) fed a Nav2-style layered costmap
built from ``/map`` (and ``/scan``), following ``/plan`` from ``/odom``.

The costmap and the controller's global path are kept exactly as ``navlab
sim`` keeps them (:class:`~navlab.sim.costmap_feed.CostmapFeed`): the static
layer from the map, the obstacle layer from the scans when the controller's
``layers`` asks for it (then the path is planned again on that costmap every
``replan_interval``), inflated for the robot's footprint. Driving, the
odometry watchdog and the reached / stalled reports are
:class:`~navlab.ros.core.Drive`'s, as in the other driving nodes.
"""

from __future__ import annotations

import math
from typing import Any, List, Optional

import numpy as np

from ..control.base import CONTROLLERS, make_controller
from ..errors import ParameterError
from ..grid.occupancy import OccupancyGrid
from ..registry import parameters_of
from ..sim.costmap_feed import CostmapFeed
from ..world.footprint import Footprint
from .core import Drive, Log, Twist

#: [m] the warm-up map's side (start-up: settings checked, kernels compiled)
WARM_UP_SIDE = 4.0


def costmap_controllers() -> List[str]:
    """The registered controllers that plan on a costmap (dwa, dwa_barn, mppi, rpp)."""
    return [name for name in CONTROLLERS.names() if getattr(CONTROLLERS.get(name), "needs_costmap", False)]


def densify(path: np.ndarray, step: float) -> np.ndarray:
    """``path`` (N, 2) with points added along each segment, at most ``step`` apart: the same polyline.

    Nav2's planners publish a pose per costmap cell and its controllers look along the path from
    the vertex nearest the robot (RPP's carrot, MPPI's path critics); navlab's pathplanner publishes
    only the vertices of its line-of-sight path, whose nearest vertex can lie metres behind the robot
    on a long segment (the carrot then points back and the robot turns round on the spot)."""
    path = np.asarray(path, float).reshape(-1, 2)
    if len(path) < 2:
        return path
    seg = np.diff(path, axis=0)
    pieces = np.maximum(np.ceil(np.hypot(*seg.T) / step), 1).astype(np.int64)
    u = np.concatenate([np.arange(n) / n for n in pieces])
    start = np.repeat(path[:-1], pieces, axis=0)
    return np.vstack((start + u[:, None] * np.repeat(seg, pieces, axis=0), path[-1:]))


def parse_footprint(footprint: str, robot_radius: float) -> Footprint:
    """The robot's footprint: ``footprint`` as Nav2 writes it (``"[[x, y], ...]"``, body frame, m), or,
    when empty, a disc of ``robot_radius`` (Nav2's ``robot_radius``)."""
    if footprint.strip():
        return Footprint.from_value(footprint, "footprint")
    return Footprint.from_value(robot_radius, "robot_radius")


class CostmapDrive:
    """Runs a costmap controller on a map, a global path, odometry and (for a
    sensor layer) scans; see the module.

    Parameters
    ----------
    log : callable
        ``log(level, text)``.
    controller : str
        ``dwa``, ``dwa_barn``, ``mppi`` or ``rpp``.
    footprint : str
        ``"[[x, y], ...]"`` in the body frame (m); empty: a disc of ``robot_radius``.
    robot_radius : float
        [m]
    controller_frequency : float
        [Hz] control cycles per second of odometry time (stamps): Nav2's
        ``controller_frequency``. A controller with a setting of that name
        (DWA's window, RPP's acceleration step) gets the same value.
    odom_timeout : float
        [s] monotonic: the robot is stopped when odometry is silent this long.
    scan_timeout : float
        [s] monotonic: with a sensor layer the robot stands still when the
        latest scan is older than this.
    costmap_interval : float
        [s] of odometry time between :meth:`costmap_due` answers with a sensor
        layer (0: the costmap is given only when a map arrives).
    seed : int
        The sampling controllers' (MPPI's) generator: the same inputs give the same commands.
    **settings
        The controller's settings by name (``inflation_radius``,
        ``cost_scaling_factor``, ``layers``, ``xy_goal_tolerance``,
        ``desired_linear_vel``, ...).

    Raises
    ------
    ParameterError
        An unknown or non-costmap controller, an unknown setting (with a "did
        you mean"), a bad value or footprint, an inflation radius below the
        footprint's inscribed radius: found by building the costmap of a small
        empty map and running one cycle on it, which also compiles the
        controller's kernels before the first path.
    """

    def __init__(self, log: Log, controller: str = "rpp", footprint: str = "", robot_radius: float = 0.105,
                 controller_frequency: float = 20.0, odom_timeout: float = 0.5, scan_timeout: float = 0.5,
                 costmap_interval: float = 1.0, seed: int = 0, **settings: Any) -> None:
        valid = costmap_controllers()
        if controller not in valid:
            factory = CONTROLLERS.get(controller)  # an unknown name: "did you mean"
            raise ParameterError(f"controller '{controller}' reads no costmap ({factory.__name__}); "
                                 f"the local planner runs {', '.join(valid)}")
        for name, value in (("controller_frequency", controller_frequency), ("scan_timeout", scan_timeout)):
            if not (value > 0 and math.isfinite(value)):
                raise ParameterError(f"{name} must be a positive number, got {value!r}")
        if not (costmap_interval >= 0 and math.isfinite(costmap_interval)):
            raise ParameterError(f"costmap_interval must be a number ≥ 0, got {costmap_interval!r}")
        if "controller_frequency" in parameters_of(CONTROLLERS.get(controller)):
            settings["controller_frequency"] = float(controller_frequency)
        self.footprint = parse_footprint(footprint, robot_radius)
        try:
            self.controller = make_controller(controller, **settings)
        except (TypeError, OverflowError) as exc:  # a value of the wrong kind (ROS parameters are typed loosely)
            raise ParameterError(f"bad setting for {controller}: {exc}") from None
        self.name = controller
        self.log = log
        self.drive = Drive(self.controller, log, odom_timeout)
        self.period = 1.0 / float(controller_frequency)
        self.scan_timeout, self.costmap_interval = float(scan_timeout), float(costmap_interval)
        self.feed: Optional[CostmapFeed] = None
        self.points: Optional[np.ndarray] = None
        self.scan_time = -math.inf
        self.next_cycle = -math.inf
        self.last_costmap = -math.inf
        self.cycles = 0
        #: [m] the followed path has a point at least this often (the costmap's cell, as Nav2's planners)
        self.path_step = float(self.controller.costmap_resolution)
        self._waiting: Optional[str] = None  # what the robot is waiting for (logged once)
        self._warm_up()
        if hasattr(self.controller, "seed"):
            self.controller.seed(np.random.default_rng(seed))

    @property
    def needs_scan(self) -> bool:
        return bool(self.controller.needs_scan)

    def _warm_up(self) -> None:
        """One cycle on an empty map: bad settings raise here, at start-up, and the
        kernels are compiled before the first path."""
        cells = int(round(WARM_UP_SIDE / 0.05))
        empty = OccupancyGrid(np.zeros((cells, cells), bool), 0.05, (0.0, 0.0, 0.0))
        start, goal = (1.0, 2.0, 0.0), (3.0, 2.0)
        try:
            feed = CostmapFeed(empty, self.footprint, self.controller, goal)
            self.controller.reset(goal, np.array((start[:2], goal)))
            points = np.zeros((0, 2)) if self.needs_scan else None
            feed.update(0.0, start, points)
            self.controller.command(0.0, start, points)
        except (TypeError, OverflowError) as exc:
            raise ParameterError(f"bad setting for {self.name}: {exc}") from None

    # -- inputs ---------------------------------------------------------------
    def set_map(self, grid: OccupancyGrid):
        """A new map: the costmap is built again on it. Returns the costmap (to
        publish), or None when the map cannot carry one (logged; the previous
        map stays in use)."""
        goal = self.controller.goal
        try:
            feed = CostmapFeed(grid, self.footprint, self.controller, goal)
            costmap = feed.layers.static_costmap()
        except ValueError as exc:
            self.log("error", f"ignoring the map: {exc}")
            return None
        self.feed = feed
        self.path_step = float(costmap.resolution)
        h, w = costmap.shape
        self.log("info", f"costmap {w}x{h} cells at {costmap.resolution:g} m, layers {self.controller.layers}, "
                         f"inflation {self.controller.costmap_settings['inflation_radius']:g} m, footprint "
                         f"{self.footprint.describe()}")
        self.last_costmap = -math.inf
        return costmap

    def set_plan(self, path) -> Optional[Twist]:
        """Follow ``path`` (N, 2) to its last point from now on (an empty path stops the robot); it is
        followed with a point every ``path_step`` (:func:`densify`)."""
        path = np.asarray(path, float).reshape(-1, 2)
        if len(path) > 1 and np.all(np.isfinite(path)):
            path = densify(path, self.path_step)
        twist = self.drive.set_target(path[-1] if len(path) else None, path)
        if self.drive.active:
            if self.feed is not None:
                self.feed.goal = np.array(self.controller.goal, float)
            self.next_cycle = -math.inf
            self._waiting = None
        return twist

    def set_scan(self, points, now: float) -> None:
        """The latest scan as world points (N, 2), received at ``now`` (monotonic)."""
        self.points, self.scan_time = np.asarray(points, float).reshape(-1, 2), now

    def _wait(self, what: str, level: str, now: float) -> Optional[Twist]:
        if self._waiting != what:
            self._waiting = what
            self.log(level, f"not moving: {what}")
        return self.drive.hold(now)

    def on_odom(self, t: float, pose, now: float) -> Optional[Twist]:
        """The command for a new pose at stamp ``t`` (None: nothing to send). A
        control cycle runs once per ``1 / controller_frequency`` of stamps; the
        poses between only keep the odometry watchdog fed."""
        if not self.drive.active:
            return self.drive.on_odom(t, pose, now)
        if self.feed is None:
            return self._wait("a path but no /map yet (the costmap is built on it)", "info", now)
        points = None
        if self.needs_scan:
            if self.points is None:
                return self._wait(f"waiting for the first /scan (layers: {self.controller.layers})", "info", now)
            if now - self.scan_time > self.scan_timeout:
                return self._wait(f"no /scan in the last {self.scan_timeout:g} s (layers: {self.controller.layers})",
                                  "warn", now)
            points = self.points
        if self._waiting is not None:
            self.log("info", "resuming")
            self._waiting = None
        last = self.next_cycle - self.period
        if last <= t < self.next_cycle - 1e-9:
            self.drive.heard(now)  # between cycles: only the watchdog hears it
            return None
        # on the period's grid; after a gap, or stamps that went back (a restarted sim), from this stamp
        self.next_cycle = self.next_cycle + self.period if last <= t < self.next_cycle + self.period \
            else t + self.period
        self.cycles += 1
        self.feed.update(t, pose, points)
        return self.drive.on_odom(t, pose, now, points)

    def watchdog(self, now: float) -> Optional[Twist]:
        return self.drive.watchdog(now)

    def costmap_due(self, t: float):
        """The costmap the controller planned on last, when a sensor layer changes it and the
        last one given is ``costmap_interval`` old (else None)."""
        if self.feed is None or not self.feed.sensing or self.costmap_interval <= 0 \
                or self.controller.costmap is None or t - self.last_costmap < self.costmap_interval:
            return None
        self.last_costmap = t
        return self.controller.costmap
