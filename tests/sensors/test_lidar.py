"""LiDAR scans against shapely ray intersections."""

import math

import numpy as np
import pytest
import shapely

from helpers import shapely_of
from navlab.grid.occupancy import OccupancyGrid
from navlab.sensors import Lidar
from navlab.world import load_world


def shapely_ranges(geoms, pose, angles, range_max):
    out = []
    for a in angles:
        end = (pose[0] + range_max * math.cos(pose[2] + a), pose[1] + range_max * math.sin(pose[2] + a))
        ray = shapely.LineString([pose[:2], end])
        best = math.inf
        for g in geoms:
            hit = ray.intersection(g)
            if not hit.is_empty:
                best = min(best, shapely.Point(pose[:2]).distance(hit))
        out.append(best)
    return np.array(out)


@pytest.mark.parametrize("scene", ["clutter", "trap", "squarefield", "pythonrobotics"])
def test_exact_scans_of_geometric_worlds(scene):
    world = load_world(scene)
    geoms = [shapely_of(o) if not hasattr(o, "radius") else shapely.Point(o.center).buffer(o.radius, 4096)
             for o in world.obstacles]
    lidar = Lidar(beams=90, range_max=30.0)
    rng = np.random.default_rng(3)
    for _ in range(3):
        while True:
            p = rng.uniform(world.bounds.low, world.bounds.high)
            if world.checker().clearance(p)[0] > 0.05:
                break
        pose = np.array((*p, rng.uniform(-3, 3)))
        ours = lidar.exact(world, pose)
        truth = shapely_ranges(geoms, pose, lidar.angles, 30.0)
        assert np.isinf(ours).tolist() == np.isinf(truth).tolist()
        finite = np.isfinite(truth)
        assert ours[finite] == pytest.approx(truth[finite], abs=2e-4)  # polygonised circles: ≤ 1e-4 m


def test_exact_scans_of_a_grid():
    rng = np.random.default_rng(5)
    blocked = rng.random((20, 25)) < 0.15
    blocked[9:12, 11:14] = False
    grid = OccupancyGrid(blocked, resolution=0.1, origin=(-1.0, 0.5, 0.0))
    boxes = [shapely.box(-1.0 + 0.1 * x, 0.5 + 0.1 * y, -1.0 + 0.1 * (x + 1), 0.5 + 0.1 * (y + 1))
             for y, x in zip(*np.nonzero(blocked))]
    pose = np.array((-1.0 + 1.23, 0.5 + 1.04, 0.4))
    lidar = Lidar(beams=180, range_max=5.0)
    ours = lidar.exact(grid, pose)
    truth = shapely_ranges([shapely.union_all(boxes)], pose, lidar.angles, 5.0)
    assert np.isinf(ours).tolist() == np.isinf(truth).tolist()
    finite = np.isfinite(truth)
    assert ours[finite] == pytest.approx(truth[finite], abs=1e-9)


def test_rep117_limits_and_points():
    world = load_world("trap")
    lidar = Lidar(beams=8, range_min=0.15, range_max=1.0)
    pose = np.array((7.5, 6.0, 0.0))  # 0.1 m from the trap's closed side, far from the rest
    ranges = lidar.scan(world, pose)
    assert ranges[0] == -math.inf  # wall at 0.1 m: closer than range_min
    assert np.isposinf(ranges[4])  # nothing within 1 m behind
    pts = lidar.points(np.array([1.0, 2.0, np.inf, -np.inf, 1, 1, 1, 1]), np.array((1.0, 1.0, math.pi / 2)))
    assert len(pts) == 6 and pts[0] == pytest.approx((1.0, 2.0))  # eq. 18–19


def test_rplidar_a1_noise_follows_the_datasheet_bands():
    lidar = Lidar(beams=360, noise="rplidar_a1", range_max=12.0)
    ranges = np.concatenate((np.full(200000, 2.0), np.full(200000, 4.0), np.full(200000, 8.0)))
    noisy = lidar.noise.apply(ranges, np.random.default_rng(0))
    for i, (d, band) in enumerate(((2.0, 0.01), (4.0, 0.02), (8.0, 0.025))):
        err = noisy[i * 200000:(i + 1) * 200000] - d
        assert np.std(err) == pytest.approx(band * d / 2, rel=0.02)
        assert np.mean(np.abs(err) <= band * d) == pytest.approx(0.954, abs=0.01)


def test_bad_lidar_settings():
    for kwargs in ({"beams": 0}, {"range_min": 2, "range_max": 1}, {"fov": 7.0}, {"noise": "rplidar"}):
        with pytest.raises(ValueError):
            Lidar(**kwargs)
