"""Sampling strategies, registered by name (seed 001 §2.3–2.5, seed 000).

``sampler.sample(world, rng, n)`` returns an ``(n, 2)`` array. Samplers that
need collision information ask the checker (counted); they never read
obstacles, so they work alike on shape worlds and occupancy maps. ``region``
replaces the bounds as the source of uniform draws (Informed RRT* passes its
ellipse). ``deadline`` (a :func:`time.perf_counter` value) bounds the time a
sampler may spend: loops that try again stop once it has passed.

Parameters are validated when a sampler is built, with a ``ParameterError``
naming the field.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from typing import Any, Dict, Optional

import numpy as np

from ..errors import ParameterError
from ..limits import check_count, check_length, plain_values
from ..registry import Registry, UnknownNameError, check_params, parameters_of, suggest
from .regions import BoxRegion

#: most rounds a sampler may be asked to try (each round is one batch of checks)
MAX_ROUNDS = 1_000_000
#: most rays a boundary sampler may spread around each inside point
MAX_DIRECTIONS = 10_000
#: rounds of free uniform draws that top up a surface sampler that found too few
TOP_UP_ROUNDS = 20

SAMPLERS: Registry[type] = Registry("sampler")


def _probability(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (0.0 <= value <= 1.0):
        raise ParameterError(f"{name} must be a probability in [0, 1], got {value!r}")
    return float(value)


def _length(name: str, value: Any) -> Optional[float]:
    """None, or a positive length in metres within navlab.limits."""
    if value is None:
        return None
    return check_length(name, plain_values(value), allow_zero=False)


def _expired(deadline: Optional[float]) -> bool:
    return deadline is not None and time.perf_counter() > deadline


class Sampler:
    """Base class: stores keyword settings; ``sample`` does the work."""

    def get_params(self) -> Dict[str, Any]:
        return {k: getattr(self, k) for k in parameters_of(type(self))}

    def resolved_params(self, world) -> Dict[str, Any]:
        """The settings this sampler uses on ``world``: defaults that depend on
        the world (a Gaussian sigma, a bisection tolerance) as computed."""
        return self.get_params()

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items())
        return f"{type(self).__name__}({args})"

    def sample(self, world, rng: np.random.Generator, n: int, checker=None, region=None,
               deadline: Optional[float] = None) -> np.ndarray:
        """Return ``n`` samples as an ``(n, 2)`` array.

        Parameters
        ----------
        world : World
        rng : numpy.random.Generator
        n : int
        checker : CollisionChecker, optional
            The planner's checker (its counters record the sampler's checks).
        region : BoxRegion or InformedRegion, optional
            Where uniform draws come from (default: the world's bounds).
        deadline : float, optional
            A :func:`time.perf_counter` value; loops that retry stop once it
            has passed and the sampler returns what it has, topped up.
        """
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ParameterError(f"n must be a non-negative whole number, got {n!r}")
        if deadline is not None and not (isinstance(deadline, (int, float)) and math.isfinite(deadline)):
            raise ParameterError(f"deadline must be a finite time.perf_counter() value, got {deadline!r}")
        region = region if region is not None else BoxRegion(world.bounds)
        checker = checker if checker is not None else world.checker()
        if n == 0:
            return np.empty((0, 2))
        out = self._sample(world, rng, int(n), checker, region, deadline)
        assert out.shape == (n, 2)
        return out

    def _sample(self, world, rng, n, checker, region, deadline) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError


@SAMPLERS.register("uniform")
class UniformSampler(Sampler):
    """Uniform over the sampling area (LaValle 1998)."""

    def _sample(self, world, rng, n, checker, region, deadline):
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
        if isinstance(base, str):
            try:
                self._base = make_sampler(base)
            except UnknownNameError as exc:  # name the field: "unknown sampler 'bogus'" left the reader guessing
                raise UnknownNameError(f"base: {exc.args[0]}") from None
        elif isinstance(base, Sampler):
            self._base = base
        else:
            raise ParameterError(f"base must be a sampler name or a Sampler, got {base!r}")
        self.base = base

    def resolved_params(self, world) -> Dict[str, Any]:
        # the base sampler's settings too (a goal-biased Gaussian's sigma), under their own names
        return {**self._base.resolved_params(world), "goal_sample_rate": self.goal_sample_rate}

    def _sample(self, world, rng, n, checker, region, deadline):
        is_goal = rng.random(n) < self.goal_sample_rate
        out = np.empty((n, 2))
        out[is_goal] = world.goal
        out[~is_goal] = self._base.sample(world, rng, int((~is_goal).sum()), checker, region, deadline)
        return out


def _fill_free(parts: list, n: int, rng, region, checker, deadline) -> np.ndarray:
    """Concatenate accepted (free) samples and top up a sampler that found
    too few (e.g. a Gaussian sampler in a world without obstacles).

    The top-up keeps only free uniform draws, so a surface sampler never
    returns a sample in collision; if even those run short (a region almost
    all blocked, or the deadline passed), found samples are repeated, and only
    a sampler that found none at all returns plain uniform draws.
    """
    out = np.concatenate(parts) if parts else np.empty((0, 2))
    for _ in range(TOP_UP_ROUNDS):
        if len(out) >= n or _expired(deadline):
            break
        draws = region.draw(rng, n - len(out))
        out = np.concatenate((out, draws[checker.points_free(draws)]))
    if len(out) == 0:
        return region.draw(rng, n)
    if len(out) < n:
        out = np.concatenate((out, out[rng.integers(len(out), size=n - len(out))]))
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
        Batches of pairs tried (at most ``MAX_ROUNDS``, and never past the
        deadline) before topping up with free uniform samples (which happens
        only where hardly any pair straddles a surface).

    References
    ----------
    V. Boor, M. H. Overmars, A. F. van der Stappen, "The Gaussian sampling
    strategy for probabilistic roadmap planners", ICRA 1999.
    """

    def __init__(self, sigma: Optional[float] = None, max_rounds: int = 50) -> None:
        self.sigma = _length("sigma", sigma)
        self.max_rounds = check_count("max_rounds", max_rounds, 1, MAX_ROUNDS)

    def resolved_params(self, world) -> Dict[str, Any]:
        return {**self.get_params(), "sigma": self.sigma_on(world)}

    def sigma_on(self, world) -> float:
        """``sigma``, or its default: 2% of the world's diagonal."""
        return self.sigma or 0.02 * world.bounds.diagonal

    def _sample(self, world, rng, n, checker, region, deadline):
        sigma = self.sigma_on(world)
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
            if found >= n or _expired(deadline):
                break
        return _fill_free(parts, n, rng, region, checker, deadline)


@SAMPLERS.register("boundary")
class BoundarySampler(Sampler):
    """Points just outside obstacle surfaces, found by bisection (J. Wang et al.).

    Take a point inside an obstacle (the checker draws it, picking obstacles
    in proportion to their inflated perimeter, and a map's blocked region in
    proportion to its surface length), spread ``directions`` rays evenly
    around it (random phase), and along each ray bisect between the inside
    point and a point outside until the interval is shorter than
    ``tolerance``; the free end of the interval is the sample ("connector
    node"), on the surface of the region inflated by the robot radius. Rays
    whose outer point is itself blocked (another obstacle, or outside the
    bounds or map) are skipped. Samples are never in collision.

    Parameters
    ----------
    directions : int
        Rays per inside point (m in the seed).
    tolerance : float, optional
        Final bisection interval in metres; default 0.1% of the diagonal.
    max_rounds : int
        Batches of inside points tried before topping up with free uniform
        samples (at most ``MAX_ROUNDS``, and never past the deadline).

    References
    ----------
    J. Wang et al., boundary sampling with bisection for RRT-based planners,
    as summarised in seed 001 §2.5.
    """

    def __init__(self, directions: int = 8, tolerance: Optional[float] = None, max_rounds: int = 50) -> None:
        self.directions = check_count("directions", directions, 1, MAX_DIRECTIONS)
        self.tolerance = _length("tolerance", tolerance)
        self.max_rounds = check_count("max_rounds", max_rounds, 1, MAX_ROUNDS)

    def resolved_params(self, world) -> Dict[str, Any]:
        return {**self.get_params(), "tolerance": self.tolerance_on(world)}

    def tolerance_on(self, world) -> float:
        """``tolerance``, or its default: 0.1% of the world's diagonal."""
        return self.tolerance or 1e-3 * world.bounds.diagonal

    def _sample(self, world, rng, n, checker, region, deadline):
        if not checker.has_obstacles:
            return region.draw(rng, n)
        tol = self.tolerance_on(world)
        parts, found = [], 0
        for _ in range(self.max_rounds):
            seeds = -(-(n - found) // self.directions) + 1
            inner, reach = checker.interior_points(rng, seeds)
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
            if found >= n or _expired(deadline):
                break
        return _fill_free(parts, n, rng, region, checker, deadline)


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
        if weights is not None and not isinstance(weights, Mapping):
            raise ParameterError("weights must be a mapping of component to probability, e.g. "
                                 f"{INTEGRATION_DEFAULT_WEIGHTS}, got {weights!r}")
        w = dict(INTEGRATION_DEFAULT_WEIGHTS if weights is None else weights)
        for key, value in w.items():
            if not isinstance(key, str) or key not in self.COMPONENTS:
                key = str(key)
                raise ParameterError(f"weights: unknown component '{key}'; valid: {', '.join(self.COMPONENTS)}." + suggest(key, list(self.COMPONENTS)))
            _probability(f"weights['{key}']", value)
        if abs(sum(w.values()) - 1.0) > 1e-9:
            raise ParameterError(f"weights must sum to 1, got {sum(w.values()):.6g} ({w})")
        self.weights = w
        self.sigma, self.directions, self.tolerance = sigma, directions, tolerance
        self._parts = {
            "uniform": UniformSampler(),
            "gaussian": GaussianSampler(sigma=sigma),
            "boundary": BoundarySampler(directions=directions, tolerance=tolerance),
        }

    def resolved_params(self, world) -> Dict[str, Any]:
        return {**self.get_params(), "sigma": self._parts["gaussian"].sigma_on(world),
                "tolerance": self._parts["boundary"].tolerance_on(world)}

    def _sample(self, world, rng, n, checker, region, deadline):
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
                out[rows] = self._parts[name].sample(world, rng, count, checker, region, deadline)
        return out


def make_sampler(name: str, **params: Any) -> Sampler:
    """Build a registered sampler by name, e.g. ``make_sampler("gaussian", sigma=0.5)``."""
    cls = SAMPLERS.get(name)
    check_params(cls, params, f"sampler '{name}'")
    return cls(**params)
