"""Contract and statistics tests over every registered sampler."""

import numpy as np
import pytest

import navlab
from navlab.sampling import SAMPLERS, make_sampler
from navlab.sampling.regions import InformedRegion

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
