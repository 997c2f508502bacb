"""Wheeled-robot kinematics: a differential drive, a three-wheel omni and a car
(the kinematic bicycle).

Frames: the *body* frame has x forward and y to the left of the robot; the
*world* frame is the map's. A pose is ``(x, y, θ)`` in the world frame, θ the
heading of the body x axis (radians, counter-clockwise). Body velocities
``(vx, vy, ω)`` are rotated into the world by θ (:func:`body_to_world`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Optional, Tuple

import numpy as np

from ..angles import wrap_angle as _wrap
from ..errors import ParameterError
from ..limits import check_length, is_finite_real, shown
from ..registry import Registry
from ..world.footprint import Footprint

ROBOTS: Registry[type] = Registry("robot")


def body_to_world(theta: float, vx: float, vy: float) -> Tuple[float, float]:
    """Rotate a body-frame vector into the world frame."""
    c, s = math.cos(theta), math.sin(theta)
    return c * vx - s * vy, s * vx + c * vy


def world_to_body(theta: float, wx: float, wy: float) -> Tuple[float, float]:
    """Rotate a world-frame vector into the body frame."""
    c, s = math.cos(theta), math.sin(theta)
    return c * wx + s * wy, -s * wx + c * wy


def integrate_pose(pose: np.ndarray, vx: float, vy: float, omega: float, dt: float) -> np.ndarray:
    """Exact pose after moving for ``dt`` at a constant body twist (vx, vy, ω):
    the body velocity rotates with the heading, so the path is a circular arc
    (a straight line when ω = 0)."""
    x, y, th = pose
    dth = omega * dt
    if abs(dth) < 1e-9:
        # second-order expansion: exact to rounding for tiny turns
        mid = th + 0.5 * dth
        wx, wy = body_to_world(mid, vx, vy)
        return np.array((x + wx * dt, y + wy * dt, _wrap(th + dth)))
    # ∫ R(th + ω t) v dt = (R(th + dth) − R(th)) J⁻¹ v / ω with J the 90° rotation
    s0, c0 = math.sin(th), math.cos(th)
    s1, c1 = math.sin(th + dth), math.cos(th + dth)
    dx = (vx * (s1 - s0) + vy * (c1 - c0)) / omega
    dy = (vx * (c0 - c1) + vy * (s1 - s0)) / omega
    return np.array((x + dx, y + dy, _wrap(th + dth)))


#: the robots' settings that are lengths [m]: positive and within navlab's length range (a 1e300 m
#: radius passed as a positive number and overflowed squaring it in the simulator's collision check)
LENGTHS = ("radius", "wheel_radius", "track", "base_radius", "wheelbase")


def _positive(name: str, value: float) -> float:
    """``value`` as a float, if a positive finite number (numpy's too: np.float32(0.05) was refused as not a
    number; API attack, session 29) and, for a length, within navlab's range."""
    if not (is_finite_real(value) and value > 0):
        raise ParameterError(f"{name} must be a positive number, got {shown(value)}")
    if name in LENGTHS:
        check_length(name, value, allow_zero=False)
    return float(value)


def _set_positive(robot, names) -> None:
    """Each of the ``names`` settings of ``robot``, checked by :func:`_positive`, as a float."""
    for name in names:
        setattr(robot, name, _positive(name, getattr(robot, name)))


def accelerate(previous, command, dt: float, max_accel: Optional[float], max_angular_accel: Optional[float]):
    """The twist reached from ``previous`` towards ``command`` within ``dt`` under the
    acceleration limits (m/s² on the linear part, as a vector; rad/s² on ω); None is no limit."""
    vx, vy, w = command
    if max_accel is not None:
        dvx, dvy = vx - previous[0], vy - previous[1]
        change = math.hypot(dvx, dvy)
        room = max_accel * dt
        if change > room:
            vx, vy = previous[0] + dvx * room / change, previous[1] + dvy * room / change
    if max_angular_accel is not None:
        room = max_angular_accel * dt
        w = min(max(w, previous[2] - room), previous[2] + room)
    return vx, vy, w


class _Shaped:
    """What every robot shares: its footprint and acceleration limits."""

    def _check_shape(self) -> None:
        _set_positive(self, [name for name in ("max_accel", "max_angular_accel") if getattr(self, name) is not None])
        if self.footprint is not None:
            self.footprint = Footprint.from_value(self.footprint, "footprint")

    @property
    def shape(self) -> Footprint:
        """The robot's footprint: the given polygon, or the disc of ``radius``."""
        return self.footprint if self.footprint is not None else Footprint.disc(self.radius)

    @property
    def planning_radius(self) -> float:
        """The clearance a global planner keeps: the disc's radius, or a polygon
        footprint's inscribed radius (Nav2 plans the centre on cells below
        ``INSCRIBED``; the local controller checks the whole footprint)."""
        return self.shape.inscribed_radius


@ROBOTS.register("diff")
@dataclass
class DiffDrive(_Shaped):
    """A differential-drive robot; the defaults are a TurtleBot3 Burger.

    Parameters
    ----------
    wheel_radius : float
        m (0.033).
    track : float
        Distance between the wheels, m (0.160).
    max_speed : float
        m/s (0.22).
    max_turn_rate : float
        rad/s (2.84).
    radius : float
        Footprint radius for collisions, m (0.105).
    footprint : list of [x, y] or Footprint, optional
        A polygon footprint in the body frame, m (default: the disc of ``radius``).
    max_accel, max_angular_accel : float, optional
        Acceleration limits, m/s² and rad/s² (default: none).
    """

    wheel_radius: float = 0.033
    track: float = 0.160
    max_speed: float = 0.22
    max_turn_rate: float = 2.84
    radius: float = 0.105
    footprint: Any = None
    max_accel: Optional[float] = None
    max_angular_accel: Optional[float] = None
    holonomic = False
    n_wheels = 2

    def __post_init__(self) -> None:
        _set_positive(self, ("wheel_radius", "track", "max_speed", "max_turn_rate", "radius"))
        self._check_shape()

    def inverse(self, vx: float, vy: float = 0.0, omega: float = 0.0) -> np.ndarray:
        """Wheel angular speeds (left, right) in rad/s for a body twist; vy is
        ignored (a differential drive cannot move sideways)."""
        half = 0.5 * self.track * omega
        return np.array(((vx - half) / self.wheel_radius, (vx + half) / self.wheel_radius))

    def forward(self, wheel_speeds) -> Tuple[float, float, float]:
        """Body twist (vx, 0, ω) from wheel angular speeds (left, right)."""
        left, right = wheel_speeds[0] * self.wheel_radius, wheel_speeds[1] * self.wheel_radius
        return 0.5 * (left + right), 0.0, (right - left) / self.track

    def limit(self, vx: float, vy: float, omega: float) -> Tuple[float, float, float]:
        """Clip speed and turn rate to the robot's limits (vy is dropped)."""
        return (min(max(vx, -self.max_speed), self.max_speed), 0.0,
                min(max(omega, -self.max_turn_rate), self.max_turn_rate))


@ROBOTS.register("jackal")
@dataclass
class Jackal(DiffDrive):
    """A Clearpath Jackal, as the BARN challenge drives it.

    The footprint is the challenge's rectangle (``costmap_common_params.yaml``:
    0.42 × 0.33 m, centred); speed limits 2.0 m/s and 4.0 rad/s and
    acceleration limits 20 m/s² and 25 rad/s² are Clearpath's
    ``jackal_control/config/control.yaml``; wheel radius 0.098 m and wheel
    separation 0.37559 m its URDF's. ``radius`` is the footprint's inscribed
    radius, the clearance the global planner keeps.
    """

    wheel_radius: float = 0.098
    track: float = 0.37559
    max_speed: float = 2.0
    max_turn_rate: float = 4.0
    radius: float = 0.165
    footprint: Any = ((-0.21, -0.165), (-0.21, 0.165), (0.21, 0.165), (0.21, -0.165))
    max_accel: Optional[float] = 20.0
    max_angular_accel: Optional[float] = 25.0
    #: its front laser as the challenge mounts it (a Hokuyo UST-10LX: 270° in 720 beams; 30 m range)
    laser = {"beams": 720, "fov": math.radians(270.0), "range_max": 30.0, "range_min": 0.06}


@ROBOTS.register("car")
@dataclass
class Car(DiffDrive):
    """A car: the kinematic bicycle model, its pose the middle of the rear axle.

    The rear axle moves along its heading at speed v (forward or reverse) and
    turns at ω = v·tan(δ)/L for a steering angle δ, L the wheelbase, so the
    rear axle's path is made of arcs of radius at least the minimum
    **turning radius** ``L / tan(max_steer)`` — the curves Dubins and
    Reeds–Shepp planners draw (Dubins, 1957; Reeds and Shepp, 1990). The
    steering angle is taken to change at once (no steering-rate limit). The
    encoders sit on the rear wheels, so odometry is a differential drive's
    with the rear track. The defaults are a compact car, as the ``parking``
    scene's: 4.4 × 1.8 m with the rear axle 1.0 m from the back, wheelbase
    2.7 m, maximum steering atan(2.7 / 4.5) ≈ 30.96°, hence a 4.5 m turning radius.

    Parameters
    ----------
    wheelbase : float
        Rear axle to front axle, m (2.7).
    max_steer : float
        Largest steering angle, rad (atan(2.7/4.5) ≈ 0.5404, below π/2).
    track : float
        Distance between the rear wheels, m (1.55).
    wheel_radius : float
        m (0.3).
    max_speed : float
        Forward and reverse, m/s (2.0).
    footprint : list of [x, y] or Footprint
        In the rear-axle frame, m (the 4.4 × 1.8 m rectangle from x = −1.0 to 3.4).
    radius : float
        The footprint's inscribed radius (0.9 m): the clearance a point planner keeps.

    References
    ----------
    R. Rajamani, *Vehicle Dynamics and Control*, 2nd ed., Springer 2012, §2.2
    (the kinematic bicycle model). L. E. Dubins, "On curves of minimal length
    with a constraint on average curvature", Am. J. Math. 79(3), 1957.
    """

    wheelbase: float = 2.7
    max_steer: float = math.atan2(2.7, 4.5)
    track: float = 1.55
    wheel_radius: float = 0.3
    max_speed: float = 2.0
    max_turn_rate: float = 10.0  #: [rad/s] only a cap on ω; the steering limit |ω| ≤ |v|/turning_radius binds first
    radius: float = 0.9
    footprint: Any = ((-1.0, -0.9), (3.4, -0.9), (3.4, 0.9), (-1.0, 0.9))
    max_accel: Optional[float] = 2.0
    max_angular_accel: Optional[float] = None
    steers = True  #: cannot turn in place: its turn rate is bounded by its speed

    def __post_init__(self) -> None:
        super().__post_init__()
        _set_positive(self, ("wheelbase", "max_steer"))
        if not self.max_steer < 0.5 * math.pi:
            raise ParameterError(f"max_steer must be below π/2 rad (90°), got {self.max_steer!r}")

    @property
    def turning_radius(self) -> float:
        """The rear axle's smallest turning radius, m: ``wheelbase / tan(max_steer)``."""
        return self.wheelbase / math.tan(self.max_steer)

    def steering_angle(self, vx: float, omega: float) -> float:
        """The steering angle δ that turns at ω while driving at vx (0 when standing)."""
        return 0.0 if vx == 0.0 else math.atan(omega * self.wheelbase / vx)

    def limit(self, vx: float, vy: float, omega: float) -> Tuple[float, float, float]:
        """Clip the speed, drop vy, and bound the turn rate by the steering:
        |ω| ≤ |vx| / turning_radius (a car standing still cannot turn)."""
        vx, _, omega = super().limit(vx, 0.0, omega)
        return vx, 0.0, self.steer(vx, omega)

    def steer(self, vx: float, omega: float) -> float:
        """ω clipped to what the steering allows at speed vx."""
        most = abs(vx) / self.turning_radius
        return min(max(omega, -most), most)


@ROBOTS.register("omni3")
@dataclass
class Omni3(_Shaped):
    """A three-wheel omnidirectional robot (seed 004).

    Wheel i sits at angle θi in the body frame, at distance ``base_radius`` L
    from the centre, and drives along the tangent direction θi + π/2. The
    rim speed of wheel i for a body twist (vx, vy, ω) is

        v_i = cos(θi + π/2)·vx + sin(θi + π/2)·vy + L·ω,

    so ``inverse`` is the matrix J with rows [cos(θi + π/2), sin(θi + π/2), L]
    (divided by the wheel radius for angular speeds), and ``forward`` is its
    inverse J⁻¹. For wheels 120° apart, J⁻¹ = [[2/3·cos(θi + π/2)],
    [2/3·sin(θi + π/2)], [1/(3L)]] column by column, the form of the seed's
    eq. 1 once its missing factor 2/3 is restored; the seed's printed eq. 2
    is not the inverse of its eq. 1. ``forward`` uses the exact inverse for
    any wheel angles.

    References
    ----------
    R. Rojas, A. G. Förster, "Holonomic control of a robot with an
    omnidirectional drive", KI – Künstliche Intelligenz 20(2), 2006.
    K. M. Lynch, F. C. Park, *Modern Robotics*, Cambridge UP, 2017, §13.2.
    """

    wheel_radius: float = 0.03
    base_radius: float = 0.12
    wheel_angles_deg: Tuple[float, float, float] = (30.0, 150.0, 270.0)
    max_speed: float = 0.35
    max_turn_rate: float = 3.0
    max_wheel_speed: float = 20.0  #: rad/s per wheel
    radius: float = 0.16
    footprint: Any = None  #: a polygon in the body frame (default: the disc of ``radius``)
    max_accel: Optional[float] = None  #: m/s² (default: none)
    max_angular_accel: Optional[float] = None  #: rad/s² (default: none)
    holonomic = True
    n_wheels = 3
    _J: np.ndarray = field(init=False, repr=False)
    _Jinv: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        _set_positive(self, ("wheel_radius", "base_radius", "max_speed", "max_turn_rate", "max_wheel_speed", "radius"))
        self._check_shape()
        angles = self.wheel_angles_deg
        try:  # (a single number, a string or a set was a TypeError, an internal error: attack run, session 18)
            degrees = np.asarray(angles, dtype=float) if isinstance(angles, (list, tuple, np.ndarray)) else None
        except (TypeError, ValueError, OverflowError):
            degrees = None
        if degrees is None or degrees.shape != (3,) or not np.isfinite(degrees).all():
            raise ParameterError(f"wheel_angles_deg must be three finite angles in degrees, [a, b, c], "
                                 f"got {shown(angles)}")
        drive = np.radians(degrees) + np.pi / 2
        self._J = np.column_stack((np.cos(drive), np.sin(drive), np.full(3, self.base_radius)))
        if abs(np.linalg.det(self._J)) < 1e-9:
            raise ParameterError(f"wheel angles {self.wheel_angles_deg} cannot drive every body twist")
        self._Jinv = np.linalg.inv(self._J)

    @property
    def inverse_matrix(self) -> np.ndarray:
        """J: rim speeds = J @ (vx, vy, ω)."""
        return self._J.copy()

    @property
    def forward_matrix(self) -> np.ndarray:
        """J⁻¹: (vx, vy, ω) = J⁻¹ @ rim speeds."""
        return self._Jinv.copy()

    def inverse(self, vx: float, vy: float = 0.0, omega: float = 0.0) -> np.ndarray:
        """Wheel angular speeds (rad/s) for a body twist."""
        return (self._J @ np.array((vx, vy, omega))) / self.wheel_radius

    def forward(self, wheel_speeds) -> Tuple[float, float, float]:
        """Body twist (vx, vy, ω) from wheel angular speeds (rad/s)."""
        v = self._Jinv @ (np.asarray(wheel_speeds, float) * self.wheel_radius)
        return float(v[0]), float(v[1]), float(v[2])

    def limit(self, vx: float, vy: float, omega: float) -> Tuple[float, float, float]:
        """Scale the twist down (direction kept) to the speed, turn-rate and
        wheel-speed limits."""
        scale = 1.0
        speed = math.hypot(vx, vy)
        if speed > self.max_speed:
            scale = self.max_speed / speed
        if abs(omega) * scale > self.max_turn_rate:
            scale = self.max_turn_rate / abs(omega)
        wheels = np.abs(self.inverse(vx, vy, omega)).max() * scale
        if wheels > self.max_wheel_speed:
            scale *= self.max_wheel_speed / wheels
        return vx * scale, vy * scale, omega * scale


def make_robot(name: str, **params) -> object:
    """A registered robot by name (``diff``, ``omni3``, ``jackal``, ``car``) with its settings."""
    from ..registry import check_finite, check_params

    cls = ROBOTS.get(name)
    check_params(cls, params, f"robot '{name}'")
    check_finite(params, f"robot '{name}'", cls)
    try:
        return cls(**params)
    except ParameterError as exc:  # named as the checks above name it (--robot-param radius=-1 said only
        # "radius must be a positive number", where --controller-param's say "controller 'rpp': ...": newcomer, s31)
        raise ParameterError(f"robot '{name}': {exc}") from None
