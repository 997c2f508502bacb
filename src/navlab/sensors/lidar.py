"""A 2D LiDAR: exact scans of geometric worlds and occupancy grids, with
range-dependent noise models (the RPLiDAR A1's by default when noisy)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Optional, Union

import numpy as np

from ..errors import ParameterError
from ..registry import Registry
from . import raycast as R

NOISE_MODELS: Registry[Callable[..., "NoiseModel"]] = Registry("lidar noise model")


class NoiseModel:
    """Range noise: ``apply(ranges, rng)`` returns noisy copies of the finite
    readings (the caller then applies the range limits)."""

    def sigma(self, ranges: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def apply(self, ranges: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        finite = np.isfinite(ranges)
        out = ranges.copy()
        out[finite] += self.sigma(ranges[finite]) * rng.standard_normal(int(finite.sum()))
        return out


@NOISE_MODELS.register("rplidar_a1")
class RPLidarA1Noise(NoiseModel):
    """The RPLiDAR A1M8 datasheet accuracy: ±1% of the range up to 3 m, ±2%
    from 3 to 5 m, ±2.5% beyond. navlab reads "±a%" as a Gaussian error with
    σ = a/2 % (95% of readings inside the datasheet band).

    The seed measured mean absolute errors of 2.23% at 0.05–0.95 m and 5.38%
    at 1–12 m on its unit, two to four times the datasheet's band (σ = 0.5%
    gives a mean absolute error of 0.4%); pass ``scale`` to match a worse
    unit (``scale=5.6`` reproduces 2.23% at short range).
    """

    def __init__(self, scale: float = 1.0) -> None:
        if not scale > 0:
            raise ParameterError(f"noise scale must be positive, got {scale!r}")
        self.scale = scale

    def sigma(self, ranges: np.ndarray) -> np.ndarray:
        band = np.where(ranges <= 3.0, 0.01, np.where(ranges <= 5.0, 0.02, 0.025))
        return self.scale * 0.5 * band * ranges


@NOISE_MODELS.register("gaussian")
class GaussianNoise(NoiseModel):
    """Constant σ (m) plus a part proportional to the range."""

    def __init__(self, sigma: float = 0.01, relative: float = 0.0) -> None:
        if sigma < 0 or relative < 0:
            raise ParameterError("noise sigma and relative must be ≥ 0")
        self.sigma_m, self.relative = sigma, relative

    def sigma(self, ranges: np.ndarray) -> np.ndarray:
        return self.sigma_m + self.relative * ranges


#: the most beams a scan may have (a 0.001° step; real 2-D LiDARs have a few thousand)
MAX_BEAMS = 360_000

@dataclass
class Lidar:
    """A planar scanning range finder at the robot's centre.

    Parameters
    ----------
    beams : int
        Readings per scan, evenly spread over ``fov``.
    fov : float
        Field of view (rad); 2π for a full turn.
    range_min, range_max : float
        Limits (m). Readings follow ROS REP 117: ``+inf`` when nothing is hit
        within ``range_max``, ``-inf`` when the target is closer than
        ``range_min`` (the RPLiDAR reads nothing there).
    noise : None, str or NoiseModel
        ``None`` for exact scans, ``"rplidar_a1"``, ``"gaussian"`` or a model.
    angle_min : float
        Body-frame angle of the first beam (default −fov/2 for a partial
        field of view, 0 for a full turn, as the RPLiDAR does).
    """

    beams: int = 360
    fov: float = 2.0 * math.pi
    range_min: float = 0.15
    range_max: float = 12.0
    noise: Union[None, str, NoiseModel] = None
    angle_min: Optional[float] = None
    angles: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if isinstance(self.beams, bool) or not isinstance(self.beams, int) or not 1 <= self.beams <= MAX_BEAMS:
            raise ParameterError(f"beams must be an integer from 1 to {MAX_BEAMS}, got {self.beams!r}")
        if not 0 < self.fov <= 2 * math.pi + 1e-12:
            raise ParameterError(f"fov must be in (0, 2π], got {self.fov!r}")
        if not 0 <= self.range_min < self.range_max:
            raise ParameterError(f"need 0 ≤ range_min < range_max, got {self.range_min}, {self.range_max}")
        if isinstance(self.noise, str):
            self.noise = NOISE_MODELS.get(self.noise)()
        elif self.noise is not None and not isinstance(self.noise, NoiseModel):  # (lidar=3 was an AttributeError)
            raise ParameterError(f"lidar noise must be a model's name ({', '.join(NOISE_MODELS.names())}) or a "
                                 f"NoiseModel, got {self.noise!r}")
        full = abs(self.fov - 2 * math.pi) < 1e-12
        start = self.angle_min if self.angle_min is not None else (0.0 if full else -self.fov / 2)
        increment = self.fov / self.beams if full else self.fov / max(self.beams - 1, 1)
        self.angles = start + increment * np.arange(self.beams)

    @property
    def angle_increment(self) -> float:
        return float(self.angles[1] - self.angles[0]) if self.beams > 1 else 0.0

    def exact(self, scene: Any, pose) -> np.ndarray:
        """Noise-free ranges (``inf`` for no return, no ``range_min`` cut)."""
        pose = np.ascontiguousarray(pose, dtype=float)
        out = np.empty(self.beams)
        if getattr(scene, "is_grid", False):  # a simulator Scene of a map
            scene = scene.world
        grid = getattr(scene, "blocked", None)
        if grid is not None:
            R.scan_grid(pose, self.angles, self.range_max, grid, np.asarray(scene.origin, float),
                        float(scene.resolution), out)
        else:
            circles, rects, verts, offsets = shapes_of(scene)
            R.scan_shapes(pose, self.angles, self.range_max, circles, rects, verts, offsets, out)
        return out

    def scan(self, scene: Any, pose, rng: Optional[np.random.Generator] = None) -> np.ndarray:
        """One scan of ``scene`` (a World, OccupancyGrid or simulator Scene) from ``pose`` (x, y, θ)."""
        ranges = self.exact(scene, pose)
        if self.noise is not None and rng is not None:
            ranges = self.noise.apply(ranges, rng)
        ranges[ranges > self.range_max] = np.inf
        ranges[ranges < self.range_min] = -np.inf
        return ranges

    def points(self, ranges: np.ndarray, pose) -> np.ndarray:
        """World coordinates of the valid readings (seed 004, eq. 18–19)."""
        out = np.empty((self.beams, 2))
        n = R.scan_points(np.ascontiguousarray(pose, dtype=float), self.angles, ranges, out)
        return out[:n]


def shapes_of(world):
    """A world's shapes packed for ray casting (un-inflated; cached on the world).
    A simulator :class:`~navlab.sim.Scene` gives its own, with the moving
    obstacles where they are at the scene's time."""
    moving = getattr(world, "lidar_shapes", None)
    if moving is not None:
        return moving
    cache = getattr(world, "__dict__", {}).get("_lidar_shapes")
    if cache is not None:
        return cache
    from ..world.geometry import pack_geometry

    circles, rects, verts, offsets, _, _ = pack_geometry(world.obstacles, 0.0, world.bounds.as_array())
    packed = (circles, rects, verts, offsets)
    try:
        object.__setattr__(world, "_lidar_shapes", packed)
    except (AttributeError, TypeError):
        pass
    return packed
