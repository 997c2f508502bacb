"""Path followers for a differential drive: seed 002's goto_waypoint and
pure pursuit, optionally replanning when the path ahead is blocked."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..errors import ParameterError
from ..limits import check_flag, check_length, is_finite_real, shown
from ..robots.kinematics import _wrap
from .base import CONTROLLERS, REACHED, RUNNING, STALLED, Command, Controller, StallDetector, check_number
from .path_tracking import split_at_cusps


class _Follower(Controller):
    """What both followers share: the path, the stall detector and the
    ``replan`` option. With ``replan`` the follower reads the LiDAR; when a
    sensed point the map does not explain lies on the next ``check_ahead``
    metres of the path it stops, and plans again from where it is around
    what it sees (at most every ``replan_interval`` s); it drives on when the
    path ahead is clear again (the obstacle has passed) or a new path is."""

    needs_path = True
    speed_setting = "speed"

    def __init__(self, stall_window: float = 8.0, stall_progress: float = 0.02, replan: bool = False,
                 replan_interval: float = 1.0, check_ahead: float = 1.0) -> None:
        replan = check_flag("replan", replan)
        for name, value in (("replan_interval", replan_interval), ("check_ahead", check_ahead)):
            if not (is_finite_real(value) and value > 0):
                raise ParameterError(f"{name} must be a positive number, got {shown(value)}")
        self.stall = StallDetector(stall_window, stall_progress)
        self.path = np.zeros((1, 2))
        self.index = 0
        self.replan, self.replan_interval, self.check_ahead = replan, replan_interval, check_ahead
        self.needs_scan = replan
        self.replanner = None  #: set by the simulator when ``replan`` is on
        self.evade_speed = 0.22  #: [m/s] speed at which the robot gets out of a moving obstacle's way
        self._last_replan = -math.inf

    def _ahead(self, pose) -> np.ndarray:
        """The path from the robot over the next ``check_ahead`` metres."""
        pts = [np.asarray(pose[:2], float)]
        left = self.check_ahead
        for q in self.path[self.index:]:
            step = float(np.hypot(*(q - pts[-1])))
            if step >= left:
                pts.append(pts[-1] + (q - pts[-1]) * (left / step))
                break
            pts.append(q)
            left -= step
        return np.asarray(pts)

    def _evade(self, pose) -> Optional[Command]:
        """Back away from (or drive on ahead of) a moving obstacle whose
        predicted sweep covers the robot, keeping the heading."""
        threat = getattr(self.replanner, "threat", None)
        if threat is None:
            return None
        centre, v = threat
        away = np.asarray(pose[:2], float) - centre
        speed = float(np.hypot(*v))
        if speed > 0:  # leave the obstacle's line of travel rather than run ahead of it
            u = v / speed
            away = away - (away @ u) * u
        forward = math.cos(pose[2]) * away[0] + math.sin(pose[2]) * away[1] >= 0
        return Command(self.evade_speed if forward else -self.evade_speed, 0.0, 0.0)

    def _wait_or_replan(self, t: float, pose, points) -> bool:
        """True when the robot should hold still this step (path ahead blocked)."""
        if not self.replan or self.replanner is None:
            return False
        self.replanner.observe(t, pose, points)
        if not self.replanner.blocked(pose, self._ahead(pose), points):
            return False
        if t - self._last_replan >= self.replan_interval:
            self._last_replan = t
            new = self.replanner.plan(pose, points)
            if new is not None:
                self.path, self.index = new, 1
                self.stall.reset()
                return self.replanner.blocked(pose, self._ahead(pose), points)
        return True

    def reset(self, goal, path=None) -> None:
        pts = np.asarray(path if path is not None else [goal], float)[:, :2]
        if len(pts) == 0:
            raise ParameterError("a path follower needs at least one waypoint")
        self.path = pts
        self.index = 1 if len(pts) > 1 else 0
        self.stall.reset()
        self._last_replan = -math.inf

    def _stalled(self, t: float, pose) -> bool:
        # progress towards the current waypoint, measured along the remaining path
        remaining = math.hypot(*(self.path[self.index] - pose[:2])) + \
            float(np.sum(np.linalg.norm(np.diff(self.path[self.index:], axis=0), axis=1)))
        return self.stall.stalled(t, remaining)


@CONTROLLERS.register("goto_waypoint")
class GotoWaypoint(_Follower):
    """Seed 002's follower: proportional control on the heading error to the
    next waypoint; when the error is large it turns harder and slows down; a
    waypoint counts as reached inside ``reach_radius``; it stops at the last.

    Parameters
    ----------
    speed : float
        Forward speed when roughly on course (m/s).
    heading_gain : float
        Turn rate per radian of heading error (1/s).
    turn_threshold : float
        Heading error (rad) above which it turns in place-ish: speed drops to
        ``slow_speed`` and the gain is multiplied by ``turn_boost``.
    reach_radius : float
        Waypoint tolerance (m); the last waypoint uses ``goal_radius``.
    replan, replan_interval, check_ahead :
        Stop and replan when a sensed obstacle blocks the next
        ``check_ahead`` m of the path, at most every ``replan_interval`` s
        (see the base class; the simulator supplies the planner).
    """

    def __init__(self, speed: float = 0.2, heading_gain: float = 1.5, turn_threshold: float = 0.5,
                 slow_speed: float = 0.02, turn_boost: float = 1.5, reach_radius: float = 0.1,
                 goal_radius: float = 0.05, stall_window: float = 8.0, replan: bool = False,
                 replan_interval: float = 1.0, check_ahead: float = 1.0) -> None:
        super().__init__(stall_window, replan=replan, replan_interval=replan_interval, check_ahead=check_ahead)
        for name, value in (("speed", speed), ("heading_gain", heading_gain), ("reach_radius", reach_radius),
                            ("goal_radius", goal_radius), ("turn_threshold", turn_threshold)):
            check_number(f"goto_waypoint {name}", value)  # a positive finite number ('fast' named, not a TypeError)
        check_number("goto_waypoint slow_speed", slow_speed, allow_low=True)  # 0: turn on the spot
        check_number("goto_waypoint turn_boost", turn_boost)
        self.speed, self.heading_gain, self.turn_threshold = speed, heading_gain, turn_threshold
        self.slow_speed, self.turn_boost = slow_speed, turn_boost
        self.reach_radius, self.goal_radius = reach_radius, goal_radius

    def command(self, t: float, pose, points=None) -> Command:
        last = len(self.path) - 1
        while True:
            dx, dy = self.path[self.index] - pose[:2]
            dist = math.hypot(dx, dy)
            if dist >= (self.goal_radius if self.index == last else self.reach_radius):
                break
            if self.index == last:
                return Command(status=REACHED)
            self.index += 1
        if self._stalled(t, pose):
            return Command(status=STALLED)
        if self._wait_or_replan(t, pose, points):
            return self._evade(pose) or Command()
        dx, dy = self.path[self.index] - pose[:2]
        dist = math.hypot(dx, dy)
        error = _wrap(math.atan2(dy, dx) - pose[2])
        if abs(error) > self.turn_threshold:
            return Command(self.slow_speed, 0.0, self.turn_boost * self.heading_gain * error)
        # slow down near the final waypoint so the robot stops inside goal_radius
        v = self.speed * math.cos(error)
        if self.index == last:
            v = min(v, max(0.05, dist))
        return Command(v, 0.0, self.heading_gain * error, RUNNING)


@CONTROLLERS.register("pure_pursuit")
class PurePursuit(_Follower):
    """Pure pursuit: steer on the arc through the path point ``lookahead``
    metres ahead (curvature 2·sin(α)/L).

    A path of poses with a direction of travel (an SE(2) plan: ``Result.path``
    and ``Result.direction``) is followed stretch by stretch, as Nav2's
    Regulated Pure Pursuit does with ``allow_reversing``: the path is cut at
    its cusps; a reverse stretch is pursued backwards (the arc is computed for
    the robot turned round, then driven at negative speed); the robot slows
    towards each cusp and moves on to the next stretch within ``cusp_radius``
    of the cusp or once it has passed it. On such paths it never turns in
    place, so it drives a car (whose turn rate its steering bounds) as well as
    a differential drive or an omni robot.

    References
    ----------
    R. C. Coulter, "Implementation of the pure pursuit path tracking
    algorithm", CMU-RI-TR-92-01, 1992. S. Macenski et al., "Regulated Pure
    Pursuit for Robot Path Tracking", Autonomous Robots 47, 2023 (reversing
    at cusps).
    """

    def __init__(self, lookahead: float = 0.2, speed: float = 0.2, goal_radius: float = 0.05,
                 stall_window: float = 8.0, replan: bool = False, replan_interval: float = 1.0,
                 check_ahead: float = 1.0, cusp_radius: float = 0.1) -> None:
        super().__init__(stall_window, replan=replan, replan_interval=replan_interval, check_ahead=check_ahead)
        for name, value in (("lookahead", lookahead), ("speed", speed), ("goal_radius", goal_radius),
                            ("cusp_radius", cusp_radius)):
            check_number(f"pure_pursuit {name}", value)  # a positive finite number ('fast' named, not a TypeError)
            if name != "speed":  # a length within navlab's range (1e300 overflowed squaring the lookahead)
                check_length(f"pure_pursuit {name}", value, allow_zero=False)
        self.lookahead, self.speed, self.goal_radius, self.cusp_radius = lookahead, speed, goal_radius, cusp_radius
        self._stretches: list = []  #: (points, sign) of each stretch between cusps, for paths with directions
        self._sign = 1.0
        self._after = 0.0  #: [m] length of the stretches after the current one
        self._directed = False  #: following a path with directions of travel

    def reset(self, goal, path=None, direction=None) -> None:
        super().reset(goal, path)
        self._stretches, self._sign, self._after = [], 1.0, 0.0
        self._directed = direction is not None
        if direction is None:
            return
        if self.replan:
            raise ParameterError("pure_pursuit cannot replan a path with headings and reverse stretches; leave replan off")
        self._stretches = split_at_cusps(self.path, direction)[::-1]  # popped from the end
        self._next_stretch()

    def _next_stretch(self) -> None:
        points, self._sign = self._stretches.pop()
        self.path, self.index = points, 1 if len(points) > 1 else 0
        self._after = sum(float(np.sum(np.hypot(*np.diff(p, axis=0).T))) for p, _ in self._stretches)

    def _stalled(self, t: float, pose) -> bool:
        remaining = math.hypot(*(self.path[self.index] - pose[:2])) + \
            float(np.sum(np.linalg.norm(np.diff(self.path[self.index:], axis=0), axis=1))) + self._after
        return self.stall.stalled(t, remaining)

    def _at_cusp(self, pose) -> bool:
        """Whether the robot has come to the end of a stretch that a cusp follows."""
        end = self.path[-1]
        offset = pose[:2] - end
        if math.hypot(*offset) < self.cusp_radius:
            return True
        if len(self.path) < 2 or math.hypot(*offset) > self.lookahead:
            return False
        tangent = end - self.path[-2]  # the way the stretch runs into the cusp
        return float(offset @ tangent) >= 0.0

    def _target(self, pose) -> np.ndarray:
        """The first point at distance ≥ lookahead on the path after the
        closest point (the path's end when none is that far)."""
        p = pose[:2]
        while self.index < len(self.path) - 1 and \
                np.linalg.norm(self.path[self.index] - p) < self.lookahead:
            self.index += 1
        a = self.path[self.index - 1] if self.index > 0 else p
        b = self.path[self.index]
        # the point on segment ab at distance lookahead from p (if any)
        d = b - a
        f = a - p
        qa, qb, qc = d @ d, 2 * f @ d, f @ f - self.lookahead ** 2
        disc = qb * qb - 4 * qa * qc
        if qa > 0 and disc >= 0:
            u = (-qb + math.sqrt(disc)) / (2 * qa)
            if 0 <= u <= 1:
                return a + u * d
        return b

    def command(self, t: float, pose, points=None) -> Command:
        while self._stretches and self._at_cusp(pose):
            self._next_stretch()
        goal = self.path[-1]
        dist = math.hypot(*(goal - pose[:2]))
        if dist < self.goal_radius and not self._stretches:
            return Command(status=REACHED)
        if self._stalled(t, pose):
            return Command(status=STALLED)
        if self._wait_or_replan(t, pose, points):
            return self._evade(pose) or Command()
        tx, ty = self._target(pose) - pose[:2]
        ld = max(math.hypot(tx, ty), 1e-9)
        last = self.index == len(self.path) - 1
        v = max(self.speed * min(1.0, dist / self.lookahead) if last else self.speed, 0.03)
        if self._directed:
            # pursue in the direction of travel: backwards, the arc is the one of the robot turned round
            alpha = _wrap(math.atan2(ty, tx) - pose[2] - (math.pi if self._sign < 0 else 0.0))
            return Command(self._sign * v, 0.0, v * 2.0 * math.sin(alpha) / ld)
        alpha = _wrap(math.atan2(ty, tx) - pose[2])
        if abs(alpha) > math.pi / 2:  # target behind: turn in place first
            return Command(0.0, 0.0, math.copysign(1.5, alpha))
        return Command(v, 0.0, v * 2.0 * math.sin(alpha) / ld)
