"""One simulation from names and settings (what ``navlab sim`` does)."""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import numpy as np

from ..control import make_controller
from ..grid.occupancy import OccupancyGrid
from ..robots import Compass, WheelEncoders, make_robot
from ..sensors import Lidar
from .scene import load_scene_world
from .simulation import SimResult, Simulation

DEFAULT_CONTROLLER = {"omni3": "potential_field", "diff": "goto_waypoint"}
#: inflation beyond the robot radius when planning a path to follow: half a
#: 0.05 m cell's diagonal for the grid's discretisation plus room for the
#: follower's tracking error
PLAN_MARGIN = 0.07


def simulate(world: Any, robot: str = "omni3", controller: Optional[str] = None, start=None, goal=None,
             planner: Optional[str] = None, lidar: Optional[str] = None, robot_params: Optional[Dict] = None,
             controller_params: Optional[Dict] = None, dt: float = 0.05, max_time: float = 120.0,
             seed: Any = 0) -> Tuple[SimResult, Any, Simulation]:
    """Build and run one simulation; every input is checked before it runs.

    Returns the result, the world or grid, and the Simulation.
    """
    scene_world = load_scene_world(world)
    bot = make_robot(robot, **(robot_params or {}))
    ctrl = make_controller(controller or DEFAULT_CONTROLLER[robot], **(controller_params or {}))
    is_grid = isinstance(scene_world, OccupancyGrid)
    if start is None:
        if is_grid:
            raise ValueError("a map has no start of its own: give --start X Y THETA")
        start = (*scene_world.start, 0.0)
    if goal is None:
        if is_grid:
            raise ValueError("a map has no goal of its own: give --goal X Y")
        goal = scene_world.goal
    start = tuple(float(v) for v in start) if len(start) == 3 else (float(start[0]), float(start[1]), 0.0)
    goal = (float(goal[0]), float(goal[1]))
    if planner is not None and not ctrl.needs_path:
        raise ValueError(f"controller '{controller}' plans nothing ahead; --planner is for goto_waypoint and "
                         "pure_pursuit")
    path = plan_path(scene_world, bot, start, goal, planner) if ctrl.needs_path else None
    sensor = None
    if lidar != "none" and (ctrl.needs_scan or lidar is not None):
        sensor = Lidar(noise=None if lidar in (None, "exact") else lidar)
    noisy = lidar == "rplidar_a1"
    sim = Simulation(scene_world, bot, ctrl, start, goal, lidar=sensor,
                     encoders=WheelEncoders(noise=0.02 if noisy else 0.0, slip=0.01 if noisy else 0.0),
                     compass=Compass(noise_deg=1.0) if noisy else None, dt=dt, max_time=max_time, path=path)
    return sim.run(seed), scene_world, sim


def plan_path(scene_world, robot, start, goal, planner: Optional[str]) -> np.ndarray:
    """A collision-free path for the robot's footprint (plus a margin)."""
    from dataclasses import replace

    from ..sim.scene import Scene

    scene = Scene(scene_world, robot.radius)
    for label, p in (("start", start), ("goal", goal)):
        if not scene.free(p):
            raise ValueError(f"the {label} is in collision: {scene.describe(p)}")
    if isinstance(scene_world, OccupancyGrid):
        from ..grid import plan_world

        result = plan_world(scene_world.inflate(robot.radius + PLAN_MARGIN), start[:2], goal,
                            algorithm=planner or "astar", smooth=True)
    else:
        from ..planning import plan

        world = replace(scene_world, start=start[:2], goal=goal,
                        robot_radius=robot.radius + PLAN_MARGIN, goal_tolerance=0.0)
        result = plan(world, planner=planner or "rrt_star", sampler="uniform", seed=0)
    if not result.success:
        raise ValueError(f"no path for the robot from {start[:2]} to {goal}: {result.status.name} {result.reason}")
    path = np.asarray(result.path, float)
    path[0], path[-1] = start[:2], goal
    return path
