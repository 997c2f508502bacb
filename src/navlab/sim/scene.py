"""What the simulator needs of a world: footprint collisions and LiDAR scans,
for geometric worlds and occupancy grids alike, with moving obstacles where
they are at the time asked."""

from __future__ import annotations

import math
from typing import Any, List, Optional, Tuple, Union

import numpy as np

from ..grid.occupancy import OccupancyGrid
from ..jit import njit
from ..world import World
from ..world.geometry import (clearance_batch, pack_geometry, point_segment_dist2, segment_free, segment_polygon_dist2,
                              segment_rect_dist2)
from ..world.motion import track, translated

CIRCLE, RECT, POLY = 0, 1, 2
#: headings tried (5° apart, as Hybrid A*'s 72 bins) where a goal has none: can the robot stand there?
STANDING_HEADINGS = 72


@njit(cache=True)
def disc_hits_grid(px, py, radius, blocked, origin, resolution):
    """Whether a disc overlaps a blocked cell or leaves the grid (exact
    point-to-square distances)."""
    c, s = math.cos(origin[2]), math.sin(origin[2])
    rx, ry = px - origin[0], py - origin[1]
    gx = (c * rx + s * ry) / resolution
    gy = (-s * rx + c * ry) / resolution
    rr = radius / resolution
    h, w = blocked.shape
    if gx - rr < 0.0 or gy - rr < 0.0 or gx + rr > w or gy + rr > h:
        return True
    for iy in range(max(0, int(math.floor(gy - rr))), min(h, int(math.floor(gy + rr)) + 1)):
        for ix in range(max(0, int(math.floor(gx - rr))), min(w, int(math.floor(gx + rr)) + 1)):
            if blocked[iy, ix]:
                dx = max(ix - gx, 0.0, gx - (ix + 1))
                dy = max(iy - gy, 0.0, gy - (iy + 1))
                if dx * dx + dy * dy < rr * rr:
                    return True
    return False


@njit(cache=True)
def first_moving_hit(ax, ay, bx, by, off0, off1, kinds, rows, circles, rects, verts, voffsets, r2):
    """Index of the first moving obstacle the robot's disc meets while it goes
    from a to b and the obstacles move from offsets ``off0`` to ``off1``
    (both straight and uniform over the step), or −1.

    In each obstacle's own frame the robot moves on the straight segment
    (a − off0) → (b − off1), so the swept test is the static segment test
    against the obstacle's t = 0 geometry: a hit between two steps is found."""
    for j in range(kinds.shape[0]):
        pax = ax - off0[j, 0]
        pay = ay - off0[j, 1]
        pbx = bx - off1[j, 0]
        pby = by - off1[j, 1]
        k = rows[j]
        if kinds[j] == 0:
            cr = circles[k, 2]
            d2 = point_segment_dist2(circles[k, 0], circles[k, 1], pax, pay, pbx, pby)
            if d2 < cr * cr:
                return j
        elif kinds[j] == 1:
            d2 = segment_rect_dist2(pax, pay, pbx, pby, rects[k, 0], rects[k, 1], rects[k, 2], rects[k, 3])
            if d2 < r2 or d2 == 0.0:
                return j
        else:
            d2 = segment_polygon_dist2(pax, pay, pbx, pby, verts, voffsets[k], voffsets[k + 1])
            if d2 < r2 or d2 == 0.0:
                return j
    return -1


def _layout(obstacles) -> tuple:
    """(kind, row) of each obstacle in the arrays pack_geometry makes of them."""
    counts = [0, 0, 0]
    out = []
    for o in obstacles:
        kind = _kind(o)
        out.append((kind, counts[kind]))
        counts[kind] += 1
    return out


def _kind(shape) -> int:
    from ..world.shapes import Circle, Rectangle

    return CIRCLE if isinstance(shape, Circle) else RECT if isinstance(shape, Rectangle) else POLY


class Scene:
    """A world (geometric or grid) seen by a robot of radius ``radius``.

    ``free_motion(a, b)`` is True when the robot's disc sweeps from a to b
    without touching an obstacle or leaving the world, with moving obstacles
    at their t = 0 places; :meth:`hit` is the same test over a time step
    during which moving obstacles move too. :meth:`set_time` puts the moving
    obstacles where they are at a time for the LiDAR (``lidar_shapes``).
    """

    def __init__(self, world: Union[World, OccupancyGrid], radius: float, footprint=None) -> None:
        self.world = world
        self.radius = float(radius)
        self.is_grid = isinstance(world, OccupancyGrid)
        self.moving: List[int] = []  #: indices (in world.obstacles) of the moving obstacles
        self.t: float = 0.0
        #: a polygon footprint's body-frame vertices (K, 2), or None for the disc of ``radius``
        self.footprint = footprint if footprint is not None and not footprint.is_disc else None
        if self.footprint is not None:
            self._body = np.ascontiguousarray(self.footprint.vertices)
            self._reach = self.footprint.circumscribed_radius
            self.radius = self.footprint.inscribed_radius
        if self.is_grid:
            self._origin = np.asarray(world.origin, float)
            return
        obstacles = world.obstacles
        bounds = world.bounds.as_array()
        self.moving = [i for i, o in enumerate(obstacles) if o.motion is not None]
        static = [o for o in obstacles if o.motion is None]
        self._geom = pack_geometry(static, self.radius, bounds)
        moving = [obstacles[i] for i in self.moving]
        self._tracks = [track(o, world.bounds, i) for i, o in zip(self.moving, moving)]
        mgeom = pack_geometry(moving, self.radius, bounds)
        self._mgeom = (mgeom[0], mgeom[1], mgeom[2], mgeom[3])
        layout = _layout(moving)
        self._kinds = np.array([k for k, _ in layout], np.int64)
        self._rows = np.array([r for _, r in layout], np.int64)
        self._r2 = self.radius ** 2
        base = pack_geometry(obstacles, 0.0, bounds)[:4]
        self._lidar_base = base
        self.lidar_shapes = tuple(a.copy() for a in base)  #: un-inflated arrays at time ``t`` (ray casting)
        all_layout = _layout(obstacles)
        self._lidar_rows = [all_layout[i] for i in self.moving]
        self._offsets_cache: dict = {}
        self.offsets = np.zeros((len(self.moving), 2))  #: displacement of each moving obstacle at ``t``
        if self.footprint is not None:
            self._all_layout = all_layout
            self._bounds = bounds

    def _footprint_hit(self, a, b, t0: float, t1: float, twist, first: int) -> Optional[str]:
        """The footprint swept from pose a (at t0) to pose b (at t1) at ``twist`` (see
        :mod:`navlab.world.footprint_collision`): None, or who was hit, where and when."""
        contact = self._footprint_contact(a, b, t0, t1, twist, first)
        if contact is None:
            return None
        t, x, y, what = contact
        return f"collision at t = {t:.2f} s near ({x:.3f}, {y:.3f}): {what}"

    def _footprint_contact(self, a, b, t0: float, t1: float, twist, first: int):
        """:meth:`_footprint_hit`'s answer as (t, x, y, what the footprint met), or None."""
        from ..world import footprint_collision as F

        dt = t1 - t0 if t1 > t0 else 1.0
        if twist is None:
            twist = F.twist_between(a, b, dt)
        twist = np.asarray(twist, float)
        pose = np.asarray(a, float)
        if self.is_grid:
            n = F.sample_count(*twist, dt, self._reach, 0.0, F.SWEEP_SPACING)
            kind, row, k = F.sweep_first_hit_grid(self._body, pose, twist, dt, first, n, self.world.blocked,
                                                  self._origin, float(self.world.resolution))
        else:
            circles, rects, verts, voffsets = self._lidar_base
            zeros = [np.zeros((len(circles), 2)), np.zeros((len(rects), 2)), np.zeros((len(voffsets) - 1, 2))]
            off0 = [z.copy() for z in zeros]
            off1 = [z.copy() for z in zeros]
            speed = 0.0
            if self.moving:
                o0, o1 = self.offsets_at(t0), self.offsets_at(t1)
                for j, (kind, row) in enumerate(self._lidar_rows):
                    off0[kind][row], off1[kind][row] = o0[j], o1[j]
                speed = float(np.max(np.hypot(*(o1 - o0).T))) / dt
            n = F.sample_count(*twist, dt, self._reach, speed, F.SWEEP_SPACING)
            kind, row, k = F.sweep_first_hit(self._body, pose, twist, dt, first, n, circles, off0[0],
                                             off1[0], rects, off0[1], off1[1], verts, voffsets, off0[2], off1[2],
                                             self._bounds)
        if kind == F.KIND_NONE:
            return None
        t = t0 + (t1 - t0) * (k / n)
        x, y, _ = F.arc_pose(pose[0], pose[1], pose[2], *twist, dt * k / n)
        if kind == F.KIND_BOUNDS:
            # ("left the bounds" read as driving out, for a start pose that never was inside: newcomer, s30)
            edge = "the map edge" if self.is_grid else "the bounds " + self.world.bounds.text()
            what = f"the robot's footprint crossed {edge}"
        elif kind == F.KIND_CELL:
            w = self.world.blocked.shape[1]
            what = f"the robot's footprint touched blocked cell (x={row % w}, y={row // w})"
        else:
            what = f"the robot's footprint touched {self.name_obstacle(self._all_layout.index((kind, row)))}"
        return t, x, y, what

    def name_obstacle(self, index: int) -> str:
        """``obstacle 12 (circle 'unit_cylinder_12')``: see :meth:`navlab.world.World.describe_obstacle`."""
        return self.world.describe_obstacle(index)

    @property
    def dynamic(self) -> bool:
        return bool(self.moving)

    def offsets_at(self, t: float) -> np.ndarray:
        """(m, 2) displacement of each moving obstacle from its t = 0 geometry."""
        cached = self._offsets_cache.get(t)
        if cached is None:
            cached = np.array([tr.offset(t) for tr in self._tracks], float).reshape(-1, 2)
            if len(self._offsets_cache) > 4:
                self._offsets_cache.clear()
            self._offsets_cache[t] = cached
        return cached

    def set_time(self, t: float) -> None:
        """Move the LiDAR's copy of the moving obstacles to time ``t``."""
        if not self.moving or t == self.t:
            self.t = t
            return
        self.t = t
        off = self.offsets = self.offsets_at(t)
        circles, rects, verts, voffsets = self.lidar_shapes
        bc, br, bv, _ = self._lidar_base
        for j, (kind, row) in enumerate(self._lidar_rows):
            dx, dy = off[j]
            if kind == CIRCLE:
                circles[row, 0] = bc[row, 0] + dx
                circles[row, 1] = bc[row, 1] + dy
            elif kind == RECT:
                rects[row] = br[row] + (dx, dy, dx, dy)
            else:
                a, b = voffsets[row], voffsets[row + 1]
                verts[a:b] = bv[a:b] + (dx, dy)

    def hit(self, a, b, t0: float = 0.0, t1: float = 0.0, twist=None) -> Optional[str]:
        """None when the robot goes from a (at t0) to b (at t1) touching
        nothing, else who hit whom (one sentence). A polygon footprint is swept
        along the arc of ``twist`` (body vx, vy, ω; by default the arc from a to b)."""
        if self.footprint is not None:
            same = t1 == t0 and np.array_equal(np.asarray(a, float), np.asarray(b, float))
            return self._footprint_hit(a, b, t0, t1, None if same else twist, first=0 if same else 1)
        if self.is_grid:
            if disc_hits_grid(b[0], b[1], self.radius, self.world.blocked, self._origin, self.world.resolution):
                return f"collision at t = {t1:.2f} s: {self.describe(b)}"
            return None
        if not segment_free(a[0], a[1], b[0], b[1], self._geom):
            return f"collision at t = {t1:.2f} s: {self._describe_static(b)}"
        if self.moving:
            off0, off1 = self.offsets_at(t0), self.offsets_at(t1)
            j = first_moving_hit(a[0], a[1], b[0], b[1], off0, off1, self._kinds, self._rows, *self._mgeom,
                                 self._r2)
            if j >= 0:
                return self._who_hit(j, a, b, off0[j], off1[j], t1)
        return None

    def free_motion(self, a, b) -> bool:
        return self.hit(a, b) is None

    def free(self, p) -> bool:
        """Whether the robot at pose p (x, y, θ; a polygon footprint at that heading) touches nothing."""
        p = np.asarray(p, float)
        if self.footprint is not None and len(p) < 3:
            p = np.array((*p[:2], 0.0))
        return self.free_motion(p, p)

    def free_at_some_heading(self, xy, heading: Optional[float] = None) -> bool:
        """Whether the robot can stand at point ``xy``: at ``heading``, or when that is None at one of
        :data:`STANDING_HEADINGS` headings around the whole circle (a disc at any). Only half the circle,
        at 8 headings, was tried: a footprint that sticks out forward fits a corner facing one way only,
        and such a goal was refused (attack, session 23)."""
        if heading is not None:
            return self.free(np.array((*xy[:2], heading)))
        if self.footprint is None:
            return self.free(np.array((*xy[:2], 0.0)))
        return any(self.free(np.array((*xy[:2], h)))
                   for h in np.linspace(0.0, 2.0 * math.pi, STANDING_HEADINGS, endpoint=False))

    def obstacles_at(self, t: float) -> list:
        """Every obstacle's shape at time ``t`` (moving ones translated)."""
        shapes = list(self.world.obstacles)
        for j, (i, off) in enumerate(zip(self.moving, self.offsets_at(t))):
            shapes[i] = translated(shapes[i], *off)
        return shapes

    def clearances(self, points, times) -> np.ndarray:
        """Distance (m) from the robot's disc at each point to the nearest
        obstacle where it is at the matching time (negative when they
        overlap; bounds do not count; grids: nan)."""
        p = np.ascontiguousarray(np.asarray(points, float)[:, :2])
        if self.is_grid:
            return np.full(len(p), math.nan)
        best = clearance_batch(p, self._geom)
        bounds = self.world.bounds.as_array()
        for j, index in enumerate(self.moving):
            single = pack_geometry((self.world.obstacles[index],), self.radius, bounds)
            off = np.array([self.offsets_at(float(t))[j] for t in times])
            best = np.minimum(best, clearance_batch(np.ascontiguousarray(p - off), single))
        return best - self.radius

    def _who_hit(self, j: int, a, b, off0, off1, t1: float) -> str:
        index = self.moving[j]
        shape = self.world.obstacles[index]
        kind = type(shape).__name__.lower()
        # who closed the gap: the robot's and the obstacle's speed towards each other
        x0, y0, x1, y1 = shape.bbox()
        # (from where both were at the start of the step: a fast obstacle may have passed the robot by its end)
        centre = np.array(((x0 + x1) / 2 + off0[0], (y0 + y1) / 2 + off0[1]))
        u = centre - np.asarray(a[:2], float)
        u /= max(float(np.hypot(*u)), 1e-12)
        robot = float(np.dot(np.asarray(b[:2], float) - np.asarray(a[:2], float), u))
        obstacle = float(np.dot(np.asarray(off1, float) - np.asarray(off0, float), -u))
        at = f"at t = {t1:.2f} s near ({b[0]:.3f}, {b[1]:.3f})"
        if obstacle >= robot:
            return f"moving obstacle {index} ({kind}) hit the robot {at}"
        return f"the robot hit moving obstacle {index} ({kind}) {at}"

    def _describe_static(self, p) -> str:
        b = self.world.bounds
        r = self.radius
        if not (b.xmin <= p[0] <= b.xmax and b.ymin <= p[1] <= b.ymax):
            return f"the robot left the bounds at ({p[0]:g}, {p[1]:g})"
        near = self._nearest_static(p)
        if near is not None and near[1] <= r + 1e-6:
            return f"the robot hit obstacle {near[0]} ({self._kind(near[0])}) at ({p[0]:g}, {p[1]:g})"
        return self.describe(p)

    def _nearest_static(self, p) -> Optional[Tuple[int, float]]:
        """The nearest obstacle that does not move, and its distance from ``p`` (0 inside it); None if none."""
        import shapely

        point = shapely.Point(p[0], p[1])
        near = [(i, _as_shapely(o).distance(point)) for i, o in enumerate(self.world.obstacles) if o.motion is None]
        return min(near, key=lambda x: x[1]) if near else None

    def _kind(self, i: int) -> str:
        return type(self.world.obstacles[i]).__name__.lower()

    def describe(self, p) -> str:
        where = f"({p[0]:g}, {p[1]:g})"
        # a point outside the bounds is said so, whatever the robot's shape (a footprint's "left the bounds"
        # gave no bounds: newcomer, session 30)
        if not self.is_grid and not self.world.bounds.contains(np.asarray(p[:2], float))[0]:
            return f"{where} is outside the bounds {self.world.bounds.text()}"
        if self.footprint is not None:  # a point (x, y) as the robot facing +x there
            pose = (p[0], p[1], p[2] if len(p) > 2 else 0.0)
            contact = self._footprint_contact(pose, pose, 0.0, 0.0, None, 0)
            return f"{where} is free" if contact is None else f"at {where} {contact[3]}"
        if self.is_grid:
            return f"{where} overlaps a blocked cell or crosses the map edge (robot radius {self.radius:g} m)"
        b = self.world.bounds
        near = self._nearest_static(p)
        if near is not None and near[1] <= self.radius + 1e-6:
            i, gap = near
            if gap == 0.0:
                return f"{where} is inside obstacle {i} ({self._kind(i)})"
            return (f"{where} is within the robot radius {self.radius:g} m of obstacle {i} ({self._kind(i)}; "
                    f"clearance {gap:.4g} m)")
        edge = min(p[0] - b.xmin, b.xmax - p[0], p[1] - b.ymin, b.ymax - p[1])
        if edge <= self.radius + 1e-6:
            return f"{where} is within the robot radius {self.radius:g} m of the bounds {b.text()}"
        return f"{where} is within the robot radius {self.radius:g} m of an obstacle"  # a moving one, where it is then


def _as_shapely(shape):
    import shapely

    from ..world.shapes import Circle, Rectangle

    if isinstance(shape, Circle):
        return shapely.Point(shape.center).buffer(shape.radius, quad_segs=64)
    if isinstance(shape, Rectangle):
        return shapely.box(*shape.min, *shape.max)
    return shapely.Polygon(shape.points)


def load_scene_world(source: Any) -> Union[World, OccupancyGrid]:
    """A World (scene name, world YAML or Gazebo SDF) or an OccupancyGrid (map_server YAML
    or Moving AI .map), told apart as ``navlab plan`` tells them
    (:func:`navlab.world.sources.source_kind`: a text file or a lone map image was a
    "world file" here, with that reader's errors, where plan said what it is: newcomer, session 31)."""
    from ..grid.mapio import load_map
    from ..world import load_world
    from ..world.sources import source_kind

    kind = source_kind(source)
    if kind in ("world", "occupancy"):
        return source
    if kind in ("ros_map", "movingai_map"):
        return load_map(source)
    return load_world(source)
