"""Regulated Pure Pursuit, as Nav2's ``nav2_regulated_pure_pursuit_controller``.

S. Macenski, S. Singh, F. Martín, J. Ginés, "Regulated Pure Pursuit for
Robot Path Tracking", Autonomous Robots 47, 2023. Each cycle:

1. **Look-ahead**: ``lookahead_time · |v|`` clipped to ``[min_lookahead_dist,
   max_lookahead_dist]`` (``use_velocity_scaled_lookahead_dist``), else
   ``lookahead_dist``; the carrot is the path point that far from the robot,
   interpolated along the path after the point nearest the robot.
2. **Curvature** of the arc through the carrot: ``κ = 2·y / L²`` with (x, y)
   the carrot in the robot's frame and L its distance.
3. **Regulation** of ``desired_linear_vel``: on tight curves (radius below
   ``regulated_linear_scaling_min_radius`` the speed is scaled by radius /
   that radius); near obstacles (the cost at the robot turned back into a
   distance with the inflation's formula; below ``cost_scaling_dist`` the
   speed is scaled by ``cost_scaling_gain · distance / cost_scaling_dist``);
   approaching the goal (within ``approach_velocity_scaling_dist`` the speed
   falls with the distance); never below ``regulated_linear_scaling_min_speed``
   (except at the goal) and within the acceleration limits.
4. **Rotate to heading**: when the carrot is more than
   ``rotate_to_heading_min_angle`` off the robot's heading, turn in place at
   ``rotate_to_heading_angular_vel`` (limited by ``max_angular_accel``).
5. **Collision look-ahead**: the commanded arc is projected for
   ``max_allowed_time_to_collision_up_to_carrot`` seconds (no farther than the
   carrot) at steps of a costmap cell; if the footprint's outline meets a
   ``LETHAL`` cell, the robot stops (Nav2 aborts; the run then stalls). Nav2's
   ``CollisionChecker::inCollision`` compares the outline's cost with
   ``LETHAL_OBSTACLE``: ``INSCRIBED`` (253) on the outline only says an obstacle
   is within the inscribed radius of the outline, not that the body touches it,
   so treating it as a collision stops a rectangle at every gap narrower than its
   width plus its inscribed diameter.

navlab's extensions (off by default): ``creep_when_blocked`` (creep along the
path where Nav2 would stop) and ``plan_poses``: where the robot has
made no progress for ``pose_plan_after`` s, the costmap feed plans a forward
path of poses for the footprint itself from where it stands
(:func:`~navlab.grid.cost_search.plan_poses_on_costmap`, Hybrid A* with a
``pose_plan_turning_radius`` curve) and RPP tracks it with the path-following
feedback law of Samson (1995),

    ω = v·κ·cos(eθ) / (1 − κ·e) − k_θ·v·eθ − k_e·v·sinc(eθ)·e,

κ the path's curvature at the reference pose nearest the robot, e the robot's
signed lateral offset from it, eθ its heading error, k_θ = 2/ℓ and k_e = 1/ℓ²
with ℓ = ``pose_track_settling`` (linearised in arc length, e'' + k_θ·e' + k_e·e
= 0: critically damped), the speed limited by the curvature ahead (RPP's
curvature regulation, braking at ``max_linear_accel``) and by the cost at the
robot. The curvature is fed forward, so the robot does not cut the corners the
footprint-aware path turns round; pure pursuit does.

C. Samson, "Control of chained systems: application to path following and
time-varying point-stabilization of mobile robots", IEEE Trans. Automatic
Control 40(1), 1995.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..errors import ParameterError
from ..limits import check_flag
from ..world.costmap import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, MAX_NON_OBSTACLE
from .base import CONTROLLERS
from .local import CostmapController, arc_rollouts, check_number


def carrot_on_path(path: np.ndarray, pose, lookahead: float) -> np.ndarray:
    """The point ``lookahead`` metres from the robot along the path: the first point past
    the one nearest the robot at that distance (interpolated on its segment), else the path's end."""
    xy = np.asarray(pose[:2], float)
    d = np.hypot(*(path - xy).T)
    start = int(np.argmin(d))
    for i in range(start, len(path) - 1):
        a, b = path[i], path[i + 1]
        if np.hypot(*(b - xy)) >= lookahead:
            # the circle of radius L about the robot meets segment ab
            u = b - a
            f = a - xy
            qa, qb, qc = float(u @ u), 2.0 * float(f @ u), float(f @ f) - lookahead ** 2
            disc = qb * qb - 4 * qa * qc
            if qa > 0 and disc >= 0:
                t = (-qb + math.sqrt(disc)) / (2 * qa)
                return a + min(max(t, 0.0), 1.0) * u
            return b
    return path[-1].copy()


#: [m/s] Nav2's default regulated_linear_scaling_min_speed
NAV2_MIN_SPEED = 0.25


@CONTROLLERS.register("rpp")
class RegulatedPurePursuit(CostmapController):
    """Nav2's Regulated Pure Pursuit (see the module); defaults are Nav2's.

    Parameters
    ----------
    desired_linear_vel : float
        [m/s] (0.5).
    lookahead_dist, min_lookahead_dist, max_lookahead_dist, lookahead_time : float
        [m], [m], [m], [s] (0.6, 0.3, 0.9, 1.5).
    use_velocity_scaled_lookahead_dist : bool
        (False).
    rotate_to_heading_angular_vel, rotate_to_heading_min_angle : float
        [rad/s], [rad] (1.8, 0.785).
    max_angular_accel, max_linear_accel : float
        [rad/s²], [m/s²] (3.2, 2.5).
    max_angular_vel : float
        [rad/s] cap on the turn rate while driving (2.0).
    regulated_linear_scaling_min_radius : float
        [m] (0.9).
    regulated_linear_scaling_min_speed : float, optional
        [m/s] (Nav2's 0.25, or ``desired_linear_vel`` when that is lower: a
        robot asked to drive slower than 0.25 m/s needs no second setting).
    use_cost_regulated_linear_velocity_scaling : bool
        (True).
    cost_scaling_dist, cost_scaling_gain : float
        [m], [-] (0.6, 1.0).
    approach_velocity_scaling_dist : float
        [m] (0.6).
    max_allowed_time_to_collision_up_to_carrot : float
        [s] (1.0).
    creep_when_blocked : bool
        navlab's extension, off by default: where Nav2 would stop, creep along the path at the lowest
        speed with the shortest look-ahead, or turn in place towards it when that is free (False).
    plan_poses : bool
        navlab's extension, off by default: after ``pose_plan_after`` s without progress, follow a
        path of poses planned for the footprint from where the robot stands (see the module) (False).
        The robot starts on such a path when its footprint grown by ``pose_plan_clearance`` meets a LETHAL
        cell somewhere along the costmap path (at the path's heading, smoothed over ±0.25 m).
    pose_plan_clearance, pose_plan_after, pose_plan_turning_radius, pose_track_settling : float
        [m], [s], [m], [m] (0.05, 3.0, 0.2, 0.2).
    inflation_radius, cost_scaling_factor : float
        The costmap's inflation (0.55 m, 3.0 1/m: Nav2's defaults).
    """

    speed_setting = "desired_linear_vel"

    def __init__(self, desired_linear_vel: float = 0.5, lookahead_dist: float = 0.6, min_lookahead_dist: float = 0.3,
                 max_lookahead_dist: float = 0.9, lookahead_time: float = 1.5,
                 use_velocity_scaled_lookahead_dist: bool = False, rotate_to_heading_angular_vel: float = 1.8,
                 rotate_to_heading_min_angle: float = 0.785, max_angular_accel: float = 3.2,
                 max_linear_accel: float = 2.5, max_angular_vel: float = 2.0,
                 regulated_linear_scaling_min_radius: float = 0.9, regulated_linear_scaling_min_speed: Optional[float] = None,
                 use_cost_regulated_linear_velocity_scaling: bool = True, cost_scaling_dist: float = 0.6,
                 cost_scaling_gain: float = 1.0, approach_velocity_scaling_dist: float = 0.6,
                 max_allowed_time_to_collision_up_to_carrot: float = 1.0, xy_goal_tolerance: float = 0.25,
                 inflation_radius: float = 0.55, cost_scaling_factor: float = 3.0, layers: str = "static",
                 replan_interval: float = 1.0, controller_frequency: float = 20.0, stall_window: float = 20.0,
                 stall_progress: float = 0.05, creep_when_blocked: bool = False, footprint_padding: float = 0.0,
                 costmap_resolution: float = 0.05, plan_poses: bool = False,
                 pose_plan_clearance: float = 0.05, pose_plan_after: float = 3.0, pose_plan_turning_radius: float = 0.2,
                 pose_track_settling: float = 0.2) -> None:
        super().__init__(xy_goal_tolerance, stall_window, stall_progress, inflation_radius, cost_scaling_factor,
                         layers, replan_interval, footprint_padding, costmap_resolution)
        use_velocity_scaled_lookahead_dist = check_flag("use_velocity_scaled_lookahead_dist",
                                                        use_velocity_scaled_lookahead_dist)
        use_cost_regulated_linear_velocity_scaling = check_flag("use_cost_regulated_linear_velocity_scaling",
                                                                use_cost_regulated_linear_velocity_scaling)
        creep_when_blocked = check_flag("creep_when_blocked", creep_when_blocked)
        plan_poses = check_flag("plan_poses", plan_poses)
        self.desired_linear_vel = check_number("desired_linear_vel", desired_linear_vel)
        self.lookahead_dist = check_number("lookahead_dist", lookahead_dist)
        self.min_lookahead_dist = check_number("min_lookahead_dist", min_lookahead_dist)
        self.max_lookahead_dist = check_number("max_lookahead_dist", max_lookahead_dist)
        if self.max_lookahead_dist < self.min_lookahead_dist:
            raise ParameterError(f"max_lookahead_dist ({max_lookahead_dist}) must be ≥ min_lookahead_dist "
                                 f"({min_lookahead_dist})")
        self.lookahead_time = check_number("lookahead_time", lookahead_time)
        self.scaled_lookahead = use_velocity_scaled_lookahead_dist
        self.rotate_vel = check_number("rotate_to_heading_angular_vel", rotate_to_heading_angular_vel)
        self.rotate_min_angle = check_number("rotate_to_heading_min_angle", rotate_to_heading_min_angle,
                                             high=math.pi)
        self.max_angular_accel = check_number("max_angular_accel", max_angular_accel)
        self.max_linear_accel = check_number("max_linear_accel", max_linear_accel)
        self.max_angular_vel = check_number("max_angular_vel", max_angular_vel)
        self.min_radius = check_number("regulated_linear_scaling_min_radius", regulated_linear_scaling_min_radius)
        if regulated_linear_scaling_min_speed is None:
            regulated_linear_scaling_min_speed = min(NAV2_MIN_SPEED, self.desired_linear_vel)
        self.min_speed = check_number("regulated_linear_scaling_min_speed", regulated_linear_scaling_min_speed,
                                      allow_low=True, high=self.desired_linear_vel)
        self.cost_regulation = use_cost_regulated_linear_velocity_scaling
        self.cost_scaling_dist = check_number("cost_scaling_dist", cost_scaling_dist)
        self.cost_scaling_gain = check_number("cost_scaling_gain", cost_scaling_gain)
        self.approach_dist = check_number("approach_velocity_scaling_dist", approach_velocity_scaling_dist)
        self.collision_time = check_number("max_allowed_time_to_collision_up_to_carrot",
                                           max_allowed_time_to_collision_up_to_carrot)
        self.period = 1.0 / check_number("controller_frequency", controller_frequency, high=1e4)
        self.creep_when_blocked = creep_when_blocked
        self.plan_poses = plan_poses
        self.pose_plan_clearance = check_number("pose_plan_clearance", pose_plan_clearance, allow_low=True,
                                                high=10.0)
        self.pose_plan_after = check_number("pose_plan_after", pose_plan_after, high=1e4)
        self.pose_plan_turning_radius = check_number("pose_plan_turning_radius", pose_plan_turning_radius,
                                                     high=100.0)
        self.pose_track_settling = check_number("pose_track_settling", pose_track_settling, high=100.0)
        self.last_carrot = None
        self._reset_run()

    def _reset_run(self) -> None:
        """Forget the last run: its pose path, its progress and when it was last blocked."""
        self._now, self._blocked_at = 0.0, -math.inf  # this cycle's time; the last the look-ahead met a LETHAL cell
        self.poses = None  #: (N, 3) the footprint-aware path being tracked (None: following ``path``)
        self.wants_pose_plan = False  #: read by the costmap feed, which then calls set_pose_path
        self._progress = (0.0, math.inf)  # (since when, the distance left then)
        self._track_index = 0

    def reset(self, goal, path=None) -> None:
        super().reset(goal, path)
        self._reset_run()
        if path is not None and np.ndim(path) == 2 and np.shape(path)[1] == 3:  # a path of poses
            self.set_pose_path(path)

    def set_path(self, path) -> None:
        super().set_path(path)
        self.poses = None

    def set_pose_path(self, poses) -> None:
        """Track these poses (N, 3) from now on (the costmap feed's answer to ``wants_pose_plan``)."""
        poses = np.ascontiguousarray(np.asarray(poses, float)[:, :3])
        super().set_path(poses[:, :2])
        self.poses = poses
        self.wants_pose_plan = False
        self._track_index = 0
        seg = np.hypot(*np.diff(poses[:, :2], axis=0).T)
        turn = np.diff(np.unwrap(poses[:, 2]))
        kappa = np.where(seg > 1e-9, turn / np.maximum(seg, 1e-9), 0.0)
        self._kappa = np.concatenate((kappa, [kappa[-1] if len(kappa) else 0.0]))  #: curvature into each pose
        self._along = np.concatenate(([0.0], np.cumsum(seg)))

    def pose_plan_failed(self, t: float) -> None:
        """No pose path from here: keep following ``path`` and ask again after ``pose_plan_after`` s."""
        self.wants_pose_plan = False
        self._progress = (t, self._progress[1])

    def lookahead(self) -> float:
        if not self.scaled_lookahead:
            return self.lookahead_dist
        return min(max(abs(self.velocity[0]) * self.lookahead_time, self.min_lookahead_dist),
                   self.max_lookahead_dist)

    def obstacle_distance(self, pose) -> float:
        """The distance to the nearest obstacle implied by the cost at the robot (the
        inflation formula inverted; inf at zero cost)."""
        cost = float(self.costmap.cost_at(pose[:2])[0])
        if cost <= 0:
            return math.inf
        if cost >= INSCRIBED_INFLATED_OBSTACLE:
            return 0.0
        factor = self.costmap_settings["cost_scaling_factor"]
        inscribed = self.footprint.inscribed_radius
        return inscribed - math.log(cost / MAX_NON_OBSTACLE) / factor if factor > 0 else inscribed

    def plan(self, t: float, pose: np.ndarray):
        self._now = t
        if self.plan_poses:
            left = self.remaining(pose)
            since, then = self._progress
            if left < then - self.stall.progress:
                self._progress = (t, left)
            elif t - since >= self.pose_plan_after and not self.wants_pose_plan:
                self.wants_pose_plan = True
                self._progress = (t, left)
        return self._track_poses(pose) if self.poses is not None else self._pursue(pose)

    def why_stalled(self) -> str:
        """A stall within the stall window of the collision look-ahead's last LETHAL cell is put down to
        it, with the setting that answers it where one does (newcomer runs: the jackal in clutter stalled
        saying only "no progress"); any other, as the base class says."""
        if self._now - self._blocked_at > self.stall.window:
            return super().why_stalled()
        if self.poses is not None:
            return "the footprint would meet a LETHAL cell on its path of poses"
        why = "the footprint would meet a LETHAL cell on the arc ahead" + (
            ", and creeping did not pass it" if self.creep_when_blocked else ", where Nav2's RPP stops")
        if not self.plan_poses:
            return f"{why}; the path is planned for the robot's centre, and plan_poses=true plans one for its footprint"
        return f"{why}, and no forward path of poses for its footprint leaves this pose"

    def _pursue(self, pose):
        """Nav2's regulated pure pursuit along ``path`` (the module's steps 1-5)."""
        lookahead = self.lookahead()
        carrot = carrot_on_path(self.path, pose, lookahead)
        self.last_carrot = carrot
        c, s = math.cos(pose[2]), math.sin(pose[2])
        dx, dy = carrot - pose[:2]
        x, y = c * dx + s * dy, -s * dx + c * dy
        dist2 = x * x + y * y
        curvature = 2.0 * y / dist2 if dist2 > 1e-12 else 0.0
        w_prev = self.velocity[2]
        angle = math.atan2(y, x)
        if abs(angle) > self.rotate_min_angle:
            w = math.copysign(self.rotate_vel, angle)
            room = self.max_angular_accel * self.period
            w = min(max(w, w_prev - room), w_prev + room)
            return 0.0, 0.0, w
        v = self.desired_linear_vel
        radius = 1.0 / abs(curvature) if abs(curvature) > 1e-9 else math.inf
        if radius < self.min_radius:
            v *= radius / self.min_radius
        if self.cost_regulation:
            d = self.obstacle_distance(pose)
            if d < self.cost_scaling_dist:
                v *= self.cost_scaling_gain * d / self.cost_scaling_dist
        v = max(v, self.min_speed)
        to_goal = float(np.hypot(*(self.goal - pose[:2])))
        if to_goal < self.approach_dist:
            v = min(v, max(self.desired_linear_vel * to_goal / self.approach_dist, 0.05))
        room = self.max_linear_accel * self.period
        v = min(max(v, self.velocity[0] - room), self.velocity[0] + room)
        w = min(max(v * curvature, -self.max_angular_vel), self.max_angular_vel)
        if self.collision_ahead(pose, v, w, math.sqrt(dist2)):
            return self._creep(pose) if self.creep_when_blocked else (0.0, 0.0, 0.0)
        return v, 0.0, w

    def _creep(self, pose):
        """navlab's extension (``creep_when_blocked``), not Nav2's: where the arc ahead is blocked,
        track the path tightly at the lowest speed (the shortest look-ahead), or turn in place
        towards it when that turn is free; stop only when neither is."""
        carrot = carrot_on_path(self.path, pose, self.min_lookahead_dist)
        c, s = math.cos(pose[2]), math.sin(pose[2])
        dx, dy = carrot - pose[:2]
        x, y = c * dx + s * dy, -s * dx + c * dy
        dist2 = max(x * x + y * y, 1e-12)
        v = max(self.min_speed, 0.05)
        w = min(max(v * 2.0 * y / dist2, -self.max_angular_vel), self.max_angular_vel)
        if abs(math.atan2(y, x)) < self.rotate_min_angle and not self.collision_ahead(pose, v, w, math.sqrt(dist2)):
            return v, 0.0, w
        return self._turn_in_place(pose, math.atan2(y, x))

    def _turn_in_place(self, pose, towards: float):
        """Turn in place (at most 1 rad/s) the way of the angle ``towards`` when the next five
        cycles of that turn keep the footprint off LETHAL cells; else stop."""
        turn = math.copysign(min(self.rotate_vel, 1.0), towards)
        headings = pose[2] + turn * self.period * np.arange(1, 6)
        turned = np.column_stack((np.full(5, pose[0]), np.full(5, pose[1]), headings))
        if (self.costmap.footprint_cost(turned, self.footprint) < LETHAL_OBSTACLE).all():
            return 0.0, 0.0, turn
        return 0.0, 0.0, 0.0

    def _track_poses(self, pose):
        """Samson's path-following law on ``poses`` (see the module); stop where the arc ahead is blocked."""
        poses, along = self.poses, self._along
        i0 = self._track_index
        i1 = int(np.searchsorted(along, along[i0] + 1.0, side="right"))  # a window: U-turns must not pull ahead
        d = np.hypot(*(poses[i0:i1 + 1, :2] - pose[:2]).T)
        i = i0 + int(np.argmin(d))
        self._track_index = i
        ref = poses[i]
        c, s = math.cos(ref[2]), math.sin(ref[2])
        e = -s * (pose[0] - ref[0]) + c * (pose[1] - ref[1])  # left of the path positive
        e_th = (pose[2] - ref[2] + math.pi) % (2 * math.pi) - math.pi
        # the speed: RPP's curvature regulation on every pose within braking reach, so the robot
        # arrives at a tight curve already slow enough for it
        ahead = slice(i, int(np.searchsorted(along, along[i] + 1.5, side="right")))
        radius = 1.0 / np.maximum(np.abs(self._kappa[ahead]), 1e-9)
        allowed = self.desired_linear_vel * np.minimum(radius / self.min_radius, 1.0)
        allowed = np.maximum(allowed, min(self.min_speed, self.desired_linear_vel))
        v = float(np.min(np.sqrt(allowed ** 2 + 2.0 * self.max_linear_accel * (along[ahead] - along[i]))))
        if self.cost_regulation:
            dist = self.obstacle_distance(pose)
            if dist < self.cost_scaling_dist:
                v = max(v * self.cost_scaling_gain * dist / self.cost_scaling_dist, self.min_speed)
        to_goal = float(np.hypot(*(self.goal - pose[:2])))
        if to_goal < self.approach_dist:
            v = min(v, max(self.desired_linear_vel * to_goal / self.approach_dist, 0.05))
        if abs(e_th) > self.rotate_min_angle:  # far off the path's heading (a new path): turn to it first
            return self._turn_in_place(pose, -e_th)
        room = self.max_linear_accel * self.period
        v = min(max(v, self.velocity[0] - room), self.velocity[0] + room)
        k_th, k_e = 2.0 / self.pose_track_settling, 1.0 / self.pose_track_settling ** 2
        kappa = float(self._kappa[min(i + 1, len(poses) - 1)])
        sinc = math.sin(e_th) / e_th if abs(e_th) > 1e-9 else 1.0
        w = v * kappa * math.cos(e_th) / max(1.0 - kappa * e, 0.1) - k_th * v * e_th - k_e * v * sinc * e
        if abs(w) > self.max_angular_vel:  # keep the curve, not the speed: slow down until the turn rate fits
            v *= self.max_angular_vel / abs(w)
            w = math.copysign(self.max_angular_vel, w)
        if self.collision_ahead(pose, v, w, max(v * self.period * 2, self.costmap.resolution)):
            return 0.0, 0.0, 0.0
        return v, 0.0, w

    def collision_ahead(self, pose, v: float, w: float, carrot_dist: float) -> bool:
        """Whether the footprint's outline meets a LETHAL (or unknown, off-map) cell on the projected arc
        (Nav2's ``inCollision``: ``footprint_cost >= LETHAL_OBSTACLE``)."""
        if v <= 0:
            return False
        reach = min(v * self.collision_time, carrot_dist)
        steps = max(int(math.ceil(reach / self.costmap.resolution)), 1)
        arc = arc_rollouts(*pose, np.array([v]), np.zeros(1), np.array([w]), reach / v / steps, steps)[0]
        blocked = bool((self.costmap.footprint_cost(arc, self.footprint) >= LETHAL_OBSTACLE).any())
        if blocked:
            self._blocked_at = self._now
        return blocked
