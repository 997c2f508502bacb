"""When measurements reach the controller: sensor rates and latencies.

Seed 004 measured its ROS topics' delays (Tables 3–4): LiDAR ``/scan``
0.50 s on average (0.26–0.74 s over ten tests) and odometry ``/odom`` 0.08 s
(0.06–0.10 s). A :class:`SensorTiming` says how often a sensor samples and
how late each sample arrives; a :class:`DelayLine` holds the samples in
flight so that the controller acts on the newest one that has arrived —
the measurement taken ``latency`` seconds ago.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
from ..errors import ParameterError
from ..limits import is_finite_real, shown

#: [s] slack when comparing times built from sums of steps
_EPS = 1e-9


@dataclass(frozen=True)
class SensorTiming:
    """Rate and latency of one sensor.

    Parameters
    ----------
    rate : float, optional
        Samples per simulated second (Hz); None samples every step.
    latency : float
        Seconds from a sample to its delivery (≥ 0; 0: at once).
    jitter : float
        Standard deviation (s) of a Gaussian added to each sample's latency,
        drawn from the run's seeded generator (the delay is clipped at 0).
    """

    rate: Optional[float] = None
    latency: float = 0.0
    jitter: float = 0.0

    def __post_init__(self) -> None:
        if self.rate is not None and not (is_finite_real(self.rate) and self.rate > 0):
            raise ParameterError(f"field 'rate' must be a positive number of Hz, got {shown(self.rate)}")
        for name in ("latency", "jitter"):
            value = getattr(self, name)
            if not (is_finite_real(value) and value >= 0):
                raise ParameterError(f"field '{name}' must be a number of seconds ≥ 0, got {shown(value)}")

    @property
    def immediate(self) -> bool:
        """Every step, no delay: the simulator's default."""
        return self.rate is None and self.latency == 0 and self.jitter == 0

    @classmethod
    def from_dict(cls, data: Optional[Dict[str, Any]], what: str) -> "SensorTiming":
        """From ``{rate, latency, jitter}``; errors name ``what`` and the field."""
        if data is None:
            return cls()
        if isinstance(data, SensorTiming):
            return data
        if not isinstance(data, dict):
            raise ParameterError(f"{what}: expected a mapping {{rate, latency, jitter}}, got {data!r}")
        unknown = sorted(set(data) - {"rate", "latency", "jitter"})
        if unknown:
            raise ParameterError(f"{what}: field '{unknown[0]}' is not one of rate, latency, jitter")
        try:
            return cls(**data)
        except ValueError as exc:
            raise ParameterError(f"{what}: {exc}") from None


class DelayLine:
    """Samples in flight from a sensor to the controller.

    Parameters
    ----------
    timing : SensorTiming
    rng : numpy.random.Generator, optional
        Draws the jitter (needed when ``timing.jitter`` > 0).
    initial : object, optional
        What :meth:`read` returns before the first sample arrives.
    """

    def __init__(self, timing: SensorTiming, rng: Optional[np.random.Generator] = None, initial: Any = None) -> None:
        self.timing = timing
        self.rng = rng
        self.period = 1.0 / timing.rate if timing.rate else 0.0
        self._next = 0.0
        self._count = 0
        self._flight: List[Tuple[float, float, Any]] = []  # (delivery time, sample time, value)
        self.value = initial
        self.sample_time = -math.inf  #: when the value read last was measured

    def due(self, t: float) -> bool:
        """Whether the sensor samples at time ``t``."""
        return t + _EPS >= self._next

    def push(self, t: float, value: Any) -> None:
        """A sample taken at ``t``; it arrives ``latency`` (± jitter) later."""
        delay = self.timing.latency
        if self.timing.jitter and self.rng is not None:
            delay = max(0.0, delay + self.timing.jitter * float(self.rng.standard_normal()))
        self._flight.append((t + delay, t, value))
        self._count += 1
        # the k-th sample is due at k·period (no drift from adding periods)
        self._next = self._count * self.period if self.period else t

    def read(self, t: float) -> Any:
        """The newest sample (by sampling time) that has arrived by ``t``."""
        if self._flight:
            keep = []
            for item in self._flight:
                if item[0] <= t + _EPS:
                    if item[1] > self.sample_time:
                        self.sample_time, self.value = item[1], item[2]
                else:
                    keep.append(item)
            self._flight = keep
        return self.value
