"""What every controller shares: a command, a status and the registry."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional

from ..errors import ParameterError
from ..limits import is_finite_real, shown
from ..registry import Registry

CONTROLLERS: Registry[Callable[..., "Controller"]] = Registry("controller")

RUNNING, REACHED, STALLED = "RUNNING", "REACHED", "STALLED"


@dataclass
class Command:
    """A body-frame twist and what the controller thinks of the run."""

    vx: float = 0.0
    vy: float = 0.0
    omega: float = 0.0
    status: str = RUNNING


class Controller:
    """Maps the robot's pose estimate (and LiDAR points) to a body twist.

    ``needs_path`` controllers follow waypoints (``reset(goal, path)``);
    ``needs_scan`` controllers read obstacle points from the LiDAR.
    """

    needs_path = False
    needs_scan = False
    holonomic = False  #: commands a sideways velocity
    #: the setting that is the controller's top forward speed (m/s), if it has one: the simulator refuses a
    #: value above the robot's ``max_speed`` (the robot would cut the speed and not the turn rate)
    speed_setting: Optional[str] = None
    #: why its last STALLED command stalled, where the controller knows more than :meth:`why_stalled` says
    stall_reason: Optional[str] = None

    def reset(self, goal, path=None) -> None:
        raise NotImplementedError

    def why_stalled(self) -> str:
        """Why a STALLED run stalled, as the simulator reports it: a path follower's progress is along its
        path, where "a local minimum?" (a field's trouble) misled (newcomer run, session 17)."""
        if self.stall_reason:
            return self.stall_reason
        if self.needs_path:
            return "no progress along its path (blocked, or a path the robot cannot follow)"
        return "no progress towards the goal (a local minimum?)"

    def command(self, t: float, pose, points=None) -> Command:
        raise NotImplementedError


def check_number(name: str, value: Any, low: float = 0.0, allow_low: bool = False,
                 high: float = math.inf) -> float:
    """``value`` as a float in (low, high] (or [low, high] with ``allow_low``), else ParameterError naming it."""
    if not is_finite_real(value):  # (math.isfinite overflowed on 10**400: an internal error until session 18)
        raise ParameterError(f"{name} must be a finite number, got {shown(value)}")
    value = float(value)
    if value < low or (value == low and not allow_low) or value > high:
        bound = f"{'≥' if allow_low else '>'} {low:g}" + (f" and ≤ {high:g}" if math.isfinite(high) else "")
        raise ParameterError(f"{name} must be {bound}, got {value!r}")
    return value


def make_controller(name: str, **params) -> Controller:
    from ..registry import UnknownNameError, check_finite, check_params

    factory = CONTROLLERS.get(name)
    check_params(factory, params, f"controller '{name}'")
    check_finite(params, f"controller '{name}'", factory)
    try:
        return factory(**params)
    except ValueError as exc:  # a setting out of range: say whose, as the checks above do (same type)
        message = str(exc)
        if not isinstance(exc, UnknownNameError) and not message.startswith((f"{name} ", f"controller '{name}'")):
            exc.args = (f"controller '{name}': {message}",) + exc.args[1:]
        raise


class StallDetector:
    """Flags a run that stops getting closer to its goal: the distance has
    not dropped by ``progress`` metres over the last ``window`` seconds."""

    def __init__(self, window: float = 4.0, progress: float = 0.03) -> None:
        # (a number's checks: a string was an internal TypeError)
        self.window, self.progress = check_number("stall_window", window), check_number("stall_progress", progress)
        self._t0: Optional[float] = None
        self._best = float("inf")

    def reset(self) -> None:
        self._t0, self._best = None, float("inf")

    def stalled(self, t: float, distance: float) -> bool:
        if self._t0 is None or distance < self._best - self.progress:
            self._t0, self._best = t, min(distance, self._best)
            return False
        return t - self._t0 > self.window
