"""Model Predictive Path Integral control, as Nav2's ``nav2_mppi_controller``.

G. Williams, A. Aldrich, E. Theodorou, "Model Predictive Path Integral
Control using Covariance Variable Importance Sampling", arXiv:1509.01149;
G. Williams et al., "Information Theoretic MPC for Model-Based
Reinforcement Learning", ICRA 2017; Nav2's MPPI controller (S. Macenski,
A. Budyakov) whose defaults and critics this follows. Each cycle:

1. the nominal control sequence U (``time_steps`` × (vx, [vy,] ωz)) is
   shifted one step (the first is spent);
2. ``batch_size`` sequences V = U + ε are drawn, ε ~ N(0, diag(vx_std²,
   [vy_std²,] wz_std²)) from the injected generator, clipped to the velocity
   limits and to the acceleration limits step to step;
3. each is rolled out through the robot's model (diff drive or omni) at
   ``model_dt`` and scored by the critics below, plus the control cost
   ``γ / σ² · Σ_t U_t · ε_t``;
4. U ← Σ_n w_n V_n with w = softmax(−(cost − min cost) / ``temperature``);
5. the command is U's first step.

Critics (Nav2's, with its default weights): **cost** (3.81: the costmap's
cost along the rollout, every ``cost_point_step`` poses, the footprint's
outline once the centre is within the circumscribed radius of an obstacle;
a footprint on an INSCRIBED-or-worse cell adds ``collision_cost``),
**path align** (14.0: mean distance of every 4th pose to the path),
**path follow** (5.0: distance of the last pose to the path point
``offset_from_furthest`` beyond the furthest one the rollouts reach),
**path angle** (2.0: heading error towards that point when the robot faces
more than ``max_angle_to_furthest`` away from it), **goal** (5.0: mean
distance to the goal once within ``goal_threshold``), **prefer forward**
(5.0: reverse motion), and **constraints** (velocities are clipped to the
limits before the rollout, so that critic is always zero here).
"""

from __future__ import annotations

import math
from typing import Any, Optional

import numpy as np

from ..errors import ParameterError
from ..jit import njit
from ..limits import check_count
from ..registry import suggest
from ..world.costmap import INSCRIBED_INFLATED_OBSTACLE, MAX_NON_OBSTACLE, footprint_cost_one
from .base import CONTROLLERS
from .local import CostmapController, check_number

#: the smallest noise standard deviation other than 0 (no noise) [m/s, rad/s]: the control cost divides by its
#: square, and 1e-300 overflowed it to NaN poses
MIN_NOISE = 1e-6
#: the largest noise standard deviation [m/s, rad/s]
MAX_NOISE = 1e3
#: the largest control-cost weight γ (Nav2's default 0.015)
MAX_GAMMA = 1e3


def _noise(name: str, value) -> float:
    """A noise standard deviation: 0 (none) or from :data:`MIN_NOISE` on."""
    value = check_number(name, value, allow_low=True, high=MAX_NOISE)
    if 0.0 < value < MIN_NOISE:
        raise ParameterError(f"{name} must be 0 (no noise) or at least {MIN_NOISE:g}, got {value!r}")
    return value


@njit(cache=True)
def rollout_and_score(pose, v0, controls, dt, acc, costs, ox, oy, res, body, possibly_inscribed, path, goal,
                      weights, params, out_poses, out_cost):
    """Roll every control sequence out and score it (see the module).

    controls : (N, T, 3) vx, vy, ωz, clipped to the velocity limits; the acceleration
        limits ``acc`` (ax_max, ax_min, ay_max, az_max) are applied here in place.
    weights : cost, path_align, path_follow, path_angle, goal, prefer_forward
    params : collision_cost, cost_point_step, align_point_step, follow_offset, angle_offset,
        max_angle, goal_threshold, consider_path (1/0), dist_to_goal
    """
    n, t_steps = controls.shape[0], controls.shape[1]
    m = path.shape[0]
    collision_cost, cost_step, align_step = params[0], int(params[1]), int(params[2])
    follow_offset, angle_offset, max_angle = int(params[3]), int(params[4]), params[5]
    goal_threshold, consider_path, dist_to_goal = params[6], params[7] > 0.5, params[8]
    for i in range(n):
        x, y, th = pose[0], pose[1], pose[2]
        pvx, pvy, pwz = v0[0], v0[1], v0[2]
        for k in range(t_steps):
            vx = min(max(controls[i, k, 0], pvx + acc[1] * dt), pvx + acc[0] * dt)
            vy = min(max(controls[i, k, 1], pvy - acc[2] * dt), pvy + acc[2] * dt)
            wz = min(max(controls[i, k, 2], pwz - acc[3] * dt), pwz + acc[3] * dt)
            controls[i, k, 0], controls[i, k, 1], controls[i, k, 2] = vx, vy, wz
            pvx, pvy, pwz = vx, vy, wz
            th = th + wz * dt
            c, s = math.cos(th), math.sin(th)
            x = x + (vx * c - vy * s) * dt
            y = y + (vx * s + vy * c) * dt
            out_poses[i, k, 0], out_poses[i, k, 1], out_poses[i, k, 2] = x, y, th
        total = 0.0
        # cost critic
        repulsive = 0.0
        collided = False
        h, w = costs.shape
        for k in range(cost_step - 1, t_steps, cost_step):
            px, py, pth = out_poses[i, k, 0], out_poses[i, k, 1], out_poses[i, k, 2]
            cx = int(math.floor((px - ox) / res))
            cy = int(math.floor((py - oy) / res))
            if cx < 0 or cy < 0 or cx >= w or cy >= h:
                collided = True
                break
            cost = costs[cy, cx]
            if cost >= possibly_inscribed and body.shape[0] > 0:
                cost = footprint_cost_one(costs, ox, oy, res, body, px, py, pth)
            if cost >= INSCRIBED_INFLATED_OBSTACLE:
                collided = True
                break
            repulsive += cost
        if collided:
            total += collision_cost
        else:
            total += weights[0] * repulsive / MAX_NON_OBSTACLE / t_steps * cost_step
        # prefer forward
        if dist_to_goal > 0.5:
            back = 0.0
            for k in range(t_steps):
                if controls[i, k, 0] < 0:
                    back -= controls[i, k, 0]
            total += weights[5] * back * dt
        # goal
        if dist_to_goal < goal_threshold:
            acc_d = 0.0
            for k in range(t_steps):
                acc_d += math.hypot(out_poses[i, k, 0] - goal[0], out_poses[i, k, 1] - goal[1])
            total += weights[4] * acc_d / t_steps
        if consider_path and m > 1:
            # furthest path point this rollout reaches: nearest to its last pose
            lx, ly = out_poses[i, t_steps - 1, 0], out_poses[i, t_steps - 1, 1]
            best, far = 1e300, 0
            for j in range(m):
                d = (path[j, 0] - lx) ** 2 + (path[j, 1] - ly) ** 2
                if d < best:
                    best, far = d, j
            # path align: mean distance of every align_step-th pose to the path (up to the furthest point)
            acc_a = 0.0
            count = 0
            for k in range(align_step - 1, t_steps, align_step):
                px, py = out_poses[i, k, 0], out_poses[i, k, 1]
                dmin = 1e300
                for j in range(0, min(far + 1, m)):
                    d = (path[j, 0] - px) ** 2 + (path[j, 1] - py) ** 2
                    if d < dmin:
                        dmin = d
                acc_a += math.sqrt(dmin)
                count += 1
            if count > 0:
                total += weights[1] * acc_a / count
        out_cost[i] = total


@njit(cache=True)
def furthest_index(out_poses, path):
    """The furthest path index any rollout's last pose is nearest to."""
    far = 0
    t_last = out_poses.shape[1] - 1
    for i in range(out_poses.shape[0]):
        lx, ly = out_poses[i, t_last, 0], out_poses[i, t_last, 1]
        best, idx = 1e300, 0
        for j in range(path.shape[0]):
            d = (path[j, 0] - lx) ** 2 + (path[j, 1] - ly) ** 2
            if d < best:
                best, idx = d, j
        if idx > far:
            far = idx
    return far


@njit(cache=True)
def follow_and_angle(out_poses, target_follow, target_angle, w_follow, w_angle, angle_on, out_cost):
    """Path-follow (distance of the last pose to a point) and path-angle (heading of the last pose
    towards a point) critics, added to ``out_cost``."""
    t_last = out_poses.shape[1] - 1
    for i in range(out_poses.shape[0]):
        lx, ly, lth = out_poses[i, t_last, 0], out_poses[i, t_last, 1], out_poses[i, t_last, 2]
        out_cost[i] += w_follow * math.hypot(target_follow[0] - lx, target_follow[1] - ly)
        if angle_on:
            a = math.atan2(target_angle[1] - ly, target_angle[0] - lx) - lth
            a = abs(math.atan2(math.sin(a), math.cos(a)))
            out_cost[i] += w_angle * a


def _possibly_inscribed_cost(circumscribed: float, inscribed: float, factor: float, inflation_radius: float) -> int:
    """The inflation cost at the footprint's circumscribed radius: below it, no footprint cell can be
    lethal, so the centre's cost is enough (Nav2's ``possibly_inscribed_cost``)."""
    if circumscribed <= inscribed:
        return INSCRIBED_INFLATED_OBSTACLE
    if circumscribed > inflation_radius:
        return 0
    return int(MAX_NON_OBSTACLE * math.exp(-factor * (circumscribed - inscribed)))


@CONTROLLERS.register("mppi")
class MPPI(CostmapController):
    """Nav2's MPPI controller (see the module); defaults are Nav2's.

    Parameters
    ----------
    motion_model : str
        ``diff`` (vx, ωz) or ``omni`` (vx, vy, ωz).
    batch_size, time_steps, iteration_count : int
        Sampled sequences, steps per sequence, updates per cycle (2000, 56, 1).
    model_dt : float
        [s] rollout step (0.05).
    vx_std, vy_std, wz_std : float
        Noise standard deviations (0.2, 0.2, 0.4): 0 (no noise) or from :data:`MIN_NOISE` to
        :data:`MAX_NOISE`.
    vx_max, vx_min, vy_max, wz_max : float
        Velocity limits [m/s, rad/s] (0.5, −0.35, 0.5, 1.9).
    ax_max, ax_min, ay_max, az_max : float
        Acceleration limits [m/s², rad/s²] (3.0, −3.0, 3.0, 3.5).
    temperature, gamma : float
        Softmax temperature and control-cost weight (0.3, 0.015; gamma at most :data:`MAX_GAMMA`).
    cost_weight, path_align_weight, path_follow_weight, path_angle_weight, goal_weight, prefer_forward_weight
        Critic weights (3.81, 14.0, 5.0, 2.0, 5.0, 5.0).
    collision_cost : float
        Added to a rollout whose footprint meets an INSCRIBED cell (1e6).
    goal_threshold, path_threshold : float
        [m] the goal critic acts within, the path critics beyond (1.4, 0.5).
    prune_distance : float
        [m] the path ahead the critics see (1.7).
    """

    speed_setting = "vx_max"

    def __init__(self, motion_model: str = "diff", batch_size: int = 2000, time_steps: int = 56,
                 iteration_count: int = 1, model_dt: float = 0.05, vx_std: float = 0.2, vy_std: float = 0.2,
                 wz_std: float = 0.4, vx_max: float = 0.5, vx_min: float = -0.35, vy_max: float = 0.5,
                 wz_max: float = 1.9, ax_max: float = 3.0, ax_min: float = -3.0, ay_max: float = 3.0,
                 az_max: float = 3.5, temperature: float = 0.3, gamma: float = 0.015, cost_weight: float = 3.81,
                 path_align_weight: float = 14.0, path_follow_weight: float = 5.0, path_angle_weight: float = 2.0,
                 goal_weight: float = 5.0, prefer_forward_weight: float = 5.0, collision_cost: float = 1e6,
                 goal_threshold: float = 1.4, path_threshold: float = 0.5, prune_distance: float = 1.7,
                 xy_goal_tolerance: float = 0.25, inflation_radius: float = 0.55, cost_scaling_factor: float = 3.0,
                 layers: str = "static", replan_interval: float = 1.0, stall_window: float = 20.0,
                 stall_progress: float = 0.05, footprint_padding: float = 0.0, costmap_resolution: float = 0.05) -> None:
        super().__init__(xy_goal_tolerance, stall_window, stall_progress, inflation_radius, cost_scaling_factor,
                         layers, replan_interval, footprint_padding, costmap_resolution)
        if motion_model not in ("diff", "omni"):
            raise ParameterError(f"motion_model must be diff or omni, got {motion_model!r}."
                                 f"{suggest(motion_model, ['diff', 'omni'])}".rstrip("."))
        self.motion_model = motion_model
        self.holonomic = motion_model == "omni"
        self.batch_size = check_count("batch_size", batch_size, 1, 100_000)
        self.time_steps = check_count("time_steps", time_steps, 2, 10_000)
        self.iteration_count = check_count("iteration_count", iteration_count, 1, 100)
        self.model_dt = check_number("model_dt", model_dt, high=10.0)
        vy_std = _noise("vy_std", vy_std)  # checked for a diff drive too, which does not sample it
        self.std = np.array([_noise("vx_std", vx_std), vy_std if self.holonomic else 0.0, _noise("wz_std", wz_std)])
        self.vx_max = check_number("vx_max", vx_max)
        self.vx_min = check_number("vx_min", vx_min, low=-1e6, allow_low=True, high=self.vx_max)
        self.vy_max = check_number("vy_max", vy_max)
        self.wz_max = check_number("wz_max", wz_max)
        self.acc = np.array([check_number("ax_max", ax_max), check_number("ax_min", ax_min, low=-1e6, high=-1e-9),
                             check_number("ay_max", ay_max), check_number("az_max", az_max)])
        self.temperature = check_number("temperature", temperature)
        # γ/σ² weighs the control cost: 1e308 overflowed it to NaN poses (attack run, session 18)
        self.gamma = check_number("gamma", gamma, allow_low=True, high=MAX_GAMMA)
        self.weights = np.array([check_number(name, value, allow_low=True) for name, value in (
            ("cost_weight", cost_weight), ("path_align_weight", path_align_weight),
            ("path_follow_weight", path_follow_weight), ("path_angle_weight", path_angle_weight),
            ("goal_weight", goal_weight), ("prefer_forward_weight", prefer_forward_weight))])
        self.collision_cost = check_number("collision_cost", collision_cost, allow_low=True)
        self.goal_threshold = check_number("goal_threshold", goal_threshold, allow_low=True)
        self.path_threshold = check_number("path_threshold", path_threshold, allow_low=True)
        self.prune_distance = check_number("prune_distance", prune_distance)
        self.rng: np.random.Generator = np.random.default_rng(0)
        self.sequence = np.zeros((self.time_steps, 3))  #: the nominal control sequence U
        self.last_rollouts: Optional[np.ndarray] = None

    def seed(self, rng: Any) -> None:
        """Draw the samples from ``rng`` (the simulator passes its generator's child)."""
        self.rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)

    def reset(self, goal, path=None) -> None:
        super().reset(goal, path)
        self.sequence = np.zeros((self.time_steps, 3))

    def optimize(self, pose, noise: Optional[np.ndarray] = None) -> np.ndarray:
        """One MPPI update of the nominal sequence from ``pose``; ``noise`` (N, T, 3) replaces
        the random draw (for tests). Returns the new sequence."""
        cm = self.costmap
        n, t_steps = self.batch_size, self.time_steps
        if noise is None:
            noise = self.rng.standard_normal((n, t_steps, 3)) * self.std
        controls = self.sequence[None, :, :] + noise
        np.clip(controls[..., 0], self.vx_min, self.vx_max, out=controls[..., 0])
        np.clip(controls[..., 1], -self.vy_max, self.vy_max, out=controls[..., 1])
        np.clip(controls[..., 2], -self.wz_max, self.wz_max, out=controls[..., 2])
        if not self.holonomic:
            controls[..., 1] = 0.0
        poses = np.empty((n, t_steps, 3))
        cost = np.empty(n)
        path = self.local_path(pose, self.prune_distance)
        distance = float(np.hypot(*(self.goal - pose[:2])))
        inscribed = self.footprint.inscribed_radius
        possibly = _possibly_inscribed_cost(self.footprint.circumscribed_radius, inscribed,
                                            self.costmap_settings["cost_scaling_factor"],
                                            self.costmap_settings["inflation_radius"])
        consider_path = distance > self.path_threshold and len(path) > 1
        params = np.array([self.collision_cost, 2, 4, 5, 4, 1.0, self.goal_threshold, float(consider_path),
                           distance])
        rollout_and_score(np.asarray(pose, float), self.velocity, controls, self.model_dt, self.acc, cm.costs,
                          cm.origin[0], cm.origin[1], cm.resolution, self.body, possibly, path, self.goal,
                          self.weights, params, poses, cost)
        if consider_path and distance > self.goal_threshold:
            far = furthest_index(poses, path)
            follow = path[min(far + 5, len(path) - 1)]
            angle_target = path[min(far + 4, len(path) - 1)]
            heading = math.atan2(angle_target[1] - pose[1], angle_target[0] - pose[0]) - pose[2]
            angle_on = abs(math.remainder(heading, 2 * math.pi)) > 1.0
            follow_and_angle(poses, follow, angle_target, self.weights[2], self.weights[3], angle_on, cost)
        # control cost γ/σ² Σ U·ε over the sampled axes, with the noise as clipped
        eps = controls - self.sequence[None]
        for axis in range(3):
            if self.std[axis] > 0:
                cost += self.gamma / self.std[axis] ** 2 * np.einsum("t,nt->n", self.sequence[:, axis], eps[..., axis])
        exponent = -(cost - cost.min()) / self.temperature
        weights = np.exp(exponent)
        weights /= weights.sum()
        self.sequence = np.einsum("n,ntk->tk", weights, controls)
        self.last_rollouts = poses
        return self.sequence

    def plan(self, t: float, pose: np.ndarray):
        # the first step was spent last cycle: shift, repeating the last
        self.sequence = np.vstack((self.sequence[1:], self.sequence[-1:]))
        for _ in range(self.iteration_count):
            self.optimize(pose)
        vx, vy, wz = self.sequence[0]
        return float(vx), float(vy) if self.holonomic else 0.0, float(wz)
