"""Paths of poses for the simulator (issue 21): when a run plans between
poses, and the plan it follows.

A run plans between poses ``(x, y, θ)`` — with Hybrid A* or an SE(2) tree,
through :func:`navlab.plan` — when the robot steers like a car, when the
world names its robot's footprint (the heading scenes ``parking``,
``narrow_aisle``, ``trap_car``), when the goal has a heading, when the
planner is heading-aware, or when ``motion`` is asked for. The robot then
follows the plan's poses and directions of travel, reversing at cusps
(``rear_wheel_feedback`` by default, :mod:`navlab.control.path_tracking`;
``pure_pursuit`` also can).
"""

from __future__ import annotations

import math
from typing import Any, Dict, Optional, Tuple

import numpy as np

from ..errors import ParameterError
from ..limits import is_finite_real

#: controllers that follow a path of poses with reverse stretches
POSE_FOLLOWERS = ("rear_wheel_feedback", "pure_pursuit")
#: a car's plan is drawn at this multiple of its smallest turning radius: the tracker keeps the rest of the
#: steering to correct errors (at exactly the smallest radius the car strays up to 9 cm from exact Reeds–Shepp
#: paths where it must steer back at full lock; with 10 % room, 1 cm: tests/sim/test_car.py)
STEERING_ROOM = 1.1
#: the planner a pose run uses unless told: deterministic and fast on the heading scenes
DEFAULT_POSE_PLANNER = "hybrid_astar"
#: the follower's settings for a car unless given: a car is driven faster than a TurtleBot, and its
#: offsets die out over a metre (its turning radius is metres)
CAR_FOLLOWER = {"rear_wheel_feedback": {"speed": 1.0, "settling_distance": 1.0},
                "pure_pursuit": {"speed": 1.0, "lookahead": 0.5}}


def wants_pose_path(scene_world, robot_name: str, planner: Optional[str], goal, plan_params: Dict[str, Any]) -> bool:
    """Whether this run plans between poses (see the module)."""
    from ..pose_queries import POSE_PLANNERS
    from ..robots.kinematics import ROBOTS

    return (getattr(ROBOTS.get(robot_name), "steers", False)
            or getattr(scene_world, "footprint", None) is not None
            or (goal is not None and len(goal) == 3)
            or planner in POSE_PLANNERS
            or plan_params.get("motion", "holonomic") != "holonomic")


def scene_robot_params(scene_world, robot_name: str, robot_params: Dict[str, Any]) -> Dict[str, Any]:
    """The robot's settings with what the scene says of its robot filled in:
    the world's ``footprint``, and for a car the steering that turns
    :data:`STEERING_ROOM` times tighter than the scene's turning radius with
    the car's wheelbase (unless given), so that its plan is drawn at the
    scene's radius."""
    from ..pose_queries import declared_turning_radius
    from ..robots.kinematics import ROBOTS

    params = dict(robot_params)
    footprint = getattr(scene_world, "footprint", None)
    if footprint is not None and "footprint" not in params:
        params["footprint"] = footprint.to_value()
        if "radius" not in params:
            params["radius"] = footprint.inscribed_radius
    radius = declared_turning_radius(scene_world)
    cls = ROBOTS.get(robot_name)
    if getattr(cls, "steers", False) and radius is not None and "max_steer" not in params:
        wheelbase = params.get("wheelbase", cls.wheelbase)
        if is_finite_real(wheelbase) and wheelbase > 0:  # (else make_robot names the bad wheelbase)
            params["max_steer"] = math.atan2(wheelbase, radius / STEERING_ROOM)
    return params


def plan_pose_path(scene_world, robot, start, goal, planner: Optional[str], plan_params: Dict[str, Any],
                   seed: Any = 0) -> Tuple[Any, np.ndarray, np.ndarray]:
    """Plan between poses for ``robot``'s footprint and turning radius.

    Returns ``(result, path (N, 3), direction (N,))``; the result is the
    planner's (a failure has no path: the caller reports it).
    """
    from ..planning import plan
    from ..pose_queries import POSE_PLANNERS, TREE_POSE_PLANNERS

    planner = DEFAULT_POSE_PLANNER if planner is None else planner
    params = dict(plan_params)
    if planner not in POSE_PLANNERS and planner not in TREE_POSE_PLANNERS:
        raise ParameterError(f"planner '{planner}' plans for a point; a run between poses needs "
                             f"{', '.join((*POSE_PLANNERS, *TREE_POSE_PLANNERS))}")
    params.setdefault("motion", "reeds_shepp")
    if getattr(robot, "steers", False):
        from ..sampling.curves import check_turning_radius

        least = robot.turning_radius
        given = check_turning_radius(params.setdefault("turning_radius", least * STEERING_ROOM))
        if given < least * (1 - 1e-12):
            raise ParameterError(f"turning_radius {given:g} m is tighter than the car can turn "
                                 f"({least:.4g} m = wheelbase / tan(max_steer); its plans are drawn at "
                                 f"{STEERING_ROOM:g} × that, {least * STEERING_ROOM:.4g} m, unless turning_radius is given)")
    params.setdefault("footprint", robot.shape.to_value())
    result = plan(scene_world, planner=planner, start=tuple(start), goal=tuple(goal), seed=seed, **params)
    if not result.success:
        return result, np.empty((0, 3)), np.empty(0)
    return result, np.asarray(result.path, float), np.asarray(result.direction, float)
