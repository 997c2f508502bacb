"""Where a sampler's uniform draws come from: the bounds, or an informed set.

Every sampler builds on uniform draws (Gaussian's first point, the uniform
share of a mixture, ...). Passing a region in place of the bounds is how
Informed RRT* composes with any sampler.
"""

from __future__ import annotations

import math

import numpy as np


class BoxRegion:
    """Uniform over the world's axis-aligned bounds."""

    def __init__(self, bounds) -> None:
        self.bounds = bounds
        self.low, self.high = bounds.low, bounds.high

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        return self.low + rng.random((n, 2)) * (self.high - self.low)

    def contains(self, points: np.ndarray) -> np.ndarray:
        return self.bounds.contains(points)


class InformedRegion:
    """The informed set {x : |x − start| + |x − goal| ≤ c_best} ∩ bounds.

    Only points in this ellipse can lie on a path shorter than ``c_best``.

    References
    ----------
    J. D. Gammell, S. S. Srinivasa, T. D. Barfoot, "Informed RRT*: Optimal
    sampling-based path planning focused via direct sampling of an admissible
    ellipsoidal heuristic", IROS 2014.
    """

    def __init__(self, start, goal, c_best: float, bounds) -> None:
        self.start, self.goal = np.asarray(start, float), np.asarray(goal, float)
        self.bounds = bounds
        c_min = float(np.linalg.norm(self.goal - self.start))
        self.c_best = max(float(c_best), c_min)
        self.centre = (self.start + self.goal) / 2
        self.a = self.c_best / 2
        self.b = math.sqrt(max(self.c_best**2 - c_min**2, 0.0)) / 2
        angle = math.atan2(*(self.goal - self.start)[::-1])
        self.rotation = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
        # Draw from whichever of ellipse and box is smaller, reject by the other.
        self._from_ellipse = math.pi * self.a * self.b <= bounds.area
        self._box = BoxRegion(bounds)

    def contains(self, points: np.ndarray) -> np.ndarray:
        p = np.atleast_2d(points)
        inside = (np.linalg.norm(p - self.start, axis=1) + np.linalg.norm(p - self.goal, axis=1)) <= self.c_best + 1e-12
        return inside & self.bounds.contains(p)

    def _draw_ellipse(self, rng: np.random.Generator, n: int) -> np.ndarray:
        rho = np.sqrt(rng.random(n))
        phi = rng.random(n) * 2 * math.pi
        unit = np.column_stack((self.a * rho * np.cos(phi), self.b * rho * np.sin(phi)))
        return self.centre + unit @ self.rotation.T

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        out = np.empty((0, 2))
        for _ in range(1000):
            if len(out) >= n:
                break
            batch = max(2 * (n - len(out)), 8)
            if self._from_ellipse:
                cand = self._draw_ellipse(rng, batch)
                cand = cand[self.bounds.contains(cand)]
            else:
                cand = self._box.draw(rng, batch)
                cand = cand[self.contains(cand)]
            out = np.concatenate((out, cand))
        if len(out) < n:  # degenerate set (zero area): its axis is all there is
            t = rng.random(n - len(out))[:, None]
            out = np.concatenate((out, self.start + t * (self.goal - self.start)))
        return out[:n]
