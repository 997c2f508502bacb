"""The dynamic-window approach as ROS ``base_local_planner`` runs it with ``dwa: true``.

Each cycle (Fox, Burgard, Thrun, "The Dynamic Window Approach to Collision
Avoidance", IEEE RA Magazine 1997; ROS ``base_local_planner`` /
``TrajectoryPlannerROS``, and Nav2 DWB with the same critics):

1. **Window**: the velocities reachable within one control period
   (``1 / controller_frequency``) under ``acc_lim_x`` and ``acc_lim_theta``,
   clipped to ``[min_vel_x, max_vel_x]`` and ``[min_vel_theta,
   max_vel_theta]``; ``vx_samples × vtheta_samples`` evenly spaced samples
   including both ends.
2. **Rollout**: each sample held constant for ``sim_time`` and traced along
   its exact arc at steps of ``sim_granularity`` metres (and
   ``angular_sim_granularity`` radians).
3. **Score** (``meter_scoring``): ``pdist_scale · path_dist + gdist_scale ·
   goal_dist + occdist_scale · occ_cost``, where ``path_dist`` and
   ``goal_dist`` are the 4-connected grid distances (in metres) from the
   rollout's end cell to the nearest cell of the global path and to the local
   goal (the last path point inside the costmap), spread through cells below
   ``INSCRIBED`` (base_local_planner's ``MapGrid``), and ``occ_cost`` the
   largest footprint cost along the rollout. A rollout whose footprint
   touches a lethal, inscribed or unknown cell, or whose end no distance
   reaches, is rejected. The cheapest rollout wins (ties: the first).
4. **Recovery**: when every forward sample is rejected, rotations in place
   (``min_in_place_vel_theta`` up to ``max_vel_theta``, either way) are
   scored the same way; when those are rejected too the robot backs up at
   ``escape_vel`` until it has moved ``escape_reset_dist`` or turned
   ``escape_reset_theta``. Oscillation: after turning in place one way, the
   other way is barred until the robot has moved ``oscillation_reset_dist``.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np
from numba import njit

from ..world.costmap import INSCRIBED_INFLATED_OBSTACLE, footprint_cost_one
from .base import CONTROLLERS
from .local import CostmapController, arc_rollouts, check_count, check_number

#: a distance no cell can have: the cell is unreachable from the path or goal
UNREACHABLE = 1e18


@njit(cache=True)
def grid_distances(passable, sources_x, sources_y):
    """4-connected breadth-first distances (in cells) from the source cells through
    passable cells (base_local_planner's MapGrid); UNREACHABLE elsewhere."""
    h, w = passable.shape
    dist = np.full((h, w), UNREACHABLE)
    qx = np.empty(h * w + len(sources_x), np.int64)
    qy = np.empty(h * w + len(sources_x), np.int64)
    head, tail = 0, 0
    for i in range(len(sources_x)):
        x, y = sources_x[i], sources_y[i]
        if 0 <= x < w and 0 <= y < h and passable[y, x] and dist[y, x] != 0.0:
            dist[y, x] = 0.0
            qx[tail], qy[tail] = x, y
            tail += 1
    while head < tail:
        x, y = qx[head], qy[head]
        head += 1
        d = dist[y, x] + 1.0
        for k in range(4):
            nx = x + (1 if k == 0 else -1 if k == 1 else 0)
            ny = y + (1 if k == 2 else -1 if k == 3 else 0)
            if 0 <= nx < w and 0 <= ny < h and passable[ny, nx] and dist[ny, nx] > d:
                dist[ny, nx] = d
                qx[tail], qy[tail] = nx, ny
                tail += 1
    return dist


@njit(cache=True)
def score_rollouts(costs, ox, oy, res, body, rollouts, lengths, path_dist, goal_dist, pdist_scale, gdist_scale,
                   occdist_scale, out):
    """Score each rollout (rows of ``rollouts``, ``lengths[i]`` poses long) as the
    module describes; ``out[i] = -1`` for a rejected one."""
    h, w = costs.shape
    for i in range(rollouts.shape[0]):
        occ = 0
        ok = True
        for k in range(lengths[i]):
            c = footprint_cost_one(costs, ox, oy, res, body, rollouts[i, k, 0], rollouts[i, k, 1], rollouts[i, k, 2])
            if c >= INSCRIBED_INFLATED_OBSTACLE:
                ok = False
                break
            if c > occ:
                occ = c
        if not ok:
            out[i] = -1.0
            continue
        end = lengths[i] - 1
        cx = int(math.floor((rollouts[i, end, 0] - ox) / res))
        cy = int(math.floor((rollouts[i, end, 1] - oy) / res))
        if cx < 0 or cy < 0 or cx >= w or cy >= h or path_dist[cy, cx] >= UNREACHABLE \
                or goal_dist[cy, cx] >= UNREACHABLE:
            out[i] = -1.0
            continue
        out[i] = (pdist_scale * path_dist[cy, cx] * res + gdist_scale * goal_dist[cy, cx] * res
                  + occdist_scale * occ)


@CONTROLLERS.register("dwa")
class DWA(CostmapController):
    """Dynamic-window local planner (ROS base_local_planner, ``dwa: true``); see the module.

    Defaults are base_local_planner's; ``dwa_barn`` has the BARN challenge's.

    Parameters
    ----------
    max_vel_x, min_vel_x : float
        [m/s] forward speed range (0.5, 0.1).
    max_vel_theta, min_in_place_vel_theta : float
        [rad/s] turn-rate limit, and the slowest turn in place (1.0, 0.4).
    acc_lim_x, acc_lim_theta : float
        [m/s², rad/s²] acceleration limits (2.5, 3.2).
    sim_time, sim_granularity, angular_sim_granularity : float
        [s], [m], [rad] rollout horizon and step (1.0, 0.025, 0.025).
    vx_samples, vtheta_samples : int
        Samples per axis (3, 20).
    controller_frequency : float
        [Hz] sets the window's period (20).
    pdist_scale, gdist_scale, occdist_scale : float
        Score weights (0.6, 0.8, 0.01).
    escape_vel, escape_reset_dist, escape_reset_theta : float
        [m/s], [m], [rad] backing up when stuck (−0.1, 0.1, π/2).
    oscillation_reset_dist : float
        [m] (0.05).
    xy_goal_tolerance : float
        [m] (0.1).
    inflation_radius, cost_scaling_factor : float
        The costmap's inflation (0.55 m, 10 1/m: ROS costmap_2d's defaults).
    layers, replan_interval, footprint_padding :
        See :class:`~navlab.control.local.CostmapController`.
    """

    def __init__(self, max_vel_x: float = 0.5, min_vel_x: float = 0.1, max_vel_theta: float = 1.0,
                 min_in_place_vel_theta: float = 0.4, acc_lim_x: float = 2.5, acc_lim_theta: float = 3.2,
                 sim_time: float = 1.0, sim_granularity: float = 0.025, angular_sim_granularity: float = 0.025,
                 vx_samples: int = 3, vtheta_samples: int = 20, controller_frequency: float = 20.0,
                 pdist_scale: float = 0.6, gdist_scale: float = 0.8, occdist_scale: float = 0.01,
                 escape_vel: float = -0.1, escape_reset_dist: float = 0.1, escape_reset_theta: float = math.pi / 2,
                 oscillation_reset_dist: float = 0.05, xy_goal_tolerance: float = 0.1,
                 inflation_radius: float = 0.55, cost_scaling_factor: float = 10.0, stall_window: float = 20.0,
                 stall_progress: float = 0.05, layers: str = "static", replan_interval: float = 1.0,
                 footprint_padding: float = 0.0, costmap_resolution: float = 0.05) -> None:
        super().__init__(xy_goal_tolerance, stall_window, stall_progress, inflation_radius, cost_scaling_factor,
                         layers, replan_interval, footprint_padding, costmap_resolution)
        self.max_vel_x = check_number("max_vel_x", max_vel_x)
        self.min_vel_x = check_number("min_vel_x", min_vel_x, allow_low=True, high=self.max_vel_x)
        self.max_vel_theta = check_number("max_vel_theta", max_vel_theta)
        self.min_in_place_vel_theta = check_number("min_in_place_vel_theta", min_in_place_vel_theta,
                                                   high=self.max_vel_theta)
        self.acc_lim_x = check_number("acc_lim_x", acc_lim_x)
        self.acc_lim_theta = check_number("acc_lim_theta", acc_lim_theta)
        self.sim_time = check_number("sim_time", sim_time, high=60.0)
        self.sim_granularity = check_number("sim_granularity", sim_granularity)
        self.angular_sim_granularity = check_number("angular_sim_granularity", angular_sim_granularity)
        self.vx_samples = check_count("vx_samples", vx_samples, 1, 1000)
        self.vtheta_samples = check_count("vtheta_samples", vtheta_samples, 1, 1000)
        self.period = 1.0 / check_number("controller_frequency", controller_frequency, high=1e4)
        self.pdist_scale = check_number("pdist_scale", pdist_scale, allow_low=True)
        self.gdist_scale = check_number("gdist_scale", gdist_scale, allow_low=True)
        self.occdist_scale = check_number("occdist_scale", occdist_scale, allow_low=True)
        self.escape_vel = check_number("escape_vel", escape_vel, low=-10.0, high=-1e-9)
        self.escape_reset_dist = check_number("escape_reset_dist", escape_reset_dist)
        self.escape_reset_theta = check_number("escape_reset_theta", escape_reset_theta)
        self.oscillation_reset_dist = check_number("oscillation_reset_dist", oscillation_reset_dist)
        self._escape_from: Optional[np.ndarray] = None
        self._turn_block = 0  #: +1 bars turning left in place, −1 right, 0 neither
        self._turn_from: Optional[np.ndarray] = None
        self.last_scores: Optional[np.ndarray] = None  #: the last cycle's forward samples' scores (−1 rejected)
        self.last_samples: Optional[np.ndarray] = None  #: (vx, ω) of those samples

    def reset(self, goal, path=None) -> None:
        super().reset(goal, path)
        self._escape_from, self._turn_block, self._turn_from = None, 0, None

    # -- the window and the samples -------------------------------------------
    def samples(self) -> np.ndarray:
        """(vx_samples · vtheta_samples, 2) forward samples (vx, ω) in this cycle's window."""
        v0, w0 = self.velocity[0], self.velocity[2]
        vmin = max(self.min_vel_x, v0 - self.acc_lim_x * self.period)
        vmax = max(vmin, min(self.max_vel_x, v0 + self.acc_lim_x * self.period))
        wmin = max(-self.max_vel_theta, w0 - self.acc_lim_theta * self.period)
        wmax = max(wmin, min(self.max_vel_theta, w0 + self.acc_lim_theta * self.period))
        vs = np.linspace(vmin, vmax, self.vx_samples) if self.vx_samples > 1 else np.array([vmax])
        ws = np.linspace(wmin, wmax, self.vtheta_samples) if self.vtheta_samples > 1 else np.array([0.0])
        return np.array([(v, w) for v in vs for w in ws])

    def rollouts(self, pose, samples: np.ndarray):
        """(N, M, 3) rollouts of the samples and each one's length in poses (≤ M)."""
        v, w = samples[:, 0], samples[:, 1]
        steps = np.maximum(np.ceil(np.maximum(np.abs(v) * self.sim_time / self.sim_granularity,
                                              np.abs(w) * self.sim_time / self.angular_sim_granularity)), 1)
        steps = steps.astype(np.int64)
        longest = int(steps.max())
        # each sample's own step (sim_time / its steps), computed on a common grid of its own length
        out = np.empty((len(samples), longest, 3))
        for n in np.unique(steps):
            rows = np.nonzero(steps == n)[0]
            out[rows, :n] = arc_rollouts(*pose, v[rows], np.zeros(len(rows)), w[rows], self.sim_time / n, int(n))
        return out, steps

    def distance_maps(self):
        """(path_dist, goal_dist) in cells over the costmap (base_local_planner's MapGrid)."""
        cm = self.costmap
        passable = cm.costs < INSCRIBED_INFLATED_OBSTACLE
        cells = cm.world_to_cell(self.path)
        h, w = cm.costs.shape
        inside = (cells[:, 0] >= 0) & (cells[:, 0] < w) & (cells[:, 1] >= 0) & (cells[:, 1] < h)
        dense = _densify_cells(cells[inside]) if inside.any() else np.zeros((0, 2), np.int64)
        path_dist = grid_distances(passable, dense[:, 0].copy(), dense[:, 1].copy())
        # the local goal: the last path point inside the costmap
        goal = dense[-1:] if len(dense) else np.zeros((0, 2), np.int64)
        goal_dist = grid_distances(passable, goal[:, 0].copy(), goal[:, 1].copy())
        return path_dist, goal_dist

    def score(self, pose, samples: np.ndarray, path_dist, goal_dist) -> np.ndarray:
        cm = self.costmap
        rollouts, lengths = self.rollouts(pose, samples)
        out = np.empty(len(samples))
        score_rollouts(cm.costs, cm.origin[0], cm.origin[1], cm.resolution, self.body, rollouts, lengths, path_dist,
                       goal_dist, self.pdist_scale, self.gdist_scale, self.occdist_scale, out)
        return out

    def plan(self, t: float, pose: np.ndarray):
        if self._escape_from is not None:
            moved = float(np.hypot(*(pose[:2] - self._escape_from[:2])))
            turned = abs(math.remainder(pose[2] - self._escape_from[2], 2 * math.pi))
            if moved < self.escape_reset_dist and turned < self.escape_reset_theta:
                return self.escape_vel, 0.0, 0.0
            self._escape_from = None
        if self._turn_from is not None and np.hypot(*(pose[:2] - self._turn_from)) >= self.oscillation_reset_dist:
            self._turn_block, self._turn_from = 0, None
        path_dist, goal_dist = self.distance_maps()
        samples = self.samples()
        scores = self.score(pose, samples, path_dist, goal_dist)
        self.last_samples, self.last_scores = samples, scores
        valid = scores >= 0
        if valid.any():
            best = int(np.flatnonzero(valid)[np.argmin(scores[valid])])
            return float(samples[best, 0]), 0.0, float(samples[best, 1])
        # turn in place, either way, at the rates the limits allow
        mags = np.linspace(self.min_in_place_vel_theta, self.max_vel_theta, max(self.vtheta_samples // 2, 1))
        turns = np.concatenate((mags, -mags))
        if self._turn_block:
            turns = turns[np.sign(turns) != self._turn_block]
        rotations = np.column_stack((np.zeros(len(turns)), turns))
        scores = self.score(pose, rotations, path_dist, goal_dist)
        valid = scores >= 0
        if valid.any():
            best = int(np.flatnonzero(valid)[np.argmin(scores[valid])])
            w = float(rotations[best, 1])
            self._turn_block, self._turn_from = -int(np.sign(w)), pose[:2].copy()
            return 0.0, 0.0, w
        self._escape_from = pose.copy()
        return self.escape_vel, 0.0, 0.0


def _densify_cells(cells: np.ndarray) -> np.ndarray:
    """Consecutive path cells joined by Bresenham lines (a sparse path leaves no gaps)."""
    out = [cells[0]]
    for a, b in zip(cells[:-1], cells[1:]):
        n = int(max(abs(b[0] - a[0]), abs(b[1] - a[1])))
        if n > 1:
            t = np.arange(1, n + 1)[:, None] / n
            out.extend(np.rint(a + (b - a) * t).astype(np.int64))
        elif n == 1:
            out.append(b)
    return np.asarray(out, np.int64)


@CONTROLLERS.register("dwa_barn")
class DWABarn(DWA):
    """DWA with the BARN challenge's move_base settings as defaults (its
    ``base_local_planner_params.yaml``: 0.5 m/s, 1.57 rad/s, acc 10 / 20, 2 s rollouts,
    6 × 20 samples, pdist 0.75, gdist 1.0, occdist 0.1, escape at −0.5 m/s; inflation 0.30 m from its
    ``costmap_common_params.yaml``, whose ``footprint_padding: 0.1`` is left at 0 here: with it our DWA
    succeeds in 7 of the 50 test worlds, without it in 27).
    """

    def __init__(self, max_vel_x: float = 0.5, min_vel_x: float = 0.1, max_vel_theta: float = 1.57,
                 min_in_place_vel_theta: float = 0.314, acc_lim_x: float = 10.0, acc_lim_theta: float = 20.0,
                 sim_time: float = 2.0, sim_granularity: float = 0.02, angular_sim_granularity: float = 0.02,
                 vx_samples: int = 6, vtheta_samples: int = 20, controller_frequency: float = 20.0,
                 pdist_scale: float = 0.75, gdist_scale: float = 1.0, occdist_scale: float = 0.1,
                 escape_vel: float = -0.5, escape_reset_dist: float = 0.1, escape_reset_theta: float = 0.1,
                 oscillation_reset_dist: float = 0.05, xy_goal_tolerance: float = 0.25,
                 inflation_radius: float = 0.30, cost_scaling_factor: float = 10.0, stall_window: float = 20.0,
                 stall_progress: float = 0.05, layers: str = "static", replan_interval: float = 1.0,
                 footprint_padding: float = 0.0, costmap_resolution: float = 0.05) -> None:
        super().__init__(max_vel_x, min_vel_x, max_vel_theta, min_in_place_vel_theta, acc_lim_x, acc_lim_theta,
                         sim_time, sim_granularity, angular_sim_granularity, vx_samples, vtheta_samples,
                         controller_frequency, pdist_scale, gdist_scale, occdist_scale, escape_vel,
                         escape_reset_dist, escape_reset_theta, oscillation_reset_dist, xy_goal_tolerance,
                         inflation_radius, cost_scaling_factor, stall_window, stall_progress, layers, replan_interval,
                         footprint_padding, costmap_resolution)

