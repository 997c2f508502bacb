"""The Smac side of ``bench_hybrid.py --smac-maps --smac-driver PATH``: costmaps, the driver process, the check.

Nav2 Smac's Hybrid-A* runs in ``smac_driver`` (built by ``benchmarks/smac/build.sh`` from a Nav2
checkout); this module hands it navlab's maps as Nav2 costmaps, sends it queries one at a time
(so the caller can interleave them with navlab's) and checks the poses it returns against the
blocked cells with shapely, independently of both planners.
"""

from __future__ import annotations

import json
import math
import subprocess
import tempfile
from pathlib import Path

import numpy as np

#: Nav2's cost values (nav2_costmap_2d/cost_values.hpp)
LETHAL, INSCRIBED = 254, 253
#: Nav2's inflation layer defaults (nav2_costmap_2d/plugins/inflation_layer.cpp at a3a97043)
INFLATION_RADIUS, COST_SCALING_FACTOR = 0.55, 10.0  # [m], [1/m]


def binary_costs(blocked: np.ndarray) -> np.ndarray:
    """navlab's map as a Nav2 costmap with no inflation layer: blocked cells lethal, the rest free."""
    return np.where(blocked, LETHAL, 0).astype(np.uint8)


def inflated_costs(blocked: np.ndarray, res: float, inscribed_radius: float,
                   radius: float = INFLATION_RADIUS, scaling: float = COST_SCALING_FACTOR) -> np.ndarray:
    """Blocked cells lethal, the others Nav2's inflation cost of their distance to the nearest
    blocked cell centre (InflationLayer::computeCost: inscribed within ``inscribed_radius``, then
    252 exp(-scaling (d - inscribed_radius)), 0 beyond ``radius``), the distance from scipy's exact
    Euclidean transform between cell centres (Nav2's layer computes its own distance transform and
    looks costs up in a table at 1/COST_LUT_PRECISION-cell steps, so a few cells may differ by one)."""
    from scipy.ndimage import distance_transform_edt

    d = distance_transform_edt(~blocked) * res  # [m]
    cost = np.floor((INSCRIBED - 1) * np.exp(-scaling * (d - inscribed_radius)))
    cost = np.where(d <= inscribed_radius, INSCRIBED, cost)
    cost = np.where(d > math.ceil(radius / res) * res, 0, cost)
    return np.where(blocked, LETHAL, cost).astype(np.uint8)


class SmacDriver:
    """One ``smac_driver`` process: one costmap and one parameter set, many queries.

    ``configure`` (the time its constructor reports) is Smac's plugin set-up, paid once per
    process: its Dubins/Reeds-Shepp distance lookup table.
    """

    def __init__(self, driver: Path, costs: np.ndarray, res: float, footprint, params: dict,
                 inflation: tuple[float, float] | None = None):
        self._dir = tempfile.TemporaryDirectory(prefix="smac-map-")
        path = Path(self._dir.name) / "costs.u8"
        np.ascontiguousarray(costs, dtype=np.uint8).tofile(path)
        h, w = costs.shape
        cmd = [str(driver), "--map", str(path), "--width", str(w), "--height", str(h),
               "--resolution", repr(res), "--origin", "0", "0",
               "--footprint", ";".join(f"{x!r},{y!r}" for x, y in footprint)]
        for name, value in params.items():
            cmd += ["--param", f"{name}={value}"]
        if inflation is not None:
            cmd += ["--inflation", repr(inflation[0]), repr(inflation[1])]
        self._proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
        self.config = self._read()

    def _read(self) -> dict:
        line = self._proc.stdout.readline()
        if not line:
            raise RuntimeError(f"smac_driver ended (exit {self._proc.wait()}); its stderr says why")
        return json.loads(line)

    def plan(self, start, goal) -> dict:
        """One query [m, m, rad]: the driver's answer (found, reason, wall_ms, cpu_ms, iterations,
        length_m, poses)."""
        self._proc.stdin.write(" ".join(repr(float(v)) for v in (*start, *goal)) + "\n")
        self._proc.stdin.flush()
        return self._read()

    def close(self) -> None:
        self._proc.stdin.close()
        self._proc.wait()
        self._dir.cleanup()


def densified(poses, step: float = 0.01) -> np.ndarray:
    """The poses and, between consecutive ones, poses at most ``step`` [m] apart on the straight
    segment (heading interpolated the short way round): (N, 3)."""
    poses = np.asarray(poses, dtype=float)
    out = [poses[:1]]
    for a, b in zip(poses[:-1], poses[1:]):
        n = max(1, math.ceil(math.hypot(b[0] - a[0], b[1] - a[1]) / step))
        t = np.arange(1, n + 1)[:, None] / n
        turn = (b[2] - a[2] + math.pi) % (2 * math.pi) - math.pi
        out.append(np.hstack([a[:2] + t * (b[:2] - a[:2]), a[2] + t * turn]))
    return np.vstack(out)


class BlockedCells:
    """The blocked cells of a map as one shapely geometry (cell squares, origin 0, row = y)."""

    def __init__(self, blocked: np.ndarray, res: float):
        import shapely

        j, i = np.nonzero(blocked)
        boxes = shapely.box(i * res, j * res, (i + 1) * res, (j + 1) * res)
        self.geometry = shapely.union_all(boxes)
        shapely.prepare(self.geometry)

    def overlaps(self, footprint, poses, min_area: float = 1e-10) -> tuple[int, float]:
        """How many of ``poses`` put the ``footprint`` polygon over a blocked cell (an overlap of
        more than ``min_area`` [m^2]: touching is not overlapping), and the largest overlap [m^2]."""
        import shapely

        poses = np.asarray(poses, dtype=float)
        fp = np.asarray(footprint, dtype=float)
        c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
        x = poses[:, :1] + c[:, None] * fp[None, :, 0] - s[:, None] * fp[None, :, 1]
        y = poses[:, 1:2] + s[:, None] * fp[None, :, 0] + c[:, None] * fp[None, :, 1]
        rings = np.stack([x, y], axis=-1)
        polygons = shapely.polygons(np.concatenate([rings, rings[:, :1]], axis=1))
        hit = shapely.intersects(self.geometry, polygons)
        if not hit.any():
            return 0, 0.0
        areas = shapely.area(shapely.intersection(self.geometry, polygons[hit]))
        return int((areas > min_area).sum()), float(areas.max())
