"""Built-in scenes, registered by name (``navlab list`` shows them).

- ``pythonrobotics``: the classic Python RRT* demo (PythonRobotics,
  A. Sakai et al.), whose parameter names the seed 000 LabVIEW program shares.
- ``clutter``, ``squarefield``, ``trap``: navlab's canonical versions of the
  seed 000 environments (the seed gives no geometry), sized so that paths are
  10–25 m like the seed's 12.7–20.8 m.
- ``growth_ratio``: the seed 003 set-up, root (1, 5), goal (5, 6), p_min 0.5
  (as ``goal_tolerance``) in an empty 10 m × 10 m workspace.
- ``one_obstacle``: seed 004's open floor with one cylinder between the
  start and the goal (the ROS 2 omni-robot demo and test).
- ``crossing``: a 10 m × 4 m corridor that a cylinder crosses at 0.2 m/s,
  back and forth across the robot's way: the dynamic-environment example
  (seed 004's moving obstacles).

Pictures: ``docs/scenes.md``.
"""

from __future__ import annotations

from typing import Callable

from ..registry import Registry
from .motion import parse_motion
from .shapes import Circle, Polygon, Rectangle
from .world import Bounds, World

SCENES: Registry[Callable[[], World]] = Registry("scene")


@SCENES.register("pythonrobotics")
def pythonrobotics() -> World:
    """PythonRobotics' RRT* demo: 8 circles, robot radius 0.8 m; optimum 21.9987 m."""
    circles = [(5, 5, 1), (3, 6, 2), (3, 8, 2), (3, 10, 2), (7, 5, 2), (9, 5, 2), (8, 10, 1), (6, 12, 1)]
    return World(
        name="pythonrobotics",
        bounds=Bounds(-2.0, 15.0, -2.0, 15.0),
        start=(0.0, 0.0),
        goal=(6.0, 10.0),
        obstacles=tuple(Circle((x, y), r) for x, y, r in circles),
        robot_radius=0.8,
    )


# 34 scattered circles, boxes and star-shaped polygons (drawn once from
# numpy.random.default_rng(7), then frozen here so the scene never changes; the polygons are
# known simple: tests/world/test_world_validation.py checks them with shapely).
_CLUTTER = (
    Circle((4.75, 10.11), 0.3),
    Polygon._known_simple(((10.94, 6.45), (10.84, 6.35), (10.35, 5.87), (10.17, 5.62), (10.50, 5.49))),
    Circle((8.66, 0.98), 0.31),
    Rectangle((6.38, 10.18), (7.28, 10.99)),
    Circle((4.09, 0.63), 0.38),
    Rectangle((3.31, 4.03), (3.71, 5.10)),
    Rectangle((11.09, 7.30), (12.09, 7.77)),
    Circle((5.04, 2.15), 0.63),
    Circle((13.23, 6.99), 0.54),
    Rectangle((9.08, 1.86), (9.83, 2.45)),
    Circle((2.21, 11.15), 0.39),
    Rectangle((2.07, 9.23), (3.22, 10.36)),
    Rectangle((2.25, 2.20), (3.39, 3.04)),
    Rectangle((5.41, 4.81), (6.00, 5.24)),
    Polygon._known_simple(((7.39, 6.61), (6.67, 6.89), (6.85, 6.07))),
    Polygon._known_simple(((8.85, 5.77), (8.76, 4.92), (9.65, 4.77))),
    Rectangle((11.79, 1.96), (12.94, 2.36)),
    Circle((11.19, 0.66), 0.55),
    Rectangle((7.12, 8.20), (7.70, 8.76)),
    Polygon._known_simple(((8.08, 4.84), (7.59, 4.45), (8.89, 4.02), (8.86, 4.16))),
    Rectangle((8.54, 10.83), (9.20, 11.55)),
    Circle((8.85, 7.49), 0.37),
    Circle((6.14, 8.90), 0.63),
    Circle((4.16, 3.23), 0.38),
    Rectangle((1.22, 6.52), (1.75, 7.47)),
    Rectangle((3.17, 6.30), (3.61, 7.34)),
    Rectangle((10.42, 3.43), (11.51, 4.47)),
    Circle((10.59, 10.21), 0.38),
    Circle((9.28, 9.64), 0.45),
    Circle((7.74, 2.87), 0.4),
    Circle((6.72, 1.40), 0.6),
    Polygon._known_simple(((12.95, 5.38), (12.39, 4.32), (12.52, 4.33), (12.86, 4.05), (12.94, 4.74))),
    Circle((1.41, 3.95), 0.42),
    Rectangle((10.88, 8.33), (11.85, 9.41)),
)


@SCENES.register("clutter")
def clutter() -> World:
    """Many scattered obstacles of every type; start (1, 1), goal (12.5, 10.5)."""
    return World(
        name="clutter",
        bounds=Bounds(0.0, 14.0, 0.0, 12.0),
        start=(1.0, 1.0),
        goal=(12.5, 10.5),
        obstacles=_CLUTTER,
        robot_radius=0.1,
    )


@SCENES.register("squarefield")
def squarefield() -> World:
    """A regular 4 × 4 field of 1.2 m square blocks ("SquareField BW")."""
    half = 0.6
    blocks = tuple(
        Rectangle((cx - half, cy - half), (cx + half, cy + half))
        for cx in (2.0, 4.0, 6.0, 8.0)
        for cy in (2.0, 4.0, 6.0, 8.0)
    )
    return World(
        name="squarefield",
        bounds=Bounds(0.0, 10.0, 0.0, 10.0),
        start=(0.5, 0.5),
        goal=(9.5, 9.5),
        obstacles=blocks,
        robot_radius=0.15,
    )


@SCENES.register("trap")
def trap() -> World:
    """A bug trap: a U of walls around the start, open away from the goal."""
    walls = (
        Rectangle((3.0, 8.6), (8.0, 9.0)),  # top
        Rectangle((3.0, 3.0), (8.0, 3.4)),  # bottom
        Rectangle((7.6, 3.0), (8.0, 9.0)),  # closed side, facing the goal
        Circle((12.0, 8.0), 0.8),
        Circle((12.5, 4.0), 0.8),
        Rectangle((14.0, 5.0), (14.6, 7.5)),
    )
    return World(
        name="trap",
        bounds=Bounds(0.0, 18.0, 0.0, 12.0),
        start=(6.0, 6.0),
        goal=(16.0, 6.0),
        obstacles=walls,
        robot_radius=0.15,
    )


@SCENES.register("growth_ratio")
def growth_ratio() -> World:
    """Seed 003: root (1, 5), goal (5, 6), p_min = 0.5 m, no obstacles."""
    return World(
        name="growth_ratio",
        bounds=Bounds(0.0, 10.0, 0.0, 10.0),
        start=(1.0, 5.0),
        goal=(5.0, 6.0),
        goal_tolerance=0.5,
    )


@SCENES.register("one_obstacle")
def one_obstacle() -> World:
    """Seed 004's open floor with one 0.15 m cylinder half way to the goal
    (3, 0), 2 cm off the line (an exactly symmetric field has a saddle the
    potential field would stop on)."""
    return World(
        name="one_obstacle",
        bounds=Bounds(-1.0, 4.0, -1.5, 1.5),
        start=(0.0, 0.0),
        goal=(3.0, 0.0),
        obstacles=(Circle((1.5, 0.02), 0.15),),
        robot_radius=0.0,
    )


@SCENES.register("crossing")
def crossing() -> World:
    """A corridor from (1, 2) to (9, 2) that a 0.3 m cylinder crosses at
    0.2 m/s, from (5, 0.6) to (5, 3.5) and back, again and again: a robot
    going straight meets it half way (replanning and potential fields dodge
    it)."""
    mover = Circle((5.0, 0.6), 0.3, motion=parse_motion({"waypoints": [[5, 3.5], [5, 0.5]], "speed": 0.2}))
    return World(
        name="crossing",
        bounds=Bounds(0.0, 10.0, 0.0, 4.0),
        start=(1.0, 2.0),
        goal=(9.0, 2.0),
        obstacles=(mover,),
        robot_radius=0.0,
    )


# --- scenes that need heading (issue 21): poses, a footprint and a turning radius ---------------------
# ``meta["turning_radius"]`` is the scene's robot's (the heading-aware planners' default for it).

#: navigation2 #5884's robot: 0.9 × 0.62 m, its origin at the centre
AISLE_ROBOT = ((-0.45, -0.31), (0.45, -0.31), (0.45, 0.31), (-0.45, 0.31))
#: a compact car, 4.4 × 1.8 m, its origin at the middle of the rear axle (1.0 m from the back)
CAR = ((-1.0, -0.9), (3.4, -0.9), (3.4, 0.9), (-1.0, 0.9))


def _walls_around(bounds: Bounds, free):
    """Rectangles filling ``bounds`` except the union of the ``free`` (x0, x1, y0, y1)
    boxes: the cells of the grid drawn by every box edge that lie in no free box."""
    xs = sorted({bounds.xmin, bounds.xmax, *(v for r in free for v in r[:2])})
    ys = sorted({bounds.ymin, bounds.ymax, *(v for r in free for v in r[2:])})
    cells = []
    for x0, x1 in zip(xs, xs[1:]):
        for y0, y1 in zip(ys, ys[1:]):
            cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            if not any(a <= cx <= b and c <= cy <= d for a, b, c, d in free):
                cells.append(Rectangle((x0, y0), (x1, y1)))
    return tuple(cells)


@SCENES.register("narrow_aisle")
def narrow_aisle() -> World:
    """navigation2 #5884: a 0.9 × 0.62 m robot in a 1.1 m wide aisle with a 90°
    turn, from (1.2, 1.55) facing east to (4.05, 4.6) facing north; turning radius 0.5 m."""
    bounds = Bounds(0.0, 6.0, 0.0, 6.0)
    return World(
        name="narrow_aisle",
        bounds=bounds,
        start=(1.2, 1.55, 0.0),
        goal=(4.05, 4.6, 1.5707963267948966),
        obstacles=_walls_around(bounds, [(0.5, 4.6, 1.0, 2.1), (3.5, 4.6, 2.1, 5.5)]),
        footprint=AISLE_ROBOT,
        meta={"turning_radius": 0.5},
    )


@SCENES.register("parking")
def parking() -> World:
    """A car (4.4 × 1.8 m, turning radius 4.5 m) in the lane of a car park must
    back into the one free 2.8 m bay of a row against a wall, ending nose out
    (facing north): forward-only motion cannot park it."""
    bays = [(1.0 + 2.8 * k, 1.0 + 2.8 * (k + 1)) for k in range(9)]
    free_bay = 5
    parked = tuple(Rectangle((x0 + 0.45, 0.8), (x1 - 0.45, 5.2)) for k, (x0, x1) in enumerate(bays) if k != free_bay)
    wall = Rectangle((0.0, 0.0), (28.0, 0.4))
    opposite = tuple(Rectangle((x0 + 0.45, 12.8), (x1 - 0.45, 17.2)) for x0, x1 in bays)
    bay_x = 0.5 * sum(bays[free_bay])
    return World(
        name="parking",
        bounds=Bounds(0.0, 28.0, 0.0, 18.0),
        start=(3.0, 9.0, 0.0),
        goal=(bay_x, 2.0, 1.5707963267948966),
        obstacles=(wall, *parked, *opposite),
        footprint=CAR,
        meta={"turning_radius": 4.5},
    )


@SCENES.register("trap_car")
def trap_car() -> World:
    """The bug trap with a car-like robot (0.9 × 0.62 m, turning radius 1 m)
    that starts at (5, 6) facing the trap's closed side: it must turn round
    inside the U to leave it; goal (16.5, 6) facing east."""
    base = trap()
    return World(
        name="trap_car",
        bounds=base.bounds,
        start=(5.0, 6.0, 0.0),
        goal=(16.5, 6.0, 0.0),  # 0.5 m further than trap's: room to turn in past the last obstacle
        obstacles=base.obstacles,
        footprint=AISLE_ROBOT,
        meta={"turning_radius": 1.0},
    )
