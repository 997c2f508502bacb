"""Contract and statistics tests over every registered sampler."""

import time

import numpy as np
import pytest
import shapely

import navlab
from navlab.grid.occupancy import OccupancyGrid
from navlab.sampling import SAMPLERS, make_sampler
from navlab.sampling.planners import RRTStar
from navlab.sampling.regions import InformedRegion
from navlab.sampling.samplers import MAX_ROUNDS, Sampler
from navlab.world import World

SCENE = "clutter"


def surface_distance(world, pts):
    """Distance to the nearest obstacle or bounds edge (Gaussian sampling
    treats the outside of the bounds as an obstacle)."""
    b = world.bounds
    walls = np.min([pts[:, 0] - b.xmin, b.xmax - pts[:, 0], pts[:, 1] - b.ymin, b.ymax - pts[:, 1]], axis=0)
    return np.minimum(world.checker().clearance(pts), walls + world.robot_radius)


@pytest.mark.parametrize("name", SAMPLERS.names())
def test_contract(name):
    world = navlab.load_world(SCENE)
    sampler = make_sampler(name)
    a = sampler.sample(world, np.random.default_rng(3), 500)
    b = sampler.sample(world, np.random.default_rng(3), 500)
    assert a.shape == (500, 2) and np.all(np.isfinite(a))
    np.testing.assert_array_equal(a, b)  # same seed, same samples
    assert world.bounds.contains(a).all()
    assert sampler.sample(world, np.random.default_rng(3), 0).shape == (0, 2)


@pytest.mark.parametrize("name", ["gaussian", "boundary"])
@pytest.mark.parametrize("scene", ["clutter", "pythonrobotics", "trap"])
def test_surface_samplers_never_collide_and_hug_surfaces(name, scene):
    world = navlab.load_world(scene)
    checker = world.checker()
    pts = make_sampler(name).sample(world, np.random.default_rng(0), 2000)
    assert checker.points_free(pts).all()
    clearance = surface_distance(world, pts)
    uniform = make_sampler("uniform").sample(world, np.random.default_rng(0), 2000)
    uclear = surface_distance(world, uniform[checker.points_free(uniform)])
    # Concentrated near inflated surfaces: far closer than uniform samples.
    assert np.median(clearance - world.robot_radius) < 0.4 * np.median(uclear - world.robot_radius)


def test_boundary_samples_lie_within_tolerance_of_surface():
    world = navlab.load_world("clutter")
    tol = 0.01
    pts = make_sampler("boundary", tolerance=tol).sample(world, np.random.default_rng(1), 1000)
    gap = world.checker().clearance(pts) - world.robot_radius
    assert np.all(gap >= 0) and np.quantile(gap, 0.99) <= tol + 1e-9


@pytest.mark.parametrize("rate", [0.0, 0.05, 0.3, 1.0])
def test_goal_bias_fraction(rate):
    world = navlab.load_world(SCENE)
    n = 20000
    pts = make_sampler("goal_bias", goal_sample_rate=rate).sample(world, np.random.default_rng(5), n)
    frac = np.mean(np.all(pts == world.goal, axis=1))
    sd = np.sqrt(rate * (1 - rate) / n)
    assert abs(frac - rate) <= 5 * sd + 1e-12


def test_integration_mixture_fractions():
    world = navlab.load_world(SCENE)
    weights = {"goal": 0.1, "uniform": 0.3, "gaussian": 0.3, "boundary": 0.3}
    n = 20000
    pts = make_sampler("integration", weights=weights).sample(world, np.random.default_rng(9), n)
    goal_frac = np.mean(np.all(pts == world.goal, axis=1))
    assert abs(goal_frac - 0.1) < 5 * np.sqrt(0.09 / n)
    # Boundary samples (30%) lie within its tolerance of a surface; swapping
    # them for uniform ones must remove about that share of near-surface points.
    checker = world.checker()

    def near_share(p):
        return np.mean(checker.points_free(p) & (checker.clearance(p) - world.robot_radius < 0.015))

    plain = make_sampler("integration", weights={"goal": 0.1, "uniform": 0.6, "gaussian": 0.3})
    ref = plain.sample(world, np.random.default_rng(9), n)
    assert near_share(pts) - near_share(ref) > 0.25


def test_integration_default_weights_are_documented_reading():
    s = make_sampler("integration")
    assert s.weights == {"goal": 0.10, "uniform": 0.30, "gaussian": 0.30, "boundary": 0.30}


@pytest.mark.parametrize("name, params, field", [
    ("goal_bias", {"goal_sample_rate": 5}, "goal_sample_rate"),
    ("goal_bias", {"goal_sample_rate": -0.1}, "goal_sample_rate"),
    ("gaussian", {"sigma": -1.0}, "sigma"),
    ("boundary", {"directions": 0}, "directions"),
    ("boundary", {"tolerance": 0}, "tolerance"),
    ("integration", {"weights": {"goal": 0.5, "uniform": 0.6}}, "weights"),
    ("integration", {"weights": {"goal": 0.5, "unifrom": 0.5}}, "unifrom"),
    ("uniform", {"sigma": 1.0}, "sigma"),
    # issue 13: wrong types and out-of-range values fail when the sampler is built
    ("integration", {"weights": 5}, "weights"),
    ("integration", {"weights": {3: 1.0}}, "unknown component"),
    ("goal_bias", {"base": 5}, "base"),
    ("goal_bias", {"base": "unifrom"}, "unifrom"),
    ("boundary", {"tolerance": 5e-324}, "tolerance"),
    ("boundary", {"tolerance": float("nan")}, "tolerance"),
    ("boundary", {"directions": True}, "directions"),
    ("boundary", {"directions": 2.5}, "directions"),
    ("boundary", {"max_rounds": 0}, "max_rounds"),
    ("gaussian", {"sigma": "big"}, "sigma"),
    ("gaussian", {"sigma": 1e300}, "sigma"),
    ("gaussian", {"max_rounds": 10**12}, "max_rounds"),
    ("integration", {"tolerance": 5e-324}, "tolerance"),
])
def test_invalid_parameters(name, params, field):
    with pytest.raises(ValueError, match=field):
        make_sampler(name, **params)


def test_unknown_sampler_hint():
    with pytest.raises(ValueError, match="Did you mean 'gaussian'"):
        make_sampler("gausian")


def test_informed_region_is_the_ellipse(rng):
    world = navlab.load_world("pythonrobotics")
    region = InformedRegion(world.start, world.goal, 14.0, world.bounds)
    pts = region.draw(rng, 5000)
    s, g = np.asarray(world.start), np.asarray(world.goal)
    total = np.linalg.norm(pts - s, axis=1) + np.linalg.norm(pts - g, axis=1)
    assert np.all(total <= 14.0 + 1e-9) and world.bounds.contains(pts).all()
    # Uniform inside: in the ellipse's own frame half the points lie within
    # the concentric ellipse of half the area.
    axis = (g - s) / np.linalg.norm(g - s)
    local = np.column_stack(((pts - (s + g) / 2) @ axis, (pts - (s + g) / 2) @ np.array([-axis[1], axis[0]])))
    a, b = 7.0, np.sqrt(14.0**2 - np.sum((g - s) ** 2)) / 2
    r2 = (local[:, 0] / a) ** 2 + (local[:, 1] / b) ** 2
    assert abs(np.mean(r2 < 0.5) - 0.5) < 0.03


@pytest.mark.parametrize("name", SAMPLERS.names())
def test_samplers_respect_informed_region(name):
    world = navlab.load_world("pythonrobotics")
    region = InformedRegion(world.start, world.goal, 16.0, world.bounds)
    pts = make_sampler(name).sample(world, np.random.default_rng(2), 300, region=region)
    assert region.contains(pts).all()


# -- budgets (issue 13) -------------------------------------------------------

@pytest.mark.parametrize("name, params", [
    ("gaussian", {"sigma": 1e-9, "max_rounds": MAX_ROUNDS}),  # pairs almost never straddle a surface
    ("boundary", {"max_rounds": MAX_ROUNDS}),
    ("integration", {"sigma": 1e-9}),
])
def test_a_passed_deadline_stops_the_retry_loops(name, params):
    world = navlab.load_world(SCENE)
    checker = world.checker()
    sampler = make_sampler(name, **params)
    pts = sampler.sample(world, np.random.default_rng(0), 200, checker=checker, deadline=time.perf_counter() - 1.0)
    assert pts.shape == (200, 2) and np.all(np.isfinite(pts))
    # one round at most: the Gaussian checks two points per pair, the boundary
    # sampler its rays plus at most ~log2(reach / tolerance) bisection calls
    assert checker.calls <= 20
    if name == "gaussian":
        # without a deadline the same query keeps trying (bounded by max_rounds)
        slow = world.checker()
        make_sampler(name, sigma=1e-9, max_rounds=40).sample(world, np.random.default_rng(0), 200, checker=slow)
        assert slow.calls >= 80


class _RecordingSampler(Sampler):
    """Uniform samples; remembers the deadline each call was given."""

    def __init__(self) -> None:
        self.deadlines = []

    def _sample(self, world, rng, n, checker, region, deadline):
        self.deadlines.append(deadline)
        return region.draw(rng, n)


def test_tree_planners_pass_their_time_budget_to_the_sampler():
    world = navlab.load_world(SCENE)
    recorder = _RecordingSampler()
    before = time.perf_counter()
    RRTStar(sampler=recorder, max_iter=200, max_time=30.0).plan(world, 0)
    assert recorder.deadlines and all(d is not None for d in recorder.deadlines)
    assert before + 30.0 <= recorder.deadlines[0] <= time.perf_counter() + 30.0
    untimed = _RecordingSampler()
    RRTStar(sampler=untimed, max_iter=200).plan(world, 0)
    assert set(untimed.deadlines) == {None}


def test_bad_deadline_and_count():
    world = navlab.load_world(SCENE)
    with pytest.raises(ValueError, match="deadline"):
        make_sampler("uniform").sample(world, np.random.default_rng(0), 5, deadline=float("nan"))
    with pytest.raises(ValueError, match="n must be"):
        make_sampler("uniform").sample(world, np.random.default_rng(0), 2.5)


# -- samplers on occupancy maps -----------------------------------------------

def small_map(origin=(0.0, 0.0, 0.0)):
    """Rooms and pillars on a 60 x 50 cell map at 0.1 m (built here, no file)."""
    blocked = np.zeros((50, 60), dtype=bool)
    blocked[[0, -1], :] = True
    blocked[:, [0, -1]] = True
    blocked[25, :40] = True  # a wall with a gap at the right
    blocked[10:20, 30:33] = True
    blocked[35:38, 15:45] = True
    rng = np.random.default_rng(1)
    blocked[rng.integers(0, 50, 40), rng.integers(0, 60, 40)] = True
    unknown = np.zeros_like(blocked)
    unknown[40:46, 48:56] = True
    return OccupancyGrid(blocked, 0.1, origin, unknown)


def map_truth(grid, radius):
    """Independent distance to blocked/unknown squares: shapely on the cells."""
    ox, oy, yaw = grid.origin
    c, s = np.cos(yaw), np.sin(yaw)
    res = grid.resolution

    def world(u, v):
        return (ox + u * c - v * s, oy + u * s + v * c)

    cells = zip(*np.nonzero(grid.blocked | grid.unknown))
    union = shapely.union_all([shapely.Polygon([world(i * res, j * res), world((i + 1) * res, j * res),
                                                world((i + 1) * res, (j + 1) * res), world(i * res, (j + 1) * res)])
                               for j, i in cells])
    extent = shapely.Polygon([world(0, 0), world(grid.width * res, 0), world(grid.width * res, grid.height * res),
                              world(0, grid.height * res)])
    return lambda pts: np.where(shapely.covers(extent, shapely.points(pts)),
                                shapely.distance(union, shapely.points(pts)), -1.0)


@pytest.mark.parametrize("origin", [(0.0, 0.0, 0.0), (2.0, -1.0, 0.5)])
@pytest.mark.parametrize("name", ["gaussian", "boundary"])
def test_surface_samplers_on_maps_never_collide_and_hug_surfaces(name, origin):
    grid = small_map(origin)
    radius = 0.15
    world = World.from_grid(grid, (0.5, 0.5), (5.0, 4.0), robot_radius=radius)
    checker = world.checker()
    pts = make_sampler(name).sample(world, np.random.default_rng(4), 1500, checker=checker)
    clearance = map_truth(grid, radius)(pts)
    assert np.all(clearance > radius)  # free by an independent check: on the map, > radius from every cell
    uniform = make_sampler("uniform").sample(world, np.random.default_rng(4), 1500)
    uclear = map_truth(grid, radius)(uniform)
    uclear = uclear[uclear > radius]
    # a crowded map: uniform samples are already close, so ask for a clear but smaller margin
    assert np.median(clearance - radius) < 0.6 * np.median(uclear - radius)
    if name == "boundary":
        tol = 1e-3 * world.bounds.diagonal
        assert np.quantile(clearance - radius, 0.9) <= tol + 1e-9


def test_integration_runs_on_a_map_with_all_components():
    grid = small_map()
    world = World.from_grid(grid, (0.5, 0.5), (5.0, 4.0), robot_radius=0.1)
    pts = make_sampler("integration").sample(world, np.random.default_rng(0), 2000)
    assert pts.shape == (2000, 2) and world.bounds.contains(pts).all()
    goal = np.all(pts == world.goal, axis=1)
    assert 0.05 < goal.mean() < 0.15


def test_boundary_sampler_on_an_empty_map_is_uniform():
    world = World.from_grid(OccupancyGrid(np.zeros((10, 10), dtype=bool), 0.5), (0.5, 0.5), (4.0, 4.0))
    a = make_sampler("boundary").sample(world, np.random.default_rng(0), 50)
    b = make_sampler("uniform").sample(world, np.random.default_rng(0), 50)
    np.testing.assert_array_equal(a, b)
