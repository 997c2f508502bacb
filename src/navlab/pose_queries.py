"""Planning between poses ``(x, y, θ)`` for robots that cannot turn in place
(issue 21): the ``motion`` setting, the heading-aware planners and their
query on any source, without warm-up.

:func:`navlab.plan` routes here when the planner is heading-aware
(``hybrid_astar``) or ``motion`` is ``dubins`` / ``reeds_shepp``.

Headings come from the query (``start=(x, y, θ)``), else from the world
(``start: [x, y, theta]`` in its file), else they point from the start to
the goal. The robot's outline comes from the ``footprint`` setting, else the
world's ``footprint``, else a disc of the world's robot radius.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from typing import Any, Dict, Optional, Tuple

import numpy as np

from .errors import ParameterError
from .registry import UnknownNameError, suggest
from .result import Result, Status
# (HYBRID_PARAMS, POSE_PLANNERS and TREE_POSE_PLANNERS here since they were first)
from .setting_names import HYBRID_PARAMS, POSE_PLANNERS, TREE_POSE_PLANNERS, car_tree_params  # noqa: F401

#: how the robot may move: any direction (today's planners), forward along
#: arcs of at least the turning radius, or forward and reverse
MOTIONS = ("holonomic", "dubins", "reeds_shepp")
#: the motions of a car-like robot, all that Hybrid A* plans for
CAR_MOTIONS = MOTIONS[1:]
#: [m] the turning radius when none is given: Nav2 Smac's ``minimum_turning_radius``
DEFAULT_TURNING_RADIUS = 0.4
#: [m] spacing of the poses at which a returned path's footprint is re-checked against the exact world
VERIFY_SPACING = 0.001


def check_motion(value: Any, allowed: Tuple[str, ...] = MOTIONS) -> str:
    """``value`` if it is one of ``allowed`` motions, else ParameterError listing them (and the nearest)."""
    if value not in allowed:
        raise ParameterError(f"motion must be one of {', '.join(allowed)}, got {value!r}."
                             + suggest(str(value), list(allowed)))
    return value


def is_pose_query(planner: str, params: Dict[str, Any]) -> bool:
    """Whether this query plans between poses (else it plans for a point robot).

    ``rrt``, ``rrt_star`` and ``informed_rrt_star`` plan between poses when
    ``motion`` is dubins or reeds_shepp; any other planner asked for it is an
    error naming the planners that can."""
    motion = params.get("motion", "holonomic" if planner not in POSE_PLANNERS else "reeds_shepp")
    # an unknown motion is told what this planner takes; holonomic has its own message below
    check_motion(motion, CAR_MOTIONS if planner in POSE_PLANNERS and motion != "holonomic" else MOTIONS)
    if planner in POSE_PLANNERS:
        if motion == "holonomic":
            raise ParameterError(f"motion: {planner} plans for a car-like robot: motion must be dubins or reeds_shepp, "
                                 "got 'holonomic'")
        return True
    if motion == "holonomic":
        return False
    if planner in TREE_POSE_PLANNERS:
        return True
    raise ParameterError(f"motion '{motion}': planner '{planner}' plans for a robot that can move in any direction; "
                         f"the planners for {motion} motion: {', '.join(POSE_PLANNERS + TREE_POSE_PLANNERS)}")


def query_poses(world) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]:
    """The start and goal poses: the world's points with :func:`query_headings`."""
    start_heading, goal_heading = query_headings(world)
    return (*world.start, start_heading), (*world.goal, goal_heading)


def query_headings(world) -> Tuple[float, float]:
    """The start and goal headings [rad]: the world's, else the direction from start to goal."""
    sx, sy = world.start
    gx, gy = world.goal
    towards = math.atan2(gy - sy, gx - sx) if (gx, gy) != (sx, sy) else 0.0
    return (towards if world.start_heading is None else world.start_heading,
            towards if world.goal_heading is None else world.goal_heading)


def declared_turning_radius(world) -> Optional[float]:
    """The turning radius a scene or world file gives for its robot
    (``meta["turning_radius"]``), or None when it names none."""
    meta = getattr(world, "meta", None)
    value = meta.get("turning_radius") if isinstance(meta, dict) else None
    return float(value) if isinstance(value, (int, float)) else None


def scene_turning_radius(world) -> float:
    """The turning radius a scene gives for its robot, else :data:`DEFAULT_TURNING_RADIUS`."""
    value = declared_turning_radius(world)
    return DEFAULT_TURNING_RADIUS if value is None else value


def query_footprint(world, value: Any):
    """The robot's outline: the ``footprint`` setting, the world's, or a disc of its robot radius."""
    from .world.footprint import Footprint

    if value is not None:
        return Footprint.from_value(value)
    if world is None:  # (a bench's check of a map world's settings, before the map is read)
        return None
    if world.footprint is not None:
        return world.footprint
    return Footprint.disc(world.robot_radius) if world.robot_radius > 0 else None


def check_radius_not_dropped(world, robot_radius, params: Dict[str, Any], planner: str) -> None:
    """Refuse a ``robot_radius`` that a pose query would drop: a ``footprint`` setting and the world's
    footprint win over it (:func:`query_footprint`), so a user's radius would otherwise vanish without a word."""
    if robot_radius is None:
        return
    disc = f"for a disc of {robot_radius:g} m give footprint={robot_radius:g} instead" if robot_radius > 0 else \
        "leave robot_radius out"
    if params.get("footprint") is not None:  # the setting wins (query_footprint)
        raise ParameterError(f"robot_radius: give footprint or robot_radius, not both ({planner} plans with the "
                             f"footprint); {disc}")
    if world.footprint is not None:
        raise ParameterError(f"robot_radius: {world.name}'s robot has its own footprint, which {planner} plans with; "
                             f"{disc}")


def _pose_grid(world, resolution):
    """The cells a heading-aware planner searches: a map's own, or the world's
    shapes rasterised with no inflation (the footprint is checked by the search)."""
    from .grid.rasterize import rasterize

    if world.occupancy is not None:
        if resolution is not None:
            raise ParameterError("resolution: a map is searched on its own cells; leave resolution out")
        grid = world.occupancy
        return replace(grid, unknown=np.zeros_like(grid.unknown)) if world.allow_unknown else grid
    return rasterize(replace(world, robot_radius=0.0), resolution)


def _query(world, planner: str, params: Dict[str, Any], valid, sampler: str = "") -> Tuple[Dict[str, Any], Any]:
    """The settings shared by every heading-aware query, checked; the rest returned as ``settings``.
    ``sampler``: a tree's, whose settings (taken from ``params`` before) a misspelt name may be meant for."""
    from .sampling.curves import check_turning_radius  # not at the top: navlab plan clutter never steers curves

    settings = dict(params)
    unknown = sorted(set(settings) - set(valid))
    if unknown:
        from .registry import parameters_of
        from .sampling.samplers import SAMPLERS
        from .setting_names import setting_hint

        # the sampler's settings are this query's too: "sigm" with the gaussian sampler was told 'sigma' was
        # the gaussian sampler's, "not of planner rrt_star" (review, session 21)
        also = ["goal_tolerance"] + (["goal_sample_rate", *parameters_of(SAMPLERS.get(sampler))] if sampler else [])
        # (Hybrid A* was told "with non-holonomic motion", which it always is: newcomer, session 22)
        motion = "" if planner in POSE_PLANNERS else f" with {settings.get('motion', 'reeds_shepp')} motion"
        budget = f" {planner}'s budget is max_expansions." if planner in POSE_PLANNERS and \
            unknown[0] in ("max_iter", "max_time") else ""  # (--max-iter: newcomer, session 22)
        raise UnknownNameError(f"unknown parameter '{unknown[0]}' for planner '{planner}'{motion}; "
                               f"valid: {', '.join(valid)}."
                               + setting_hint(unknown[0], planner, list(valid) + also, sampler) + budget)
    common = {"motion": check_motion(settings.pop("motion", "reeds_shepp")),
              "turning_radius": check_turning_radius(settings.pop(
                  "turning_radius", DEFAULT_TURNING_RADIUS if world is None else scene_turning_radius(world))),
              "footprint": query_footprint(world, settings.pop("footprint", None)),
              "resolution": settings.pop("resolution", None)}
    if common["resolution"] is not None:  # its sign and kind (the raster's own checks come after the warm-up,
        from .limits import finite_number  # and say what a tiny one would cost: 6e+300 x 6e+300 cells)

        if not finite_number("resolution", common["resolution"]) > 0:
            raise ParameterError(f"resolution must be positive, got {common['resolution']!r}")
    settings.pop("allow_unknown", None)  # already applied to the world
    return common, settings


def _invalid_endpoint(world, planner: str, common, start, goal, t0: float) -> Optional[Result]:
    footprint = common["footprint"]
    for label, pose, status in (("start", start, Status.INVALID_START), ("goal", goal, Status.INVALID_GOAL)):
        why = pose_problem(world, footprint, pose, label)
        if why is not None:
            if getattr(world, f"{label}_heading") is None:  # the heading was not given: say where it came from
                why += f" (its heading points from start to goal; give the {label} as X Y THETA for another)"
            return Result(status=status, reason=why, stats={"time_s": time.perf_counter() - t0},
                          params={"planner": planner, "motion": common["motion"],
                                  "turning_radius": common["turning_radius"], "start": list(start),
                                  "goal": list(goal), "footprint": None if footprint is None else footprint.to_value()})
    return None


def _verified(world, footprint, result: Result, map_checked: bool = False) -> Result:
    """The result, or FAILED when its path's footprint touches the exact world (a bug to report).
    ``map_checked``: the planner has re-checked its path against the map's cells itself."""
    if result.success and not (map_checked and world.occupancy is not None):
        why = footprint_hits_world(world, footprint, result)
        if why is not None:
            return replace(result, status=Status.FAILED, path=np.empty((0, 3)), cost=math.inf,
                           reason=f"internal check: {why}; please report it")
    return result


def check_pose_query(world, planner: str, params: Dict[str, Any], sampler: str = "") -> None:
    """Refuse a heading-aware query's bad settings as :func:`hybrid_query` and :func:`tree_pose_query` would,
    without planning: names, motion, turning radius, resolution, footprint, and Hybrid A*'s own settings or
    a tree's heading bins and other settings. Before the kernels load: a typo waited for their first compile
    (80 s; newcomer run, session 21).

    Parameters
    ----------
    world : World or None
        The query's world (its footprint and turning radius are the defaults); None checks the
        settings alone (a bench's map world, before its map is read).
    planner : str
        ``hybrid_astar`` or a tree planner.
    params : dict
        The query's settings, the tree's sampler's already taken out.
    sampler : str, optional
        A tree's sampler, whose settings a misspelt name may be meant for.

    Raises
    ------
    ParameterError
        Naming the first bad setting (:class:`~navlab.registry.UnknownNameError` for an unknown one).
    """
    if planner in POSE_PLANNERS:
        from .grid.hybrid_astar import check_settings

        check_settings(**_query(world, planner, params, HYBRID_PARAMS)[1])
    else:
        from .sampling.se2_planners import check_se2_settings, se2_tree_params

        settings = _query(world, planner, params, car_tree_params(), sampler)[1]
        _tree_heading_bins(settings.pop("heading_bins", 72))
        # (a car-like rrt took it and recorded it, and never read it: attack, session 22)
        if "connect_circle_dist" in settings and "connect_circle_dist" not in se2_tree_params(planner):
            raise ParameterError("connect_circle_dist: rrt does not rewire (rrt_star and informed_rrt_star take "
                                 "it); leave connect_circle_dist out")
        check_se2_settings(settings)


def _tree_heading_bins(bins: Any) -> int:
    """A tree's ``heading_bins`` (the footprint lattice's), checked."""
    if isinstance(bins, bool) or not isinstance(bins, (int, np.integer)) or not 4 <= bins <= 1440:
        raise ParameterError(f"heading_bins must be a whole number from 4 to 1440, got {bins!r}")
    return bins


def hybrid_query(world, params: Dict[str, Any]) -> Result:
    """Hybrid A* between the world's start and goal poses, on its map or on a
    raster of its shapes (cells any obstacle touches are blocked), the path
    then re-checked against the exact world.

    Parameters
    ----------
    world : World
    params : dict
        ``motion`` (dubins | reeds_shepp, default reeds_shepp),
        ``turning_radius`` [m] (default: the scene's, else 0.4, Nav2 Smac's), ``footprint``,
        ``resolution`` [m] for geometric worlds, and
        :func:`~navlab.grid.hybrid_astar.plan_hybrid`'s settings.
    """
    from .grid.hybrid_astar import plan_hybrid

    common, settings = _query(world, "hybrid_astar", params, HYBRID_PARAMS)
    t0 = time.perf_counter()
    grid = _pose_grid(world, common["resolution"])
    rasterize_s = time.perf_counter() - t0
    start, goal = query_poses(world)
    invalid = _invalid_endpoint(world, "hybrid_astar", common, start, goal, t0)
    if invalid is not None:
        return invalid
    footprint = common["footprint"]
    result = plan_hybrid(grid, start, goal, common["turning_radius"], motion=common["motion"], footprint=footprint,
                         **settings)
    result.stats["rasterize_s"] = rasterize_s
    result.stats["time_s"] = result.stats.get("time_s", 0.0) + rasterize_s
    result.params.update(start=list(start), goal=list(goal),
                         footprint=None if footprint is None else footprint.to_value())
    return _verified(world, footprint, result, map_checked=True)  # plan_hybrid re-checks with shapely


def tree_pose_query(world, planner: str, sampler, seed: Any, params: Dict[str, Any]) -> Result:
    """RRT, RRT* or Informed RRT* between poses with Dubins or Reeds–Shepp
    steering (:mod:`navlab.sampling.se2_planners`), edges checked with the
    footprint on the world's cells (as Hybrid A*), the path re-checked
    against the exact world."""
    from .sampling.curves import LETTERS, CurvePath
    from .sampling.footprint_lattice import check_turning_scale, lattice_for, robot_outline
    from .sampling.se2_planners import plan_se2_tree

    common, settings = _query(world, planner, params, car_tree_params())
    bins = _tree_heading_bins(settings.pop("heading_bins", 72))
    t0 = time.perf_counter()
    grid = _pose_grid(world, common["resolution"])
    start, goal = query_poses(world)
    invalid = _invalid_endpoint(world, planner, common, start, goal, t0)
    if invalid is not None:
        return invalid
    footprint, motion, r = common["footprint"], common["motion"], common["turning_radius"]
    vertices, disc = robot_outline(footprint)
    extent = math.hypot(grid.width, grid.height) * grid.resolution
    check_turning_scale(r, vertices, disc, grid.resolution, int(bins), extent)
    lattice = lattice_for(tuple(map(tuple, vertices.tolist())), disc, r, grid.resolution, int(bins),
                          motion == "reeds_shepp", 0.0)
    blocked = np.ascontiguousarray(grid.blocked | grid.unknown)
    ox, oy, yaw = grid.origin
    c, s = math.cos(yaw), math.sin(yaw)

    def to_grid(x, y, theta):
        return c * (x - ox) + s * (y - oy), -s * (x - ox) + c * (y - oy), theta - yaw

    result = plan_se2_tree(planner, world, sampler, lattice, blocked, to_grid, start, goal, motion, r,
                           np.random.default_rng(seed), settings)
    result.params.update(motion=motion, turning_radius=r, heading_bins=int(bins), resolution=grid.resolution,
                         start=list(start), goal=list(goal),
                         footprint=None if footprint is None else footprint.to_value())
    result.stats["time_s"] = time.perf_counter() - t0
    if result.tree is not None:  # its poses in the world's frame
        nodes = result.tree.nodes
        wx, wy = ox + c * nodes[:, 0] - s * nodes[:, 1], oy + s * nodes[:, 0] + c * nodes[:, 1]
        result.tree = replace(result.tree, nodes=np.column_stack([wx, wy, nodes[:, 2] + yaw]))
    segments = result.stats.pop("segments_raw", [])
    if result.success:
        curve = CurvePath(start, "".join(LETTERS[k] for k, _ in segments), tuple(v for _, v in segments), r)
        result.path, result.direction = curve.sample(grid.resolution)
        result.stats.update(word=curve.word, segments=list(curve.segments), cusps=curve.cusps)
    return _verified(world, footprint, result)


def footprint_hits_world(world, footprint, result: Result) -> Optional[str]:
    """Why the path's footprint overlaps an obstacle of the exact world (None
    when it does not), checked with shapely at poses :data:`VERIFY_SPACING` apart.
    On a map, against its blocked cells (:func:`~navlab.sampling.footprint_lattice.first_overlap`)."""
    from .sampling.curves import CurvePath
    from .sampling.footprint_lattice import first_overlap, robot_outline

    curve = CurvePath(tuple(result.path[0]), result.stats["word"], tuple(result.stats["segments"]),
                      float(result.params["turning_radius"]))
    poses, _ = curve.sample(VERIFY_SPACING)
    if world.occupancy is not None:
        grid = _pose_grid(world, None)
        ox, oy, yaw = grid.origin
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = poses[:, 0] - ox, poses[:, 1] - oy
        local = np.column_stack([c * dx + s * dy, -s * dx + c * dy, poses[:, 2] - yaw])
        vertices, disc = robot_outline(footprint)
        cell = first_overlap(grid.blocked | grid.unknown, grid.resolution, vertices, disc, local, 0.0)
        return None if cell is None else f"the footprint overlaps the map's blocked cell {cell} (x, y)"
    hit = first_touch(world, footprint, poses)
    if hit is None:
        return None
    k, what = hit
    return f"the footprint at ({poses[k, 0]:.3f}, {poses[k, 1]:.3f}) {what}"


def pose_problem(world, footprint, pose, label: str) -> Optional[str]:
    """Why the robot cannot stand at ``pose`` in the exact world (None when it can)."""
    hit = first_touch(world, footprint, np.array([pose], dtype=float))
    if hit is None:
        return None
    return f"the robot's footprint at the {label} pose ({pose[0]:g}, {pose[1]:g}, {pose[2]:.4g}) {hit[1]}"


def first_touch(world, footprint, poses: np.ndarray) -> Optional[Tuple[int, str]]:
    """The first of ``poses`` (N, 3) at which the footprint touches an
    obstacle of the exact world or crosses its bounds, and what it touches."""
    import shapely

    from .world.shapes import Circle, Rectangle

    if footprint is None:
        shapes = shapely.points(poses[:, :2])
    elif footprint.is_disc:
        shapes = shapely.buffer(shapely.points(poses[:, :2]), footprint.radius, quad_segs=256)
    else:
        shapes = shapely.polygons(footprint.at_many(poses))
    b = world.bounds
    found: Optional[Tuple[int, str]] = None
    outside = ~shapely.covered_by(shapes, shapely.box(b.xmin, b.ymin, b.xmax, b.ymax))
    if np.any(outside):
        # (it said "leaves", as for driving out, of a start pose never inside, and gave no bounds: review, s31)
        found = (int(np.argmax(outside)), f"crosses the world's bounds {b.text()}")
    if world.occupancy is not None:
        return found  # the map's cells are checked by the search itself
    index = shapely.STRtree(shapes)  # each obstacle meets only the poses near it
    for k, o in enumerate(world.obstacles):
        if isinstance(o, Circle):  # exact: the distance to the centre, not a polygon inside the circle
            hits = index.query(shapely.Point(o.center), predicate="dwithin", distance=o.radius)
        else:
            points = ((o.min[0], o.min[1]), (o.max[0], o.min[1]), (o.max[0], o.max[1]), (o.min[0], o.max[1])) \
                if isinstance(o, Rectangle) else o.points
            hits = index.query(shapely.Polygon(points), predicate="intersects")
        if len(hits) and (found is None or int(hits.min()) < found[0]):
            found = (int(hits.min()), f"touches {world.describe_obstacle(k)}")
    return found


__all__ = ["MOTIONS", "POSE_PLANNERS", "TREE_POSE_PLANNERS", "hybrid_query", "is_pose_query", "query_headings",
           "query_footprint", "tree_pose_query"]
