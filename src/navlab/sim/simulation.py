"""A fixed-step simulator of a wheeled robot with encoders, compass, LiDAR
and a controller (the Gazebo stand-in).

Each step: the LiDAR scans the world from the true pose; the compass reads
the true heading; odometry integrates the encoder ticks; the controller sees
the odometry pose and the LiDAR points placed around it; its twist is
limited, turned into wheel speeds, perturbed by the motors (encoder noise)
and slip, and the true pose moves exactly along the resulting arc. The disc
footprint is checked over the whole motion of each step.
"""

from __future__ import annotations

import enum
import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional

import numpy as np

from ..arrays import grown
from ..control.base import REACHED, STALLED, Controller
from ..errors import ParameterError
from ..limits import MAX_COORDINATE, check_flag, float_array, is_finite_real, shown
from ..robots.proprioception import Compass, WheelEncoders
from ..sensors.lidar import Lidar
from ..sensors.timing import DelayLine, SensorTiming
from .plant import Plant
from .polyline import distance_to_polyline
from .scene import Scene

#: simulation steps the logs hold at first (they double as the run goes on)
INITIAL_LOG_ROWS = 4096
#: [s] the smallest time step (a tenth of a millisecond: far below any robot's control period)
MIN_DT = 1e-4
#: [s] the largest time step. The motion within a step is integrated exactly, but the controller
#: acts once a step: at 2 s a robot at 0.5 m/s drives a metre blind, past goals and gaps, and a
#: sensor at 10 Hz (the LiDAR's default) would be read once in twenty scans. 0.2 s (5 Hz control)
#: is the slowest rate at which the followers and the potential field still stop inside their goal
#: radius on the built-in scenes.
MAX_DT = 0.2
#: [m] the run is REACHED only when the *true* pose ends this close to the goal (the controller
#: judges its own, odometry, estimate): beyond it the status is OFF_GOAL
GOAL_TOLERANCE = 0.3
#: [rad] a goal with a heading is REACHED only with the true heading this close to it (Nav2's
#: ``yaw_goal_tolerance`` default)
GOAL_YAW_TOLERANCE = 0.25
#: the most steps one run may take (max_time / dt): about two hours of computing at 0.08 ms a step
MAX_STEPS = 100_000_000


class SimStatus(enum.Enum):
    REACHED = "reached"  #: the controller stopped at the goal and the true pose is within the tolerance
    OFF_GOAL = "off_goal"  #: the controller stopped at its estimate of the goal, but the robot is not there
    COLLIDED = "collided"
    TIMEOUT = "timeout"
    STALLED = "stalled"


@dataclass
class SimResult:
    """A simulated run. Arrays have one row per step plus the initial state."""

    status: SimStatus
    time_s: float  #: simulated time at the end
    steps: int
    wall_time_s: float
    t: np.ndarray
    true_poses: np.ndarray  #: (N, 3) x, y, θ
    odom_poses: np.ndarray  #: (N, 3) the robot's own estimate
    commands: np.ndarray  #: (N, 3) vx, vy, ω issued (body frame, after limits)
    goal: np.ndarray
    path: Optional[np.ndarray] = None  #: the planned path followed, if any
    scans: Optional[np.ndarray] = None  #: (N, beams) when recorded
    reason: str = ""
    meta: Dict[str, Any] = field(default_factory=dict)
    #: paths planned during the run (replans), each from the robot's pose then (a controller that plans at
    #: a high rate keeps its last ones only: ``replan_count`` counts them all)
    replans: List[np.ndarray] = field(default_factory=list)
    replan_count: int = 0

    @property
    def real_time_factor(self) -> float:
        return self.time_s / self.wall_time_s if self.wall_time_s > 0 else float("inf")

    @property
    def final_true(self) -> np.ndarray:
        return self.true_poses[-1]

    @property
    def final_odom(self) -> np.ndarray:
        return self.odom_poses[-1]

    @property
    def error_true(self) -> float:
        """Distance of the true final position from the goal (m)."""
        return float(np.hypot(*(self.final_true[:2] - self.goal)))

    @property
    def error_odom(self) -> float:
        """Distance of the odometry's final estimate from the goal (m)."""
        return float(np.hypot(*(self.final_odom[:2] - self.goal)))

    @property
    def distance(self) -> float:
        return float(np.sum(np.hypot(*np.diff(self.true_poses[:, :2], axis=0).T)))

    def tracking_error(self) -> float:
        """Largest distance of the true trajectory from the planned path (m)."""
        if self.path is None:
            return float("nan")
        if len(self.path) == 1:  # a goal at the start: the distance from that point (it was NaN)
            return float(np.max(np.hypot(*(self.true_poses[:, :2] - self.path[0, :2]).T)))
        return float(np.max(distance_to_polyline(self.true_poses[:, :2], self.path[:, :2])))

    def to_dict(self, trajectory: bool = False) -> Dict[str, Any]:
        out = {"status": self.status.name, "reason": self.reason, "goal": self.goal.tolist(),
               "time_s": self.time_s, "steps": self.steps, "wall_time_s": self.wall_time_s,
               "real_time_factor": self.real_time_factor, "final_true": self.final_true.tolist(),
               "final_odom": self.final_odom.tolist(), "error_true_m": self.error_true,
               "error_odom_m": self.error_odom, "distance_m": self.distance, **self.meta}
        if trajectory:
            out.update(t=self.t.tolist(), true_poses=self.true_poses.tolist(), odom_poses=self.odom_poses.tolist(),
                       commands=self.commands.tolist(), path=None if self.path is None else self.path.tolist())
        return out


def check_progress(progress: Any) -> None:
    """Refuse a ``progress`` that is neither None nor callable, naming it (``progress=3`` was a raw TypeError,
    "'int' object is not callable", at the run's first step: attack, session 23)."""
    if progress is not None and not callable(progress):
        raise ParameterError(f"progress must be a function of (t, max_time) or None, got {shown(progress)}")


def _check_parts(robot, controller, start, goal) -> None:
    """ParameterError naming a robot, controller, start or goal the simulation cannot take: a robot or a
    controller given by name, a start of None or text, met AttributeError or TypeError inside (API attack,
    session 29; :func:`navlab.sim.runner.simulate` takes names)."""
    if not isinstance(controller, Controller):
        raise ParameterError(f"controller: expected a Controller (navlab.control.make_controller), got "
                             f"{shown(controller)}")
    if not all(hasattr(robot, part) for part in ("radius", "holonomic", "shape")):
        raise ParameterError(f"robot: expected a robot (navlab.robots.make_robot), got {shown(robot)}")
    for name, point, sizes in (("start", start, (2, 3)), ("goal", goal, (2, 3))):  # (a goal's heading: its own)
        values = float_array(point)
        if values.ndim != 1 or len(values) not in sizes or not np.isfinite(values).all():
            raise ParameterError(f"{name}: expected {' or '.join(f'{n} numbers' for n in sizes)} "
                                 f"(x, y [m][, heading rad]), got {shown(point)}")


def _checked_path(path) -> np.ndarray:
    """``path`` as an (N, 2) or (N, 3) float array of N >= 1 finite points within the coordinate limits, or a
    ParameterError naming it (a NaN waypoint ran to COLLIDED at step 1 with NaN poses and numpy's warnings;
    an empty one was an IndexError: API attack, session 29)."""
    try:
        points = np.asarray(path, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"path: expected (N, 2) waypoints [m], got {shown(path)}") from None
    if points.ndim != 2 or points.shape[1] not in (2, 3) or len(points) == 0:
        raise ParameterError(f"path: expected (N, 2) waypoints [m] (or (N, 3) poses), N >= 1, got shape "
                             f"{points.shape}")
    if not np.isfinite(points).all() or np.abs(points[:, :2]).max() > MAX_COORDINATE:
        raise ParameterError(f"path: waypoints must be finite and within ±{MAX_COORDINATE:g} m "
                             f"(navlab.limits), got {shown(points.tolist())}")
    return points


class Simulation:
    """One robot in one world.

    Parameters
    ----------
    scene_world : World or OccupancyGrid
    robot : DiffDrive or Omni3
    controller : Controller
    start : (x, y, θ)
    goal : (x, y)
    lidar : Lidar, optional
        Needed by controllers that read scans.
    encoders : WheelEncoders, optional
        Default: 1440 ticks per revolution, no noise, no slip.
    compass : Compass, optional
        When given, odometry takes its heading from it (seed 004).
    dt : float
        Step (s).
    max_time : float
        Simulated time limit (s); then the status is TIMEOUT.
    path : (N, 2) array, optional
        Waypoints for path-following controllers.
    record_scans : bool
        Keep every scan in the result.
    lidar_timing, odometry_timing : SensorTiming or dict, optional
        Rate, latency and jitter of the LiDAR and of the odometry
        (``{rate: 10, latency: 0.5}``); the controller acts on the newest
        measurement that has arrived. Default: every step, no delay.
    direction : (N,) array, optional
        With a path of poses: +1 forward, −1 reverse, on the way into each
        pose (``Result.direction``); the controller follows it with its cusps.
    goal_heading : float, optional
        [rad] The run is REACHED only with the true heading within
        :data:`GOAL_YAW_TOLERANCE` of it.
    """

    def __init__(self, scene_world, robot, controller: Controller, start, goal, lidar: Optional[Lidar] = None,
                 encoders: Optional[WheelEncoders] = None, compass: Optional[Compass] = None, dt: float = 0.05,
                 max_time: float = 120.0, path=None, record_scans: bool = False,
                 lidar_timing: Optional[SensorTiming] = None, odometry_timing: Optional[SensorTiming] = None,
                 direction=None, goal_heading: Optional[float] = None) -> None:
        if not (is_finite_real(dt) and dt > 0):  # (numpy's numbers too: np.float32 was refused, API attack)
            raise ParameterError(f"time step dt must be a positive number of seconds, got {shown(dt)}")
        if dt < MIN_DT:
            raise ParameterError(f"time step dt = {dt:g} s is below the smallest supported step, {MIN_DT:g} s")
        if dt > MAX_DT:
            raise ParameterError(f"time step dt = {dt:g} s is above the largest supported step, {MAX_DT:g} s "
                                 "(the controller acts once a step: a longer step drives blind past goals and gaps)")
        if not (is_finite_real(max_time) and max_time > 0):
            raise ParameterError(f"max_time must be a positive, finite number of seconds, got {shown(max_time)}")
        if max_time / dt > MAX_STEPS:
            raise ParameterError(f"max_time / dt = {max_time / dt:.3g} steps, more than the {MAX_STEPS:.0e} a run "
                                 f"supports; lower max_time or raise dt")
        _check_parts(robot, controller, start, goal)
        if controller.needs_scan and lidar is None:
            raise ParameterError(f"controller {type(controller).__name__} reads LiDAR points: give a lidar")
        if controller.needs_path and path is None:
            raise ParameterError(f"controller {type(controller).__name__} follows a path: give a path or a planner")
        if controller.holonomic and not robot.holonomic:
            raise ParameterError(f"controller {type(controller).__name__} commands sideways motion, "
                                 f"which a {type(robot).__name__} cannot do")
        self.scene = Scene(scene_world, robot.radius, getattr(robot, "footprint", None))
        self.robot, self.controller, self.lidar = robot, controller, lidar
        self.encoders = encoders or WheelEncoders()
        self.compass = compass
        self.dt, self.max_time = float(dt), float(max_time)
        self.start = np.array(start, float) if len(start) == 3 else np.array((*start, 0.0))
        self.goal = np.asarray(goal, float)[:2]
        self.path = None if path is None else _checked_path(path)
        self.direction = None if direction is None else np.asarray(direction, float)
        if self.direction is not None and (self.path is None or len(self.direction) != len(self.path)):
            raise ParameterError("direction needs a path with one direction per pose")
        if goal_heading is not None and not (isinstance(goal_heading, (int, float)) and math.isfinite(goal_heading)):
            raise ParameterError(f"goal_heading must be a finite number of radians, got {goal_heading!r}")
        self.goal_heading = None if goal_heading is None else float(goal_heading)
        self.record_scans = check_flag("record_scans", record_scans)  # ("no" recorded them: attack, session 25)
        self.lidar_timing = SensorTiming.from_dict(lidar_timing, "lidar")
        self.odometry_timing = SensorTiming.from_dict(odometry_timing, "odometry")
        if controller.needs_path and getattr(controller, "replanner", False) is None:
            # replanning controllers (hybrid, followers with replan) plan again with navlab's defaults
            # unless the caller gave them a replanner (navlab sim passes its --planner on)
            from .replan import Replanner

            controller.replanner = Replanner(scene_world, robot.radius, self.goal)
        self.costmap_feed = None
        if getattr(controller, "needs_costmap", False):
            from .costmap_feed import CostmapFeed

            self.costmap_feed = CostmapFeed(scene_world, robot.shape, controller, self.goal)
        if not self.scene.free(self.start):
            raise ParameterError(f"the robot starts in collision: {self.scene.describe(self.start)}")
        if not self.scene.free_at_some_heading(self.goal, self.goal_heading):
            raise ParameterError(f"the goal is unreachable: {self.scene.describe(self.goal)}")

    def run(self, seed: Any = 0, progress: Optional[Callable[[float, float], None]] = None) -> SimResult:
        """Run from the start until the goal, a stall, a collision or ``max_time``; ``progress(t,
        max_time)``, if given, is called at every step with the simulated time."""
        check_progress(progress)
        rng = np.random.default_rng(seed)
        replanner = getattr(self.controller, "replanner", None)
        replans_before = len(getattr(replanner, "paths", ()))
        if self.costmap_feed is not None:
            self.costmap_feed.reset()
        # latency jitter has its own stream, so runs without jitter draw exactly as before
        entropy = int(seed) if isinstance(seed, (int, np.integer)) else 0
        timing_rng = np.random.default_rng(np.random.SeedSequence(entropy, spawn_key=(4,)))
        if hasattr(self.controller, "seed"):  # sampling controllers (MPPI) draw from their own stream
            self.controller.seed(np.random.default_rng(np.random.SeedSequence(entropy, spawn_key=(5,))))
        n_max = int(math.ceil(self.max_time / self.dt)) + 1
        # The logs grow by doubling: memory follows the run, not max_time.
        rows = min(n_max, INITIAL_LOG_ROWS)
        true = np.empty((rows, 3))
        odo = np.empty((rows, 3))
        cmds = np.zeros((rows, 3))
        scans = np.empty((rows, self.lidar.beams)) if (self.record_scans and self.lidar) else None
        scene = self.scene
        scene.set_time(0.0)
        plant = Plant(scene, self.robot, self.start, self.encoders, self.compass)
        if self.direction is None:
            self.controller.reset(self.goal, self.path)
        else:
            self.controller.reset(self.goal, self.path, direction=self.direction)
        true[0], odo[0] = plant.pose, plant.odometry.pose
        status, reason = SimStatus.TIMEOUT, f"goal not reached in {self.max_time:g} s of simulated time"
        dt = self.dt
        scanning = self.lidar is not None and (self.controller.needs_scan or scans is not None)
        lidar_line = DelayLine(self.lidar_timing, timing_rng, initial=np.empty((0, 2)))
        odom_line = DelayLine(self.odometry_timing, timing_rng, initial=plant.odometry.pose.copy())
        n = 1  # states recorded
        wall0 = time.perf_counter()
        while n < n_max:
            if n == len(true):
                rows = min(2 * n, n_max)
                true, odo, cmds = grown(true, rows), grown(odo, rows), grown(cmds, rows)
                scans = None if scans is None else grown(scans, rows)
            t = (n - 1) * dt
            if progress is not None:
                progress(t, self.max_time)
            scene.set_time(t)
            if odom_line.due(t):
                odom_line.push(t, plant.odometry.pose)
            points = None
            if scanning:
                if lidar_line.due(t):
                    ranges = self.lidar.scan(scene, plant.pose, rng)
                    if scans is not None:
                        scans[n - 1] = ranges
                    # the points are placed around the pose the robot believed in when it scanned
                    lidar_line.push(t, self.lidar.points(ranges, plant.odometry.pose))
                elif scans is not None:
                    scans[n - 1] = np.nan
                points = lidar_line.read(t)
            believed = odom_line.read(t)
            if self.costmap_feed is not None:
                self.costmap_feed.update(t, believed, points)
            command = self.controller.command(t, believed, points)
            if command.status == REACHED:
                # the controller judged its estimate; the run is judged on where the robot really is
                off = float(np.hypot(*(plant.pose[:2] - self.goal[:2])))
                turn = 0.0 if self.goal_heading is None else abs(math.remainder(plant.pose[2] - self.goal_heading,
                                                                                 2.0 * math.pi))
                if off <= GOAL_TOLERANCE and turn <= GOAL_YAW_TOLERANCE:
                    status, reason = SimStatus.REACHED, ""
                elif off <= GOAL_TOLERANCE:
                    status, reason = SimStatus.OFF_GOAL, (
                        f"the robot stopped at the goal facing {plant.pose[2]:.3f} rad, {turn:.3g} rad from the goal's "
                        f"heading (more than {GOAL_YAW_TOLERANCE:g} rad)")
                else:
                    status, reason = SimStatus.OFF_GOAL, (
                        f"the controller stopped at its estimate of the goal, but the robot is {off:.3g} m from it "
                        f"(more than {GOAL_TOLERANCE:g} m: odometry drift, or a time step too long to stop in)")
                break
            if command.status == STALLED:
                status, reason = SimStatus.STALLED, self.controller.why_stalled()
                break
            collided = plant.step(command.vx, command.vy, command.omega, dt, rng, t)
            cmds[n - 1] = plant.last_twist
            true[n], odo[n] = plant.pose, plant.odometry.pose
            n += 1
            if collided:
                status, reason = SimStatus.COLLIDED, plant.hit
                break
        wall = time.perf_counter() - wall0
        steps = n - 1
        meta = {}
        if self.goal_heading is not None:
            meta = {"goal_heading": self.goal_heading,
                    "heading_error_rad": abs(math.remainder(true[n - 1, 2] - self.goal_heading, 2.0 * math.pi))}
        # the paths planned during the run: the replanner's (followers), the costmap feed's and a controller's
        # own global planner's (DWA's move_base, which keeps its last ones and counts them all)
        replanned = list(getattr(replanner, "paths", ())[replans_before:]) + (
            self.costmap_feed.paths if self.costmap_feed is not None else [])
        own = list(getattr(self.controller, "paths", ()))
        return SimResult(status, steps * dt, steps, wall, np.arange(n) * dt, true[:n].copy(), odo[:n].copy(),
                         cmds[:n].copy(), self.goal.copy(), self.path,
                         None if scans is None else scans[:n].copy(), reason, meta, replans=replanned + own,
                         replan_count=len(replanned) + getattr(self.controller, "plans_made", len(own)))

    def min_clearance(self, result: SimResult) -> float:
        """Smallest gap (m) between the robot's disc and any obstacle, where
        each was, over a run (negative after a collision; nan on maps)."""
        if self.scene.is_grid:
            return math.nan
        return float(np.min(self.scene.clearances(result.true_poses, result.t)))
