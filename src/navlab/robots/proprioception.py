"""Wheel encoders and a compass: what the robot knows of its own motion."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
from ..errors import ParameterError


@dataclass
class WheelEncoders:
    """Incremental encoders on every wheel, with the wheel–ground errors that
    make odometry drift.

    Parameters
    ----------
    ticks_per_rev : int
        Counts per wheel revolution; rotation is measured in whole ticks.
    noise : float
        Relative standard deviation of each wheel's actual speed around the
        commanded one (motor and surface variation): the robot really moves
        that way and the encoders see it.
    slip : float
        Largest fraction of a wheel's rotation lost to slip each step (uniform
        in [0, slip]): the wheel turns, the robot does not move as far, and
        the encoder cannot tell.
    """

    ticks_per_rev: int = 1440
    noise: float = 0.0
    slip: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.ticks_per_rev, int) or self.ticks_per_rev < 1:
            raise ParameterError(f"ticks_per_rev must be a positive integer, got {self.ticks_per_rev!r}")
        if not 0 <= self.noise < 1 or not 0 <= self.slip < 1:
            raise ParameterError("encoder noise and slip are fractions in [0, 1)")

    def actual_speeds(self, commanded: np.ndarray, rng: Optional[np.random.Generator]) -> np.ndarray:
        """Wheel angular speeds the motors really achieve."""
        if self.noise == 0 or rng is None:
            return commanded
        return commanded * (1.0 + self.noise * rng.standard_normal(len(commanded)))

    def ground_rotation(self, rotation: np.ndarray, rng: Optional[np.random.Generator]) -> np.ndarray:
        """The part of each wheel's rotation that moves the robot."""
        if self.slip == 0 or rng is None:
            return rotation
        return rotation * (1.0 - self.slip * rng.random(len(rotation)))

    def counts(self, wheel_angles: np.ndarray) -> np.ndarray:
        """Cumulative tick counts for cumulative wheel angles (rad)."""
        return np.floor(wheel_angles * (self.ticks_per_rev / (2.0 * math.pi))).astype(np.int64)

    def angles(self, counts: np.ndarray) -> np.ndarray:
        """Wheel angles (rad) that tick counts stand for."""
        return counts * (2.0 * math.pi / self.ticks_per_rev)


def calibrate_heading(raw_deg: float, offset_deg: float) -> float:
    """The seed's heading calibration (seed 004, eq. 3–4), in degrees:
    θ' = (θ − θ0 + 360) mod 360, then mapped to (−180, 180]."""
    calibrated = (raw_deg - offset_deg + 360.0) % 360.0
    return calibrated - 360.0 if calibrated > 180.0 else calibrated


@dataclass
class Compass:
    """A magnetic compass mounted ``offset_deg`` (θ0) off the body x axis.

    ``read`` gives the raw reading in degrees [0, 360) as such a sensor does;
    ``heading`` applies the calibration of eq. 3–4 and returns radians.

    Parameters
    ----------
    noise_deg : float
        Standard deviation of the reading, degrees.
    offset_deg : float
        Mounting offset θ0, degrees.
    """

    noise_deg: float = 0.0
    offset_deg: float = 0.0

    def __post_init__(self) -> None:
        if self.noise_deg < 0:
            raise ParameterError(f"compass noise must be ≥ 0, got {self.noise_deg}")

    def read(self, true_heading: float, rng: Optional[np.random.Generator] = None) -> float:
        noise = self.noise_deg * rng.standard_normal() if (rng is not None and self.noise_deg) else 0.0
        return (math.degrees(true_heading) + self.offset_deg + noise) % 360.0

    def heading(self, raw_deg: float) -> float:
        """Calibrated heading in radians, (−π, π]."""
        return math.radians(calibrate_heading(raw_deg, self.offset_deg))
