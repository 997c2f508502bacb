"""Global planning for the simulator's path followers and hybrid navigator:
the first plan, and replans from where the robot is around what its LiDAR
sees that the map does not know (a moving obstacle, for instance).

A dynamic world's first plan is made against the obstacles' t = 0 places
(the packed geometry holds their t = 0 geometry). A replan uses only the
static obstacles plus the sensed points the static ones do not explain.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Optional

import numpy as np

from ..grid.occupancy import OccupancyGrid
from ..world.geometry import clearance_batch, pack_geometry
from ..world.shapes import Circle

#: inflation beyond the robot radius when planning a path to follow: half a
#: 0.05 m cell's diagonal for the grid's discretisation plus room for the
#: follower's tracking error
PLAN_MARGIN = 0.07
#: a tree planner's iterations for a simulation's plan on a map, unless given: a maze's corridors
#: need far more samples than the 5000 of a plan in the open (the README's 10 x 10 maze: 60 000)
MAP_TREE_ITERATIONS = 60_000
#: most cells on each side of a point that :func:`margin_room` scans on a map
MAX_ROOM_WINDOW = 512
#: [m] sensed points farther than this from every static obstacle are news
UNEXPLAINED = 0.05
#: [m] radius of the obstacle a sensed point stands for in a replan
POINT_RADIUS = 0.05
#: [m] neighbouring unexplained points (in scan order) farther apart start a new cluster
CLUSTER_GAP = 0.15
#: [m] a cluster's centre moving less than this between scans is the same obstacle
MATCH_RADIUS = 0.5
#: [s] how far ahead the follower predicts a sensed obstacle's motion
HORIZON = 3.0
#: [m/s] slower clusters count as standing still
STILL = 0.05


def plan_path(scene_world, robot_radius: float, start, goal, planner: Optional[str] = None,
              sampler: str = "uniform", seed: Any = 0, extra=(), params: Optional[dict] = None):
    """A path for a disc of ``robot_radius`` (plus :data:`PLAN_MARGIN`), or
    the failed planner Result. ``extra`` obstacles join a geometric world."""
    from ..planning import is_grid_planner

    # A start (or goal) the robot itself fits at is valid for every planner, A* on the inflated grid
    # and RRT* on exact geometry alike: the margin gives way there (a fixed margin made the same start
    # INVALID_START for RRT* and not for A*, whose inflation is measured between cell centres)
    room = margin_room(scene_world, robot_radius, [start[:2], goal])
    on_map = isinstance(scene_world, OccupancyGrid)
    # the default planner: A* on a map, RRT* on shapes ("" is a name no registry holds, not the default)
    planner = ("astar" if on_map else "rrt_star") if planner is None else planner
    if on_map and is_grid_planner(planner):
        from ..grid import plan_world

        inflated = scene_world.inflate(robot_radius + PLAN_MARGIN)
        ends = scene_world.world_to_cell(np.array([start[:2], goal], float))
        inside = scene_world.contains(ends)
        blocked = inflated.blocked.copy()
        # the start and goal cells stay open where only the margin closed them (the robot fits there)
        for (cx, cy), ok in zip(ends, inside):
            if ok and not scene_world.blocked[cy, cx]:
                blocked[cy, cx] = False
        result = plan_world(inflated.with_blocked(blocked), start[:2], goal, algorithm=planner, smooth=True)
    elif on_map:  # a tree planner on the map's exact cells
        from ..planning import plan

        settings = {"max_iter": MAP_TREE_ITERATIONS, **(params or {})}
        result = plan(scene_world, planner=planner, sampler=sampler, start=tuple(start[:2]), goal=tuple(goal),
                      seed=seed, robot_radius=robot_radius + min(PLAN_MARGIN, room), **settings)
    else:
        from ..planning import plan

        world = replace(scene_world, start=tuple(start[:2]), goal=tuple(goal),
                        obstacles=tuple(scene_world.obstacles) + tuple(extra),
                        robot_radius=robot_radius + min(PLAN_MARGIN, room), goal_tolerance=0.0)
        settings = dict(params or {})
        if is_grid_planner(planner):
            settings.setdefault("smooth", True)  # as on maps: a follower wants few waypoints, not every cell
        result = plan(world, planner=planner, sampler=sampler, seed=seed, **settings)
    if not result.success:
        return result
    path = np.asarray(result.path, float)
    path[0], path[-1] = start[:2], goal
    return path


def margin_room(scene_world, robot_radius: float, points) -> float:
    """How much the robot's disc may grow at every one of ``points`` before it
    touches an obstacle (or, on a map, a blocked or unknown cell or the map's
    edge), less a micrometre; 0 when it already touches."""
    pts = np.asarray(points, float).reshape(-1, 2)
    if isinstance(scene_world, OccupancyGrid):
        res = scene_world.resolution
        reach = robot_radius + PLAN_MARGIN + res
        closed = scene_world.blocked | scene_world.unknown
        best = np.inf
        k = int(np.ceil(reach / res)) + 1
        if k > MAX_ROOM_WINDOW:  # cells far finer than the robot: keep the fixed margin (no window scan)
            return PLAN_MARGIN
        for p in pts:
            (cx, cy), = scene_world.world_to_cell([p])
            xs = np.arange(max(cx - k, -1), min(cx + k, scene_world.width) + 1)
            ys = np.arange(max(cy - k, -1), min(cy + k, scene_world.height) + 1)
            if len(xs) == 0 or len(ys) == 0:
                return 0.0
            gx, gy = np.meshgrid(xs, ys)
            inside = (gx >= 0) & (gy >= 0) & (gx < scene_world.width) & (gy < scene_world.height)
            hit = ~inside.copy()
            hit[inside] = closed[gy[inside], gx[inside]]
            if not hit.any():
                continue
            local = (p - np.asarray(scene_world.origin[:2])) @ scene_world._rotation() / res  # in cells
            dx = np.maximum(0.0, np.maximum(gx[hit] - local[0], local[0] - gx[hit] - 1))
            dy = np.maximum(0.0, np.maximum(gy[hit] - local[1], local[1] - gy[hit] - 1))
            best = min(best, float(np.hypot(dx, dy).min()) * res)
        clearance = best
    else:
        from .scene import Scene

        # the disc's distance to the nearest obstacle (the bounds do not count)
        clearance = robot_radius + float(np.min(Scene(scene_world, robot_radius).clearances(pts, np.zeros(len(pts)))))
    return max(0.0, clearance - robot_radius - 1e-6) if np.isfinite(clearance) else PLAN_MARGIN


class Replanner:
    """Checks the path ahead against sensed points and plans again.

    Parameters
    ----------
    scene_world : World or OccupancyGrid
    robot_radius : float
    goal : (x, y)
    planner, sampler : str, optional
        As for the first plan.
    sense_range : float
        Sensed points farther than this (m) from the robot are ignored.
    """

    def __init__(self, scene_world, robot_radius: float, goal, planner: Optional[str] = None,
                 sampler: str = "uniform", sense_range: float = 3.0, params: Optional[dict] = None) -> None:
        self.is_grid = isinstance(scene_world, OccupancyGrid)
        if self.is_grid:
            self.world = scene_world
        else:
            static = tuple(o for o in scene_world.obstacles if o.motion is None)
            self.world = replace(scene_world, obstacles=static)
            self._static = pack_geometry(static, 0.0, scene_world.bounds.as_array())
        self.radius, self.goal = float(robot_radius), tuple(float(v) for v in goal)
        self.planner, self.sampler, self.params = planner, sampler, params
        self.sense_range = sense_range
        self.count = 0  #: replans made
        self.paths: list = []  #: each new path found, from the pose it was planned at (for drawing)
        self._tracks: list = []  # (centre, velocity, points) per cluster of the last scan
        self.threat: Optional[tuple] = None  #: (centre, velocity) of an obstacle about to run into the robot
        self._t_last = -np.inf

    def news(self, pose, points) -> np.ndarray:
        """The sensed points near the robot that the static world does not explain."""
        if points is None or len(points) == 0 or self.is_grid:
            return np.empty((0, 2))
        p = np.asarray(points, float)
        near = p[np.hypot(p[:, 0] - pose[0], p[:, 1] - pose[1]) < self.sense_range]
        if len(near) == 0:
            return near
        return near[clearance_batch(np.ascontiguousarray(near), self._static) > UNEXPLAINED]

    def observe(self, t: float, pose, points) -> None:
        """Track what the map does not explain: the unexplained points split
        into clusters (neighbours in scan order closer than
        :data:`CLUSTER_GAP`), each matched to the nearest cluster of the last
        scan to estimate its velocity."""
        news = self.news(pose, points)
        clusters = []
        if len(news):
            cut = np.flatnonzero(np.hypot(*np.diff(news, axis=0).T) > CLUSTER_GAP) + 1
            clusters = [c for c in np.split(news, cut) if len(c)]
        tracked = []
        for c in clusters:
            centre = c.mean(axis=0)
            v = np.zeros(2)
            if self._tracks and t > self._t_last:
                prev = min(self._tracks, key=lambda tr: float(np.hypot(*(tr[0] - centre))))
                if np.hypot(*(prev[0] - centre)) < MATCH_RADIUS:
                    v = 0.5 * prev[1] + 0.5 * (centre - prev[0]) / (t - self._t_last)
            tracked.append((centre, v, c))
        self._tracks, self._t_last = tracked, t

    def blocked(self, pose, ahead: np.ndarray, points=None) -> bool:
        """Whether what the LiDAR sees, moved on at its estimated velocity
        over the next :data:`HORIZON` seconds, comes within the robot's
        footprint (plus half the planning margin) of the polyline ``ahead``.
        A moving obstacle whose sweep covers the robot itself sets
        :attr:`threat` to its centre and velocity: stopping there would let it run into
        the robot, so the follower gets out of its way instead."""
        self.threat = None
        if len(ahead) < 2 or not self._tracks:
            return False
        from .polyline import distance_to_polyline

        reach = self.radius + 0.5 * PLAN_MARGIN
        here = np.asarray(pose[:2], float)
        blocked = False
        for centre, v, pts in self._tracks:
            moving = float(np.hypot(*v)) > STILL
            taus = np.linspace(0.0, HORIZON, 7) if moving else np.zeros(1)
            sweep = (pts[None, :, :] + taus[:, None, None] * v[None, None, :]).reshape(-1, 2)
            if moving and np.min(np.hypot(sweep[:, 0] - here[0], sweep[:, 1] - here[1])) < reach:
                self.threat = (centre, v)
                return True
            blocked = blocked or bool(np.min(distance_to_polyline(sweep, ahead)) < reach)
        return blocked

    def plan(self, pose, points, seed: Any = 0) -> Optional[np.ndarray]:
        """A new path from ``pose`` around the unexplained points, or None."""
        self.count += 1
        news = self.news(pose, points)
        # points touching the robot already would make the start invalid: the path leaves them behind
        keep = np.hypot(news[:, 0] - pose[0], news[:, 1] - pose[1]) > self.radius + PLAN_MARGIN + POINT_RADIUS
        extra = tuple(Circle((float(x), float(y)), POINT_RADIUS) for x, y in news[keep])
        path = plan_path(self.world, self.radius, pose, self.goal, self.planner, self.sampler,
                         seed=self.count + 1000 * (seed if isinstance(seed, int) else 0), extra=extra,
                         params=self.params)
        if not isinstance(path, np.ndarray):
            return None
        self.paths.append(path)
        return path
