"""What the simulator needs of a world: footprint collisions and LiDAR scans,
for geometric worlds and occupancy grids alike."""

from __future__ import annotations

import math
from typing import Any, Union

import numpy as np
from numba import njit

from ..grid.occupancy import OccupancyGrid
from ..world import World
from ..world.geometry import pack_geometry, segment_free


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


class Scene:
    """A world (geometric or grid) seen by a robot of radius ``radius``.

    ``free_motion(a, b)`` is True when the robot's disc sweeps from a to b
    without touching an obstacle or leaving the world.
    """

    def __init__(self, world: Union[World, OccupancyGrid], radius: float) -> None:
        self.world = world
        self.radius = float(radius)
        self.is_grid = isinstance(world, OccupancyGrid)
        if self.is_grid:
            self._origin = np.asarray(world.origin, float)
        else:
            self._geom = pack_geometry(world.obstacles, self.radius, world.bounds.as_array())

    def free_motion(self, a, b) -> bool:
        if self.is_grid:
            return not disc_hits_grid(b[0], b[1], self.radius, self.world.blocked, self._origin,
                                      self.world.resolution)
        return bool(segment_free(a[0], a[1], b[0], b[1], self._geom))

    def free(self, p) -> bool:
        return self.free_motion(p, p)

    def describe(self, p) -> str:
        where = f"({p[0]:g}, {p[1]:g})"
        if self.is_grid:
            return f"{where} overlaps a blocked cell or leaves the map (robot radius {self.radius:g} m)"
        return f"{where} is within the robot radius {self.radius:g} m of an obstacle or outside the bounds"


def load_scene_world(source: Any) -> Union[World, OccupancyGrid]:
    """A World (scene name or world YAML) or an OccupancyGrid (map_server YAML
    or Moving AI .map): map files are told apart by their keys."""
    if isinstance(source, (World, OccupancyGrid)):
        return source
    from pathlib import Path

    import yaml

    from ..grid.mapio import load_map
    from ..world import load_world

    path = Path(str(source))
    if path.suffix == ".map":
        return load_map(path)
    if path.is_file() and path.suffix in (".yaml", ".yml"):
        try:
            data = yaml.safe_load(path.read_text())
        except yaml.YAMLError:
            data = None
        if isinstance(data, dict) and "image" in data:
            return load_map(path)
    return load_world(source)
