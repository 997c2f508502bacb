"""Sampling strategies, registered by name (seed 001 §2.3–2.5, seed 000).

``sampler.sample(world, rng, n)`` returns an ``(n, 2)`` array. Samplers that
need collision information ask the checker (counted); they never read
obstacles. ``region`` replaces the bounds as the source of uniform draws
(Informed RRT* passes its ellipse).
"""

from __future__ import annotations

import math
from typing import Any, Dict, Optional

import numpy as np

from ..registry import Registry, check_params, parameters_of
from .regions import BoxRegion

SAMPLERS: Registry[type] = Registry("sampler")


def _probability(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (0.0 <= value <= 1.0):
        raise ValueError(f"{name} must be a probability in [0, 1], got {value!r}")
    return float(value)


def _positive(name: str, value: Any, allow_none: bool = True) -> Optional[float]:
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (value > 0 and math.isfinite(value)):
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    return float(value)


class Sampler:
    """Base class: stores keyword settings; ``sample`` does the work."""

    def get_params(self) -> Dict[str, Any]:
        return {k: getattr(self, k) for k in parameters_of(type(self))}

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items())
        return f"{type(self).__name__}({args})"

    def sample(self, world, rng: np.random.Generator, n: int, checker=None, region=None) -> np.ndarray:
        """Return ``n`` samples as an ``(n, 2)`` array."""
        if n < 0:
            raise ValueError(f"n must be non-negative, got {n}")
        region = region if region is not None else BoxRegion(world.bounds)
        checker = checker if checker is not None else world.checker()
        if n == 0:
            return np.empty((0, 2))
        out = self._sample(world, rng, int(n), checker, region)
        assert out.shape == (n, 2)
        return out

    def _sample(self, world, rng, n, checker, region) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError


@SAMPLERS.register("uniform")
class UniformSampler(Sampler):
    """Uniform over the sampling area (LaValle 1998)."""

    def _sample(self, world, rng, n, checker, region):
        return region.draw(rng, n)


@SAMPLERS.register("goal_bias")
class GoalBiasSampler(Sampler):
    """With probability ``goal_sample_rate`` the goal, otherwise the base sampler.

    Parameters
    ----------
    goal_sample_rate : float
        Probability in [0, 1] (PythonRobotics' ``goal_sample_rate=5`` percent
        is 0.05 here); the seed recommends 0–0.10.
    base : str or Sampler
        The sampler used otherwise (uniform by default).
    """

    def __init__(self, goal_sample_rate: float = 0.05, base: Any = "uniform") -> None:
        self.goal_sample_rate = _probability("goal_sample_rate", goal_sample_rate)
        self.base = base
        self._base = make_sampler(base) if isinstance(base, str) else base

    def _sample(self, world, rng, n, checker, region):
        is_goal = rng.random(n) < self.goal_sample_rate
        out = np.empty((n, 2))
        out[is_goal] = world.goal
        out[~is_goal] = self._base.sample(world, rng, int((~is_goal).sum()), checker, region)
        return out


def _fill_uniform(parts: list, n: int, rng, region) -> np.ndarray:
    """Concatenate accepted samples; top up with uniform draws if a sampler
    found too few (e.g. a Gaussian sampler in a world without obstacles)."""
    out = np.concatenate(parts) if parts else np.empty((0, 2))
    if len(out) < n:
        out = np.concatenate((out, region.draw(rng, n - len(out))))
    return out[:n]


@SAMPLERS.register("gaussian")
class GaussianSampler(Sampler):
    """Samples near obstacle surfaces (Boor, Overmars, van der Stappen 1999).

    Draw c1 uniformly, d ~ N(0, sigma), c2 at distance |d| from c1 in a random
    direction. If exactly one of c1, c2 is valid (free and inside the bounds),
    return it; otherwise discard both. Samples are never in collision.

    Parameters
    ----------
    sigma : float, optional
        Standard deviation of the pair distance in metres; default 2% of the
        bounds' diagonal.
    max_rounds : int
        Batches of pairs tried before topping up with uniform samples (which
        happens only where hardly any pair straddles a surface).

    References
    ----------
    V. Boor, M. H. Overmars, A. F. van der Stappen, "The Gaussian sampling
    strategy for probabilistic roadmap planners", ICRA 1999.
    """

    def __init__(self, sigma: Optional[float] = None, max_rounds: int = 50) -> None:
        self.sigma = _positive("sigma", sigma)
        if not isinstance(max_rounds, int) or max_rounds < 1:
            raise ValueError(f"max_rounds must be a positive integer, got {max_rounds!r}")
        self.max_rounds = max_rounds

    def _sample(self, world, rng, n, checker, region):
        sigma = self.sigma or 0.02 * world.bounds.diagonal
        parts, found = [], 0
        for _ in range(self.max_rounds):
            m = max(4 * (n - found), 16)
            c1 = region.draw(rng, m)
            d = rng.normal(0.0, sigma, m)
            phi = rng.random(m) * 2 * math.pi
            c2 = c1 + d[:, None] * np.column_stack((np.cos(phi), np.sin(phi)))
            free1 = checker.points_free(c1)
            free2 = checker.points_free(c2) & region.contains(c2)
            keep = np.where(free1 & ~free2, 0, np.where(free2 & ~free1, 1, -1))
            chosen = np.where((keep == 0)[:, None], c1, c2)[keep >= 0]
            parts.append(chosen)
            found += len(chosen)
            if found >= n:
                break
        return _fill_uniform(parts, n, rng, region)


@SAMPLERS.register("boundary")
class BoundarySampler(Sampler):
    """Points just outside obstacle surfaces, found by bisection (J. Wang et al.).

    Take a point inside an obstacle (obstacles picked in proportion to their
    inflated perimeter), spread ``directions`` rays evenly around it (random
    phase), and along each ray bisect between the inside point and a point
    outside until the interval is shorter than ``tolerance``; the free end of
    the interval is the sample ("connector node"). Rays whose outer point is
    itself blocked (another obstacle, or outside the bounds) are skipped.
    Samples are never in collision.

    Parameters
    ----------
    directions : int
        Rays per inside point (m in the seed).
    tolerance : float, optional
        Final bisection interval in metres; default 0.1% of the diagonal.

    References
    ----------
    J. Wang et al., boundary sampling with bisection for RRT-based planners,
    as summarised in seed 001 §2.5.
    """

    def __init__(self, directions: int = 8, tolerance: Optional[float] = None, max_rounds: int = 50) -> None:
        if isinstance(directions, bool) or not isinstance(directions, int) or directions < 1:
            raise ValueError(f"directions must be a positive integer, got {directions!r}")
        self.directions = directions
        self.tolerance = _positive("tolerance", tolerance)
        self.max_rounds = max_rounds

    def _sample(self, world, rng, n, checker, region):
        if not world.obstacles:
            return region.draw(rng, n)
        r = world.robot_radius
        weights = np.array([o.perimeter(r) for o in world.obstacles])
        tol = self.tolerance or 1e-3 * world.bounds.diagonal
        parts, found = [], 0
        for _ in range(self.max_rounds):
            seeds = -(-(n - found) // self.directions) + 1
            which = rng.choice(len(world.obstacles), size=seeds, p=weights / weights.sum())
            inner = np.concatenate([world.obstacles[k].interior_points(rng, 1) for k in which])
            reach = np.array([_reach(world.obstacles[k], r) for k in which])
            phase = rng.random(seeds) * 2 * math.pi
            angles = phase[:, None] + np.arange(self.directions) * (2 * math.pi / self.directions)
            unit = np.stack((np.cos(angles), np.sin(angles)), axis=-1).reshape(-1, 2)
            lo = np.repeat(inner, self.directions, axis=0)
            hi = lo + unit * np.repeat(reach, self.directions)[:, None]
            # Keep rays whose inner point is blocked and outer point is free.
            ok = ~checker.points_free(lo) & checker.points_free(hi)
            lo, hi = lo[ok], hi[ok]
            steps = int(math.ceil(math.log2(max(np.max(np.linalg.norm(hi - lo, axis=1), initial=tol) / tol, 1.0))))
            for _ in range(steps):
                mid = (lo + hi) / 2
                free = checker.points_free(mid)
                hi = np.where(free[:, None], mid, hi)
                lo = np.where(free[:, None], lo, mid)
            chosen = hi[region.contains(hi)]
            parts.append(chosen[rng.permutation(len(chosen))])
            found += len(chosen)
            if found >= n:
                break
        return _fill_uniform(parts, n, rng, region)


def _reach(obstacle, inflate: float) -> float:
    """A length that takes any interior point outside the inflated obstacle."""
    x0, y0, x1, y1 = obstacle.bbox()
    return math.hypot(x1 - x0, y1 - y0) + inflate + 1e-6


INTEGRATION_DEFAULT_WEIGHTS = {"goal": 0.10, "uniform": 0.30, "gaussian": 0.30, "boundary": 0.30}


@SAMPLERS.register("integration")
class IntegrationSampler(Sampler):
    """Seed 000's mixture: each sample picks goal, uniform, Gaussian or boundary.

    The seed draws r in [0, 100): r < 10 goal, 10 ≤ r < 20 uniform, 20 ≤ r < 50
    Gaussian, 50 ≤ r < 80 boundary, and leaves 80 ≤ r < 100 unspecified. navlab
    gives that 20% to uniform, so the default weights are goal 0.10, uniform
    0.30, Gaussian 0.30, boundary 0.30. The seed's first branch calls its
    goal-bias routine; navlab reads it as "return the goal" (10% of samples are
    the goal), since a nested goal-bias routine would return the goal only
    k·10% of the time.

    Parameters
    ----------
    weights : dict, optional
        Probabilities of ``goal``, ``uniform``, ``gaussian``, ``boundary``;
        must sum to 1.
    sigma, directions, tolerance :
        Passed to the Gaussian and boundary components.
    """

    COMPONENTS = ("goal", "uniform", "gaussian", "boundary")

    def __init__(self, weights: Optional[Dict[str, float]] = None, sigma: Optional[float] = None,
                 directions: int = 8, tolerance: Optional[float] = None) -> None:
        w = dict(INTEGRATION_DEFAULT_WEIGHTS if weights is None else weights)
        for key, value in w.items():
            if key not in self.COMPONENTS:
                from ..registry import suggest
                raise ValueError(f"weights: unknown component '{key}'; valid: {', '.join(self.COMPONENTS)}." + suggest(key, list(self.COMPONENTS)))
            _probability(f"weights['{key}']", value)
        if abs(sum(w.values()) - 1.0) > 1e-9:
            raise ValueError(f"weights must sum to 1, got {sum(w.values()):.6g} ({w})")
        self.weights = w
        self.sigma, self.directions, self.tolerance = sigma, directions, tolerance
        self._parts = {
            "uniform": UniformSampler(),
            "gaussian": GaussianSampler(sigma=sigma),
            "boundary": BoundarySampler(directions=directions, tolerance=tolerance),
        }

    def _sample(self, world, rng, n, checker, region):
        names = [k for k in self.COMPONENTS if self.weights.get(k, 0.0) > 0]
        probs = np.array([self.weights[k] for k in names])
        pick = rng.choice(len(names), size=n, p=probs / probs.sum())
        out = np.empty((n, 2))
        for idx, name in enumerate(names):
            rows = pick == idx
            count = int(rows.sum())
            if count == 0:
                continue
            if name == "goal":
                out[rows] = world.goal
            else:
                out[rows] = self._parts[name].sample(world, rng, count, checker, region)
        return out


def make_sampler(name: str, **params: Any) -> Sampler:
    """Build a registered sampler by name, e.g. ``make_sampler("gaussian", sigma=0.5)``."""
    cls = SAMPLERS.get(name)
    check_params(cls, params, f"sampler '{name}'")
    return cls(**params)
