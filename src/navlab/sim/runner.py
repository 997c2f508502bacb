"""One simulation from names and settings (what ``navlab sim`` does)."""

from __future__ import annotations

import math
from typing import Any, Callable, Dict, Optional, Tuple

import numpy as np

from ..control import make_controller
from ..errors import NavlabError, ParameterError
from ..grid.occupancy import OccupancyGrid
from ..limits import is_finite_real
from ..robots import Compass, WheelEncoders, make_robot
from ..sensors import Lidar
from .replan import PLAN_MARGIN, Replanner  # noqa: F401  (PLAN_MARGIN: the seeds' experiments use it)
from .replan import plan_path as _plan_path
from .scene import load_scene_world
from .simulation import SimResult, Simulation, check_progress

#: the omni robot follows a global plan with the potential field as its local
#: avoider (the plain field stalls in traps and clutter); the diff drive
#: follows the plan with seed 002's goto_waypoint
DEFAULT_CONTROLLER = {"omni3": "hybrid", "diff": "goto_waypoint", "jackal": "rpp", "car": "rear_wheel_feedback"}
#: followers that can replan around what the LiDAR sees; the default one does
#: so by itself in worlds with moving obstacles
REPLANNING_FOLLOWERS = ("goto_waypoint", "pure_pursuit")


def _has_moving(scene_world) -> bool:
    return any(getattr(o, "motion", None) is not None for o in getattr(scene_world, "obstacles", ()))


class NoPathError(NavlabError):
    """The global planner found no path for the robot (an answer about the
    world, not bad input: an experiment records it and goes on). ``status``
    says which answer, as ``navlab plan``'s statuses do."""

    def __init__(self, reason: str, status: str = "NO_PATH") -> None:
        super().__init__(reason)
        self.status = status


def _speed_within_robot(name: str, params: Dict[str, Any], given: Dict[str, Any], bot: Any) -> Dict[str, Any]:
    """The controller's settings with its top speed (``Controller.speed_setting``)
    within the robot's ``max_speed``: a default above it is lowered to it, a value
    the user set above it is refused, naming both. The robot would cut the speed
    but not the turn rate, so the controller would steer for a speed it never
    gets (RPP's default 0.5 m/s on the 0.22 m/s diff drive; 150 m/s drove at
    0.22 without a word)."""
    from ..control.base import CONTROLLERS
    from ..registry import parameters_of

    factory = CONTROLLERS.get(name)
    setting = factory.speed_setting
    speed = params.get(setting, parameters_of(factory).get(setting)) if setting else None
    if not is_finite_real(speed) or speed <= bot.max_speed:  # not a number: the controller names it
        return params
    if setting in given:
        raise ParameterError(f"controller {name} {setting} {speed:g} m/s is more than the robot's max_speed "
                             f"{bot.max_speed:g} m/s: lower it, or raise the robot's (--robot-param max_speed=...)")
    return {**params, setting: bot.max_speed}


def simulate(world: Any, robot: str = "omni3", controller: Optional[str] = None, start=None, goal=None,
             planner: Optional[str] = None, lidar: Optional[str] = None, robot_params: Optional[Dict] = None,
             controller_params: Optional[Dict] = None, dt: float = 0.05, max_time: Optional[float] = None,
             seed: Any = 0, sampler: str = "uniform", lidar_timing: Optional[Dict] = None,
             odometry_timing: Optional[Dict] = None,
             plan_params: Optional[Dict] = None,
             progress: Optional[Callable[[float, float], None]] = None) -> Tuple[SimResult, Any, Simulation]:
    """Build and run one simulation; every input is checked before it runs.

    ``max_time`` defaults to :func:`default_max_time` of the path (or the
    straight line) to the goal. ``goal`` may be a pose (x, y, θ): the run
    then plans between poses (as it does for a car, a world that names its
    robot's footprint, ``planner='hybrid_astar'`` or ``plan_params={'motion':
    ...}``; see :mod:`navlab.sim.pose_path`) and ends REACHED only with the
    heading within :data:`~navlab.sim.simulation.GOAL_YAW_TOLERANCE`.
    ``plan_params`` go to the global planner. ``progress(t, max_time)`` is
    called at every step with the simulated time (the command line's bar).
    Returns the result, the world or grid, and the Simulation.
    """
    from .pose_path import CAR_FOLLOWER, POSE_FOLLOWERS, plan_pose_path, scene_robot_params, wants_pose_path

    from ..angles import planned_heading
    from ..limits import check_coordinate, check_seed

    check_progress(progress)  # (before any planning)
    checked = {}
    for name, values in (("start", start), ("goal", goal)):
        if values is None:
            continue
        if isinstance(values, (str, bytes, dict)) or not hasattr(values, "__len__") or len(values) not in (2, 3):
            raise ParameterError(f"{name} must be (x, y) or (x, y, θ), got {values!r}")
        for axis, v in zip("xy", values):
            check_coordinate(f"{name} {axis}", v)
        # any finite heading, wrapped (and a note beyond ±2π, most often degrees), as the planners take it
        checked[name] = tuple(values[:2]) + ((planned_heading(f"{name} theta", values[2]),) if len(values) == 3 else ())
    start, goal = checked.get("start", start), checked.get("goal", goal)
    for name, value in (("robot_params", robot_params), ("controller_params", controller_params),
                        ("plan_params", plan_params)):
        if value is not None and not isinstance(value, dict):
            raise ParameterError(f"{name} must be a mapping of name: value, got {value!r}")
    check_seed(seed)
    if lidar is not None and not isinstance(lidar, str):  # (lidar=3 was an AttributeError deep in a scan)
        from ..sensors.lidar import NOISE_MODELS

        raise ParameterError(f"lidar must be 'none', 'exact' or a noise model's name ({', '.join(NOISE_MODELS.names())}), "
                             f"got {lidar!r}")
    scene_world = load_scene_world(world)
    plan_params = dict(plan_params or {})
    for key in ("planner", "sampler", "seed"):  # the run's own settings (a TypeError, "multiple values", until 17)
        if key in plan_params:
            raise ParameterError(f"plan_params: '{key}' is the run's own setting: give {key}={plan_params[key]!r} "
                                 "(--" + key + " on the command line)")
    poses = wants_pose_path(scene_world, robot, planner, goal, plan_params)
    bot = make_robot(robot, **(scene_robot_params(scene_world, robot, robot_params or {}) if poses
                               else (robot_params or {})))
    params = dict(controller_params or {})
    if poses:
        if controller is not None:
            from ..control.base import CONTROLLERS

            CONTROLLERS.get(controller)  # an unknown name first: "did you mean"
        if controller is not None and controller not in POSE_FOLLOWERS:
            raise ParameterError(f"controller '{controller}' cannot follow a path of poses with reverse stretches (this "
                                 f"run plans between poses); use {', '.join(POSE_FOLLOWERS)}")
        follower = POSE_FOLLOWERS[0] if controller is None else controller
        if getattr(bot, "steers", False):
            params = {**CAR_FOLLOWER[follower], **params}
    elif controller is None and DEFAULT_CONTROLLER.get(robot) in REPLANNING_FOLLOWERS and _has_moving(scene_world):
        # the default follower watches the path ahead where obstacles move (crossing): blind, it drove into them
        params.setdefault("replan", True)
    # ("" is a name no registry holds, not the default: API attack, session 29)
    name = controller if controller is not None else POSE_FOLLOWERS[0] if poses else DEFAULT_CONTROLLER[robot]
    ctrl = make_controller(name, **_speed_within_robot(name, params, controller_params or {}, bot))
    is_grid = isinstance(scene_world, OccupancyGrid)
    if start is None:
        if is_grid:
            raise ParameterError("a map has no start of its own: give --start X Y [THETA] (and --goal X Y)")
        start = (*scene_world.start, getattr(scene_world, "start_heading", None) or 0.0)
    if goal is None:
        if is_grid:
            raise ParameterError("a map has no goal of its own: give --goal X Y")
        heading = getattr(scene_world, "goal_heading", None)
        goal = tuple(scene_world.goal) + ((heading,) if poses and heading is not None else ())
    start = tuple(float(v) for v in start) if len(start) == 3 else (float(start[0]), float(start[1]), 0.0)
    goal_heading = float(goal[2]) if len(goal) == 3 else None
    goal = (float(goal[0]), float(goal[1]))
    if planner is not None and not ctrl.needs_path:
        raise ParameterError(f"controller '{controller}' plans nothing ahead; --planner is for hybrid, goto_waypoint "
                             "and pure_pursuit")
    direction = None
    if poses:
        result, path, direction = plan_pose_path(scene_world, bot, start, goal + ((goal_heading,) if goal_heading
                                                                                  is not None else ()),
                                                 planner, plan_params, seed)
        if not result.success:
            invalid = result.status.name.startswith("INVALID_")  # an endpoint the robot cannot stand on
            raise NoPathError(result.reason if invalid else f"no path between the poses: {result.status.name} "
                              f"{result.reason}", result.status.name if invalid else "NO_PATH")
    elif getattr(ctrl, "needs_costmap", False) and planner is None:
        check_endpoints(scene_world, bot, start, goal, goal_heading)
        path = costmap_path(scene_world, bot, ctrl, start, goal)
    else:
        path = plan_path(scene_world, bot, start, goal, planner, sampler, plan_params) if ctrl.needs_path else None
    if ctrl.needs_path and hasattr(ctrl, "replanner"):  # replans use the same planner as the first plan
        ctrl.replanner = Replanner(scene_world, bot.radius, goal, planner, sampler)
    if max_time is None:
        max_time = default_max_time(path if path is not None else np.array((start[:2], goal)), bot, ctrl)
    sensor = None
    if lidar != "none" and (ctrl.needs_scan or lidar is not None):
        # a robot that names its own laser (the jackal) gets it; the others the seed's RPLiDAR
        sensor = Lidar(**getattr(bot, "laser", {}), noise=None if lidar in (None, "exact") else lidar)
    noisy = lidar == "rplidar_a1"
    sim = Simulation(scene_world, bot, ctrl, start, goal, lidar=sensor,
                     encoders=WheelEncoders(noise=0.02 if noisy else 0.0, slip=0.01 if noisy else 0.0),
                     compass=Compass(noise_deg=1.0) if noisy else None, dt=dt, max_time=max_time, path=path,
                     lidar_timing=lidar_timing, odometry_timing=odometry_timing, direction=direction,
                     goal_heading=goal_heading)
    return sim.run(seed, progress=progress), scene_world, sim


def default_max_time(path: np.ndarray, robot, controller) -> float:
    """Four times the path's length at the slower of the robot's and the
    controller's top speed, plus a minute for turning and waiting (a 49 m
    map path gets about 15 min rather than a fixed 120 s), rounded up to a whole second."""
    length = float(np.sum(np.hypot(*np.diff(np.asarray(path, float)[:, :2], axis=0).T)))
    field = getattr(controller, "field", controller)
    speed = min(robot.max_speed, getattr(controller, "speed", None) or getattr(field, "max_speed", robot.max_speed))
    return float(math.ceil(60.0 + 4.0 * length / speed))  # whole seconds: "90.8701 s" read as a measurement


def costmap_path(scene_world, robot, controller, start, goal) -> np.ndarray:
    """The global path a costmap controller starts with: A* on its costmap (cost-weighted, as Nav2's planners)."""
    from .costmap_feed import CostmapFeed

    path = CostmapFeed(scene_world, robot.shape, controller, goal).initial_path(start)
    if path is None:
        raise NoPathError(f"no path on the costmap from {tuple(start[:2])} to {tuple(goal)} (every way passes "
                          "cells of INSCRIBED cost or more: the footprint would touch an obstacle)")
    return path


def check_endpoints(scene_world, robot, start, goal, goal_heading: Optional[float] = None) -> None:
    """NoPathError INVALID_START / INVALID_GOAL (an answer about the world, as navlab plan's) when the
    robot's shape cannot stand at the start, or at the goal at its heading (at any of 72 headings when it
    has none: :meth:`~navlab.sim.scene.Scene.free_at_some_heading`), by the rule the simulation itself
    applies."""
    from ..sim.scene import Scene

    scene = Scene(scene_world, robot.radius, getattr(robot, "footprint", None))

    def why(what: str, p) -> str:
        # "the goal is in collision: (100, 100) is outside the bounds" read oddly (newcomer, session 29): a
        # point's own description says what is wrong, a footprint's contact follows "in collision"
        text = scene.describe(p)
        return f"the {what} {text}" if text.startswith("(") else f"the {what} is in collision: {text}"

    if not scene.free(np.asarray(start, float)):
        raise NoPathError(why("start", start), "INVALID_START")
    if not scene.free_at_some_heading(goal, goal_heading):
        # at its heading, when it has one (described facing +x it read "the goal (x, y) is free": review, s. 29)
        raise NoPathError(why("goal", goal if goal_heading is None else (*goal[:2], goal_heading)), "INVALID_GOAL")


def plan_path(scene_world, robot, start, goal, planner: Optional[str], sampler: str = "uniform",
              params: Optional[Dict] = None) -> np.ndarray:
    """A collision-free path for the robot's footprint (plus a margin)."""
    check_endpoints(scene_world, robot, start, goal)
    path = _plan_path(scene_world, robot.radius, start, goal, planner, sampler, params=params or None)
    if not isinstance(path, np.ndarray):
        raise NoPathError(f"no path for the robot from {start[:2]} to {goal}: {path.status.name} {path.reason}")
    return path
