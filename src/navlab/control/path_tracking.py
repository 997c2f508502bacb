"""Tracking a path of poses with reverse stretches: the rear-wheel feedback
law, for cars as well as differential drives and omni robots.

An SE(2) plan (``Result.path`` of poses and ``Result.direction``, +1 forward
and −1 reverse on the way into each pose) is cut at its cusps into
stretches (:func:`split_at_cusps`). Each stretch is tracked as if the robot
drove forward along it: on a reverse stretch the robot is "turned round"
(its travel heading is its heading + π) and the command's speed is negated;
the heading rate is the same either way, so one law serves both.

The law (Samson, 1995; De Luca, Oriolo and Samson, 1998, §4.2) acts on the
reference point nearest the robot's reference point (a car's rear axle):
with ``e`` the signed lateral offset (left positive), ``eθ`` the heading
error and ``κ`` the path's curvature there,

    ω = v·κ·cos(eθ) / (1 − κ·e) − k_θ·v·eθ − k_e·v·sinc(eθ)·e,

which feeds the path's own curvature forward (no corner cutting, unlike
pure pursuit) and makes the errors decay over distance like a critically
damped spring when ``k_θ = 2/ℓ`` and ``k_e = 1/ℓ²`` (``ℓ`` =
``settling_distance``: linearised, e'' + k_θ·e' + k_e·e = 0 in arc length).
A car's steering bound clips ω in the plant; the pose planners leave it
room (they plan at a larger turning radius than the car's smallest, see
:mod:`navlab.sim.pose_path`).

References
----------
C. Samson, "Control of chained systems: application to path following and
time-varying point-stabilization of mobile robots", IEEE Trans. Automatic
Control 40(1), 1995. A. De Luca, G. Oriolo, C. Samson, "Feedback control of
a nonholonomic car-like robot", in *Robot Motion Planning and Control*,
LNCIS 229, Springer 1998.
"""

from __future__ import annotations

import math
from typing import List, Tuple

import numpy as np

from ..errors import ParameterError
from ..limits import is_finite_real, shown
from ..robots.kinematics import _wrap
from .base import CONTROLLERS, REACHED, RUNNING, STALLED, Command, Controller, StallDetector, check_number


#: [m] how far along the stretch the nearest point is looked for each step: a path that passes
#: near itself again (a U-turn) must not pull the reference ahead
SEARCH_WINDOW = 2.0
#: [m] the settling distances rear_wheel_feedback takes: 1e-300 divided its gains by zero, 1e308 overflowed them
SETTLING_RANGE = (1e-3, 1e3)


def split_at_cusps(path, direction) -> List[Tuple[np.ndarray, float]]:
    """The path's stretches between cusps, each ``(poses (M, 2 or 3), sign)``.

    ``direction[i]`` is the direction of travel on the way into pose ``i``, so
    a cusp is a pose ``i`` where ``direction[i + 1] != direction[i]``; it ends
    one stretch and starts the next.
    """
    path = np.asarray(path, float)
    signs = np.where(np.asarray(direction, float) < 0, -1.0, 1.0)
    if len(signs) != len(path):
        raise ParameterError(f"a path of {len(path)} poses needs as many directions, got {len(signs)}")
    cuts = [0, *(i for i in range(1, len(signs) - 1) if signs[i + 1] != signs[i]), len(signs) - 1]
    return [(path[a:b + 1], float(signs[min(a + 1, b)])) for a, b in zip(cuts, cuts[1:]) if b > a]


class _Stretch:
    """One stretch prepared for tracking: points, travel headings, curvature and arc length."""

    def __init__(self, poses: np.ndarray, sign: float) -> None:
        pts = np.ascontiguousarray(poses[:, :2], float)
        if len(pts) < 2:
            pts = np.vstack((pts, pts))
        step = np.diff(pts, axis=0)
        length = np.hypot(*step.T)
        if poses.shape[1] >= 3:
            # the body heading, turned round on a reverse stretch: the way the robot travels
            travel = poses[:, 2] + (math.pi if sign < 0 else 0.0)
        else:
            chord = np.arctan2(step[:, 1], step[:, 0])
            travel = np.append(chord, chord[-1])
        turn = np.array([_wrap(b - a) for a, b in zip(travel[:-1], travel[1:])])
        self.points, self.sign = pts, sign
        self.travel = np.array([_wrap(a) for a in travel])
        self.curvature = np.where(length > 1e-12, turn / np.maximum(length, 1e-12), 0.0)
        self.arc = np.concatenate(([0.0], np.cumsum(length)))  #: arc length at each point
        self.length = float(self.arc[-1])


@CONTROLLERS.register("rear_wheel_feedback")
class RearWheelFeedback(Controller):
    """Follows a path of poses, reversing at its cusps (see the module).

    Parameters
    ----------
    speed : float
        [m/s] Cruising speed (0.5).
    settling_distance : float
        [m] Distance over which an offset from the path dies out (0.5):
        the gains are k_θ = 2/ℓ and k_e = 1/ℓ².
    approach_dist : float
        [m] The speed falls in proportion to the distance left within this
        distance of a cusp or the goal (1.0).
    creep_speed : float
        [m/s] The slowest speed on the way (0.05).
    goal_radius : float
        [m] The run is over within this distance of the last pose, or once
        the robot has passed it (0.03).
    cusp_radius : float
        [m] The next stretch starts within this distance of a cusp, or once
        the robot has passed it (0.05).
    stall_window : float
        [s] STALLED when the distance left along the path has not dropped by
        2 cm in this time (8.0).
    """

    needs_path = True
    speed_setting = "speed"

    def __init__(self, speed: float = 0.5, settling_distance: float = 0.5, approach_dist: float = 1.0,
                 creep_speed: float = 0.05, goal_radius: float = 0.03, cusp_radius: float = 0.05,
                 stall_window: float = 8.0) -> None:
        for name, value in (("speed", speed), ("settling_distance", settling_distance),
                            ("approach_dist", approach_dist), ("creep_speed", creep_speed),
                            ("goal_radius", goal_radius), ("cusp_radius", cusp_radius),
                            ("stall_window", stall_window)):
            if not (is_finite_real(value) and value > 0):
                raise ParameterError(f"rear_wheel_feedback {name} must be a positive number, got {shown(value)}")
        # its gains are 2/d and 1/d²
        check_number("rear_wheel_feedback settling_distance", settling_distance, low=SETTLING_RANGE[0],
                     allow_low=True, high=SETTLING_RANGE[1])
        if creep_speed > speed:
            raise ParameterError(f"rear_wheel_feedback creep_speed ({creep_speed:g}) must not exceed speed ({speed:g})")
        self.speed, self.creep_speed = float(speed), float(creep_speed)
        self.k_heading, self.k_offset = 2.0 / settling_distance, 1.0 / settling_distance ** 2
        self.approach_dist, self.goal_radius, self.cusp_radius = approach_dist, goal_radius, cusp_radius
        self.stall = StallDetector(stall_window, 0.02)
        self._stretches: List[_Stretch] = []
        self._index = 0
        self._after = 0.0

    def reset(self, goal, path=None, direction=None) -> None:
        poses = np.asarray(path if path is not None else [goal], float)
        if poses.ndim != 2 or len(poses) == 0:
            raise ParameterError("rear_wheel_feedback needs a path of at least one pose")
        signs = np.ones(len(poses)) if direction is None else direction
        self._stretches = [_Stretch(p, s) for p, s in reversed(split_at_cusps(poses, signs))]
        self.stall.reset()
        self._next()

    def _next(self) -> None:
        self.current = self._stretches.pop()
        self._index = 0
        self._after = sum(s.length for s in self._stretches)

    def _project(self, xy: np.ndarray) -> Tuple[int, float, float]:
        """(segment, fraction, arc length) of the point of the stretch nearest ``xy``, searched from
        the last segment on (the robot does not go back along a stretch)."""
        s = self.current
        stop = int(np.searchsorted(s.arc, s.arc[self._index] + SEARCH_WINDOW)) + 1
        a = s.points[self._index:min(stop, len(s.points) - 1)]
        d = s.points[self._index + 1:self._index + 1 + len(a)] - a
        dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-24)
        u = np.clip(np.einsum("ij,ij->i", xy - a, d) / dd, 0.0, 1.0)
        near = a + u[:, None] * d
        k = int(np.argmin(np.hypot(*(near - xy).T)))
        i = self._index + k
        return i, float(u[k]), float(s.arc[i] + u[k] * (s.arc[i + 1] - s.arc[i]))

    def _passed_end(self, xy: np.ndarray) -> bool:
        s = self.current
        tangent = np.array((math.cos(s.travel[-1]), math.sin(s.travel[-1])))
        return float((xy - s.points[-1]) @ tangent) >= 0.0

    def command(self, t: float, pose, points=None) -> Command:
        xy = np.asarray(pose[:2], float)
        while True:
            i, u, at = self._project(xy)
            self._index = i
            left = self.current.length - at
            end_dist = math.hypot(*(xy - self.current.points[-1]))
            done = end_dist < (self.cusp_radius if self._stretches else self.goal_radius) or \
                (left < 1e-9 and self._passed_end(xy))
            if not done:
                break
            if not self._stretches:
                return Command(status=REACHED)
            self._next()
        if self.stall.stalled(t, left + self._after):
            return Command(status=STALLED)
        s = self.current
        p = s.points[i] + u * (s.points[i + 1] - s.points[i])
        phi = s.travel[i] + u * _wrap(s.travel[i + 1] - s.travel[i])
        kappa = s.curvature[i]
        offset = -math.sin(phi) * (xy[0] - p[0]) + math.cos(phi) * (xy[1] - p[1])
        heading_error = _wrap(pose[2] + (math.pi if s.sign < 0 else 0.0) - phi)
        v = min(self.speed, max(self.creep_speed, self.speed * max(left, end_dist) / self.approach_dist))
        sinc = math.sin(heading_error) / heading_error if abs(heading_error) > 1e-9 else 1.0
        feed = v * kappa * math.cos(heading_error) / max(1.0 - kappa * offset, 0.1)
        omega = feed - self.k_heading * v * heading_error - self.k_offset * v * sinc * offset
        return Command(s.sign * v, 0.0, omega, RUNNING)
