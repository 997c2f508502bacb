"""The dynamic-window approach as ROS 1 ``base_local_planner`` runs it with ``dwa: true``, under move_base.

This is ``TrajectoryPlanner::createTrajectories`` / ``generateTrajectory``
(``TrajectoryPlannerROS``, the local planner the BARN challenge's
``move_base_DWA.launch`` names), read line by line (Fox, Burgard, Thrun,
"The Dynamic Window Approach to Collision Avoidance", IEEE RA Magazine 1997):

1. **Window**: ``max_vel_x`` is first capped by (distance to the local
   plan's end) / ``sim_time``; then the velocities reachable within one
   control period (``1 / controller_frequency``) under ``acc_lim_x`` and
   ``acc_lim_theta``, clipped to ``[min_vel_x, max_vel_x]`` and
   ``[−max_vel_theta, max_vel_theta]``.
2. **Samples**, in ROS's order: for each of ``vx_samples`` speeds from the
   window's lowest, first ω = 0, then ``vtheta_samples − 1`` turn rates from
   the window's lowest in steps of (max − min) / (``vtheta_samples`` − 1)
   (so the window's highest rate is never sampled, as in ROS).
3. **Rollout**: from the current pose and velocity, each sample approached
   under the acceleration limits and integrated by Euler steps of
   ``sim_time / n``, ``n = ⌊max(|v|·sim_time / sim_granularity,
   |ω| / angular_sim_granularity) + 0.5⌋`` (ROS's own formula: the angular
   term is not multiplied by ``sim_time``); the points are the poses at the
   start of each step, the current pose first.
4. **Rejection** at each point (``CostmapModel::footprintCost``): the cell
   off the local costmap, a ``LETHAL`` or ``NO_INFORMATION`` cell under the
   footprint's outline (``INSCRIBED`` on the outline is allowed: it only
   means an obstacle within the inscribed radius of the edge; a disc robot
   is rejected at ``INSCRIBED`` at its centre), or a cell no path or goal
   distance reaches.
5. **Score** (``meter_scoring``, under which TrajectoryPlannerROS multiplies
   all three weights by the cell size, ``occdist_scale`` too):
   ``(pdist_scale · path_dist + gdist_scale · goal_dist + occdist_scale ·
   occ_cost) · resolution`` at the last point; ``path_dist``
   and ``goal_dist`` are ``MapGrid``'s 4-connected breadth-first distances
   from the local plan's cells and from its last cell (the local goal),
   spread through cells below ``INSCRIBED`` (the path map also through the
   cells under the robot's current footprint), and ``occ_cost`` the largest
   outline cost or centre-cell cost met. The cheapest wins (ties: the first).
6. **In-place rotations** (ω = each window rate limited to at least
   ``min_in_place_vel_theta``, skipping those within one step of 0) are
   scored the same way and win when no dearer than the best so far and
   their end, ``heading_lookahead`` ahead, is nearer the local goal.
   Oscillation: after turning in place twice one way, the other way is
   barred until the robot has moved ``oscillation_reset_dist``.
7. **Escape**: when nothing is valid the robot backs up at ``escape_vel``
   (even when that rollout hits an obstacle, as ROS); until it has moved
   ``escape_reset_dist`` or turned ``escape_reset_theta`` only rotations are
   tried. A rollout failing for want of a path (cost −2) is no command.

The local plan is move_base's: the global plan pruned to its first point
within 1 m of the robot (``prune_plan``) and cut where it first leaves a
circle of half the local costmap's width (``transformGlobalPlan``), all
on the ``local_costmap_size`` rolling window around the robot.

move_base around it (``move_base_params.yaml``): the global path is planned
again on the global costmap by navfn, move_base's default global planner and
the challenge's (:mod:`~navlab.control.move_base_navfn`: its 50 + 0.8·cost
cell weights and interpolated potential, not navlab's 8-connected A*), from
the robot every ``1 / planner_frequency`` s (0: only when the local planner
fails, as move_base does; with a sensed costmap and ``planner_frequency`` 0
the costmap feed replans every ``replan_interval`` s instead); when the
local planner has found no command for ``controller_patience`` s, or the
global planner no path for ``planner_patience`` s, move_base runs its
recovery behaviours and aborts; here the run ends ``STALLED`` then (see
:meth:`DWA.command` for why the recoveries change nothing in these worlds).
``oscillation_timeout`` is 0 in the challenge (off), so a robot that keeps
finding commands keeps trying until the run's time limit: ``dwa_barn``'s
``stall_window`` is longer than any BARN run.

References
----------
D. Fox, W. Burgard, S. Thrun, "The Dynamic Window Approach to Collision
Avoidance", IEEE Robotics & Automation Magazine 4(1), 1997. ROS 1
navigation: ``base_local_planner/src/trajectory_planner.cpp``,
``costmap_model.cpp``, ``map_grid.cpp``, ``trajectory_planner_ros.cpp``,
``goal_functions.cpp``; ``move_base/src/move_base.cpp``; ``navfn/src/navfn.cpp``.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Optional

import numpy as np

from ..errors import ParameterError
from ..jit import njit
from ..limits import check_count
from ..world.costmap import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, footprint_cost_one
from .base import CONTROLLERS, RUNNING, STALLED, Command
from .local import CostmapController, check_number
from .move_base_navfn import plan_navfn

#: the most Euclidean steps one rollout may take (ROS's defaults give 22; a sim_granularity of 1e-9 m gave 10⁹
#: steps per rollout and a run that never ended: an attack on the command, session 17)
MAX_ROLLOUT_STEPS = 10_000
#: a distance no cell can have: the cell is unreachable from the path or goal (MapGrid's obstacleCosts)
UNREACHABLE = 1e18
#: rollout costs for a rejected rollout: the footprint meets an obstacle or leaves the map / no path reaches a point
HITS, NO_PATH = -1.0, -2.0
#: [m] move_base's prunePlan drops the plan's points before its first one this close to the robot
PRUNE_DISTANCE = 1.0
#: how many of its global paths a run keeps for its result and plot (the last ones; all are counted)
KEPT_PLANS = 100


@njit(cache=True)
def grid_distances(passable, sources_x, sources_y):
    """4-connected breadth-first distances (in cells) from the source cells (base_local_planner's
    ``MapGrid::computeTargetDistance``): a source is 0 whatever its cost, the search spreads only into
    ``passable`` cells; UNREACHABLE elsewhere."""
    h, w = passable.shape
    dist = np.full((h, w), UNREACHABLE)
    qx = np.empty(h * w + len(sources_x), np.int64)
    qy = np.empty(h * w + len(sources_x), np.int64)
    head, tail = 0, 0
    for i in range(len(sources_x)):
        x, y = sources_x[i], sources_y[i]
        if 0 <= x < w and 0 <= y < h and dist[y, x] != 0.0:
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
def _toward(goal, v, acc, dt):
    """base_local_planner's computeNewVelocity: ``v`` moved toward ``goal`` by at most ``acc · dt``."""
    if goal >= v:
        return min(goal, v + acc * dt)
    return max(goal, v - acc * dt)


@njit(cache=True)
def generate_trajectories(costs, ox, oy, res, body, x, y, th, vx, vth, samples, acc_x, acc_th, sim_time, sim_gran,
                          ang_gran, path_dist, goal_dist, pdist_scale, gdist_scale, occdist_scale, cost, end):
    """``TrajectoryPlanner::generateTrajectory`` for each sample (vx, ω): ``cost[i]`` its score, HITS or NO_PATH;
    ``end[i]`` its last valid point (x, y, θ). See the module for the rules."""
    h, w = costs.shape
    disc = body.shape[0] == 0
    for n in range(samples.shape[0]):
        vs, ws = samples[n, 0], samples[n, 1]
        steps = int(max(abs(vs) * sim_time / sim_gran, abs(ws) / ang_gran) + 0.5)
        if steps == 0:
            steps = 1
        dt = sim_time / steps
        xi, yi, ti, vi, wi = x, y, th, vx, vth
        occ, pd, gd = 0.0, 0.0, 0.0
        c = 0.0
        end[n, 0], end[n, 1], end[n, 2] = x, y, th
        for _ in range(steps):
            cx = int(math.floor((xi - ox) / res))
            cy = int(math.floor((yi - oy) / res))
            if cx < 0 or cy < 0 or cx >= w or cy >= h:
                c = HITS
                break
            fc = footprint_cost_one(costs, ox, oy, res, body, xi, yi, ti)
            if fc >= (INSCRIBED_INFLATED_OBSTACLE if disc else LETHAL_OBSTACLE):
                c = HITS
                break
            occ = max(occ, float(fc), float(costs[cy, cx]))
            pd, gd = path_dist[cy, cx], goal_dist[cy, cx]
            if pd >= UNREACHABLE or gd >= UNREACHABLE:
                c = NO_PATH
                break
            end[n, 0], end[n, 1], end[n, 2] = xi, yi, ti
            vi = _toward(vs, vi, acc_x, dt)
            wi = _toward(ws, wi, acc_th, dt)
            xi, yi, ti = xi + vi * math.cos(ti) * dt, yi + vi * math.sin(ti) * dt, ti + wi * dt
        cost[n] = c if c < 0 else (pdist_scale * pd + gdist_scale * gd + occdist_scale * occ) * res


def footprint_cells(costmap, body: np.ndarray, pose) -> np.ndarray:
    """(N, 2) cells (x, y) under the footprint at ``pose``, outline and inside (``FootprintHelper::
    getFootprintCells`` with ``fill``); a disc footprint (empty ``body``) is its centre cell."""
    x, y, th = (float(v) for v in pose[:3])
    if len(body) == 0:
        return costmap.world_to_cell([(x, y)])
    c, s = math.cos(th), math.sin(th)
    corners = costmap.world_to_cell(np.column_stack((x + c * body[:, 0] - s * body[:, 1],
                                                     y + s * body[:, 0] + c * body[:, 1])))
    outline = _densify_cells(np.vstack((corners, corners[:1])))
    cells = []
    for cx in np.unique(outline[:, 0]):
        col = outline[outline[:, 0] == cx, 1]
        cells.extend((cx, cy) for cy in range(int(col.min()), int(col.max()) + 1))
    return np.asarray(cells, np.int64)


def _densify_cells(cells: np.ndarray) -> np.ndarray:
    """Consecutive path cells joined by lines of cells (a sparse path leaves no gaps, as
    base_local_planner's ``adjustPlanResolution``)."""
    out = [cells[0]]
    for a, b in zip(cells[:-1], cells[1:]):
        n = int(max(abs(b[0] - a[0]), abs(b[1] - a[1])))
        if n > 1:
            t = np.arange(1, n + 1)[:, None] / n
            out.extend(np.rint(a + (b - a) * t).astype(np.int64))
        elif n == 1:
            out.append(b)
    return np.asarray(out, np.int64)


@CONTROLLERS.register("dwa")
class DWA(CostmapController):
    """Dynamic-window local planner (ROS base_local_planner, ``dwa: true``, under move_base); see the module.

    Defaults are base_local_planner's and move_base's; ``dwa_barn`` has the BARN challenge's.

    Parameters
    ----------
    max_vel_x, min_vel_x : float
        [m/s] forward speed range (0.5, 0.1).
    max_vel_theta, min_in_place_vel_theta : float
        [rad/s] turn-rate limit (both ways), and the slowest turn in place (1.0, 0.4).
    acc_lim_x, acc_lim_theta : float
        [m/s², rad/s²] acceleration limits (2.5, 3.2).
    sim_time, sim_granularity, angular_sim_granularity : float
        [s], [m], [rad] rollout horizon and step (1.0, 0.025, 0.025).
    vx_samples, vtheta_samples : int
        Samples per axis (3, 20).
    controller_frequency : float
        [Hz] sets the window's period (20).
    pdist_scale, gdist_scale, occdist_scale : float
        Score weights (0.6, 0.8, 0.01); the distances in metres (``meter_scoring``).
    heading_lookahead : float
        [m] how far ahead of a turn in place its end is judged against the local goal (0.325).
    escape_vel, escape_reset_dist, escape_reset_theta : float
        [m/s], [m], [rad] backing up when stuck (−0.1, 0.1, π/2).
    oscillation_reset_dist : float
        [m] (0.05).
    xy_goal_tolerance : float
        [m] (0.1).
    local_costmap_size : float
        [m] the side of the rolling local costmap the planner sees (10, costmap_2d's default and the
        challenge's).
    planner_frequency : float
        [Hz] move_base plans the global path again (navfn) from the robot this often (0: only after the
        local planner fails, move_base's default). Above 0 with a sensor layer, the costmap feed's own
        replanning is switched off (``replan_interval`` = ∞): move_base plans on the sensed costmap.
    controller_patience, planner_patience : float
        [s] move_base recovers and aborts (the run ends STALLED) after this long without a command, or
        without a global path (15, 5).
    inflation_radius, cost_scaling_factor : float
        The costmap's inflation (0.55 m, 10 1/m: ROS costmap_2d's defaults).
    layers, replan_interval, footprint_padding :
        See :class:`~navlab.control.local.CostmapController`.
    """

    speed_setting = "max_vel_x"

    def __init__(self, max_vel_x: float = 0.5, min_vel_x: float = 0.1, max_vel_theta: float = 1.0,
                 min_in_place_vel_theta: float = 0.4, acc_lim_x: float = 2.5, acc_lim_theta: float = 3.2,
                 sim_time: float = 1.0, sim_granularity: float = 0.025, angular_sim_granularity: float = 0.025,
                 vx_samples: int = 3, vtheta_samples: int = 20, controller_frequency: float = 20.0,
                 pdist_scale: float = 0.6, gdist_scale: float = 0.8, occdist_scale: float = 0.01,
                 heading_lookahead: float = 0.325,
                 escape_vel: float = -0.1, escape_reset_dist: float = 0.1, escape_reset_theta: float = math.pi / 2,
                 oscillation_reset_dist: float = 0.05, xy_goal_tolerance: float = 0.1,
                 local_costmap_size: float = 10.0, planner_frequency: float = 0.0,
                 controller_patience: float = 15.0, planner_patience: float = 5.0,
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
        steps = max(self.max_vel_x * self.sim_time / self.sim_granularity,
                    self.max_vel_theta / self.angular_sim_granularity)  # the rollout's n at the fastest sample
        if steps > MAX_ROLLOUT_STEPS:
            raise ParameterError(f"sim_granularity {self.sim_granularity:g} m and angular_sim_granularity "
                                 f"{self.angular_sim_granularity:g} rad give rollouts of up to {steps:.3g} steps, "
                                 f"more than {MAX_ROLLOUT_STEPS}: raise them (ROS's defaults, 0.025 and 0.025, "
                                 "give 22)")
        self.vx_samples = check_count("vx_samples", vx_samples, 1, 1000)
        self.vtheta_samples = check_count("vtheta_samples", vtheta_samples, 1, 1000)
        self.period = 1.0 / check_number("controller_frequency", controller_frequency, high=1e4)
        self.pdist_scale = check_number("pdist_scale", pdist_scale, allow_low=True)
        self.gdist_scale = check_number("gdist_scale", gdist_scale, allow_low=True)
        self.occdist_scale = check_number("occdist_scale", occdist_scale, allow_low=True)
        self.heading_lookahead = check_number("heading_lookahead", heading_lookahead, allow_low=True, high=100.0)
        self.escape_vel = check_number("escape_vel", escape_vel, low=-10.0, high=-1e-9)
        self.escape_reset_dist = check_number("escape_reset_dist", escape_reset_dist)
        self.escape_reset_theta = check_number("escape_reset_theta", escape_reset_theta)
        self.oscillation_reset_dist = check_number("oscillation_reset_dist", oscillation_reset_dist)
        self.local_costmap_size = check_number("local_costmap_size", local_costmap_size, high=1000.0)
        self.planner_frequency = check_number("planner_frequency", planner_frequency, allow_low=True, high=1e4)
        if self.planner_frequency > 0 and self.needs_scan:
            # move_base's planner (replan) plans on the sensed costmap itself, with navfn's costs: the
            # costmap feed's own replanning (Nav2-style, its A* weighting) is switched off
            self.replan_interval = math.inf
        self.controller_patience = check_number("controller_patience", controller_patience)
        self.planner_patience = check_number("planner_patience", planner_patience)
        self.last_scores: Optional[np.ndarray] = None  #: the last cycle's forward samples' costs (< 0 rejected)
        self.last_samples: Optional[np.ndarray] = None  #: (vx, ω) of those samples
        self.reset(np.zeros(2))

    def reset(self, goal, path=None) -> None:
        super().reset(goal, path)
        self.stall_reason = None  # a new run has not stalled
        self._prev: Optional[np.ndarray] = None  #: where the robot last turned in place (prev_x_, prev_y_)
        self._rotating = {1: False, -1: False}  #: rotating_left, rotating_right
        self._stuck = {1: False, -1: False}  #: stuck_left, stuck_right
        self._escaping = False
        self._escape_from: Optional[np.ndarray] = None
        self._failing_since: Optional[float] = None
        self._no_plan_since: Optional[float] = None
        self._last_plan = -math.inf
        self._replan_now = False
        self.stats = {"cycles": 0, "forward": 0, "rotate": 0, "escape": 0, "failed": 0, "replans": 0}
        #: the last KEPT_PLANS global paths move_base's planner made during the run, for the run's result and
        #: its plot (the path a run plotted and measured its tracking error against was only the first one:
        #: newcomer, session 29); at 20 Hz (dwa_barn) keeping all took 50 MB over a 341 s run (review)
        self.paths: deque = deque(maxlen=KEPT_PLANS)

    @property
    def plans_made(self) -> int:
        """How many global paths move_base's planner made during the run (``paths`` keeps the last ones)."""
        return self.stats["replans"]

    def set_path(self, path) -> None:
        super().set_path(path)
        self._plan_start = 0  #: how many of the path's points move_base has pruned

    # -- move_base around the local planner -----------------------------------
    def command(self, t: float, pose, points=None) -> Command:
        """As :class:`~navlab.control.local.CostmapController`, and STALLED once move_base would abort.

        move_base recovers when the local planner has found no command for ``controller_patience``
        s (or the global planner no path for ``planner_patience`` s): it clears the costmaps'
        obstacles beyond a square around the robot (conservative, then aggressive) and turns in
        place once round, each followed by a new try, then aborts. Every obstacle here is real and
        seen again at once, and a full turn ends at the pose where the planner failed, so the
        recoveries are not simulated: the run ends there (for BARN, a timeout either way)."""
        cmd = super().command(t, pose, points)
        if cmd.status != RUNNING or cmd.vx != 0.0 or cmd.omega != 0.0:
            return cmd
        for since, patience, what in ((self._failing_since, self.controller_patience, "no valid command"),
                                      (self._no_plan_since, self.planner_patience, "no global path")):
            if since is not None and t - since >= patience:
                self.velocity = np.zeros(3)
                self.stall_reason = f"move_base would abort: {what} for {patience:g} s"
                return Command(0.0, 0.0, 0.0, STALLED)
        return cmd

    def replan(self, t: float, pose: np.ndarray) -> None:
        """move_base's global planner (navfn, its default and the challenge's): a new path from the robot
        on the whole costmap."""
        self._last_plan, self._replan_now = t, False
        path = plan_navfn(self.costmap, pose, self.goal, allow_unknown=self.needs_scan)
        if path is None:
            self._no_plan_since = t if self._no_plan_since is None else self._no_plan_since
            return
        self._no_plan_since = None
        self.set_path(path)
        self.paths.append(self.path.copy())
        self.stats["replans"] += 1

    def local_plan(self, pose: np.ndarray) -> np.ndarray:
        """(N, 2) the plan the local planner sees: from the first point within half the local costmap's
        width until the plan first leaves that circle (transformGlobalPlan), then pruned to start at its
        first point within 1 m of the robot (prunePlan, which drops those points for good)."""
        radius = self.local_costmap_size / 2
        d = np.hypot(*(self.path[self._plan_start:] - pose[:2]).T)
        inside = d <= radius
        if not inside.any():
            return np.zeros((0, 2))
        i0 = int(np.argmax(inside))
        out = np.flatnonzero(~inside[i0:])
        i1 = i0 + (int(out[0]) if len(out) else len(d) - i0)
        near = np.flatnonzero(d[i0:i1] < PRUNE_DISTANCE)
        if not len(near):
            self._plan_start += i1
            return np.zeros((0, 2))
        k = i0 + int(near[0])
        self._plan_start += k
        return self.path[self._plan_start:self._plan_start + (i1 - k)]

    # -- the local planner ----------------------------------------------------
    def window(self, final_goal_dist: float = math.inf):
        """(vmin, vmax, dvx, wmin, wmax, dω): this cycle's dynamic window and sample steps."""
        v0, w0 = self.velocity[0], self.velocity[2]
        top = min(self.max_vel_x, final_goal_dist / self.sim_time)
        vmax = max(min(top, v0 + self.acc_lim_x * self.period), self.min_vel_x)
        vmin = max(self.min_vel_x, v0 - self.acc_lim_x * self.period)
        wmax = min(self.max_vel_theta, w0 + self.acc_lim_theta * self.period)
        wmin = max(-self.max_vel_theta, w0 - self.acc_lim_theta * self.period)
        dv = (vmax - vmin) / (self.vx_samples - 1) if self.vx_samples > 1 else 0.0
        dw = (wmax - wmin) / (self.vtheta_samples - 1) if self.vtheta_samples > 1 else 0.0
        return vmin, vmax, dv, wmin, wmax, dw

    def samples(self, final_goal_dist: float = math.inf) -> np.ndarray:
        """(vx_samples · vtheta_samples, 2) forward samples (vx, ω) in ROS's order: per speed, ω = 0 first."""
        vmin, _, dv, wmin, _, dw = self.window(final_goal_dist)
        out = []
        for i in range(self.vx_samples):
            v = vmin + i * dv
            out.append((v, 0.0))
            out.extend((v, wmin + j * dw) for j in range(self.vtheta_samples - 1))
        return np.array(out, float)

    def rotations(self, final_goal_dist: float = math.inf):
        """(vtheta_samples, 2) in-place turns (0, ω limited to ≥ min_in_place_vel_theta) and each one's
        unlimited rate (only those beyond one step from 0 may be chosen)."""
        _, _, _, wmin, _, dw = self.window(final_goal_dist)
        raw = wmin + dw * np.arange(self.vtheta_samples)
        limited = np.where(raw > 0, np.maximum(raw, self.min_in_place_vel_theta),
                           np.minimum(raw, -self.min_in_place_vel_theta))
        return np.column_stack((np.zeros(len(raw)), limited)), raw, dw

    def distance_maps(self, local, pose: np.ndarray, plan: np.ndarray):
        """(path_dist, goal_dist) in cells over the local costmap (base_local_planner's MapGrid), from the
        local plan's cells and its last cell inside the map (the local goal)."""
        from ..world.costmap import NO_INFORMATION

        passable = local.costs < INSCRIBED_INFLATED_OBSTACLE
        h, w = local.costs.shape
        cells = _densify_cells(local.world_to_cell(plan)) if len(plan) else np.zeros((0, 2), np.int64)
        ok = (cells[:, 0] >= 0) & (cells[:, 0] < w) & (cells[:, 1] >= 0) & (cells[:, 1] < h)
        ok[ok] = local.costs[cells[ok, 1], cells[ok, 0]] != NO_INFORMATION
        if ok.any():  # the cells from the first usable one until the plan first leaves the map
            first = int(np.argmax(ok))
            gone = np.flatnonzero(~ok[first:])
            cells = cells[first:first + (int(gone[0]) if len(gone) else len(cells) - first)]
        else:
            cells = cells[:0]
        goal_dist = grid_distances(passable, cells[-1:, 0].copy(), cells[-1:, 1].copy())
        under = footprint_cells(local, self.body, pose)
        under = under[(under[:, 0] >= 0) & (under[:, 0] < w) & (under[:, 1] >= 0) & (under[:, 1] < h)]
        passable[under[:, 1], under[:, 0]] = True  # MapGrid's within_robot: the path map only
        path_dist = grid_distances(passable, cells[:, 0].copy(), cells[:, 1].copy())
        return path_dist, goal_dist

    def score(self, local, pose, samples: np.ndarray, path_dist, goal_dist):
        """(costs, ends) of the samples' rollouts on the local costmap."""
        cost = np.empty(len(samples))
        end = np.empty((len(samples), 3))
        generate_trajectories(local.costs, local.origin[0], local.origin[1], local.resolution, self.body,
                              float(pose[0]), float(pose[1]), float(pose[2]), float(self.velocity[0]),
                              float(self.velocity[2]), np.ascontiguousarray(samples, float), self.acc_lim_x,
                              self.acc_lim_theta, self.sim_time, self.sim_granularity, self.angular_sim_granularity,
                              path_dist, goal_dist, self.pdist_scale, self.gdist_scale, self.occdist_scale, cost,
                              end)
        return cost, end

    def plan(self, t: float, pose: np.ndarray):
        self.stats["cycles"] += 1
        if self._replan_now or (self.planner_frequency > 0
                                and t - self._last_plan >= 1.0 / self.planner_frequency - 1e-9):
            self.replan(t, pose)
        plan = self.local_plan(pose)
        if not len(plan):
            return self._fail(t)
        local = self.costmap.window(pose[:2], self.local_costmap_size, self.local_costmap_size)
        path_dist, goal_dist = self.distance_maps(local, pose, plan)
        final_goal_dist = float(np.hypot(*(plan[-1] - pose[:2])))
        best_cost, best = -1.0, None
        if not self._escaping:
            samples = self.samples(final_goal_dist)
            costs, _ = self.score(local, pose, samples, path_dist, goal_dist)
            self.last_samples, self.last_scores = samples, costs
            for i, c in enumerate(costs):
                if c >= 0 and (best is None or c < best_cost):
                    best_cost, best = c, (float(samples[i, 0]), float(samples[i, 1]))
        turns, raw, dw = self.rotations(final_goal_dist)
        costs, ends = self.score(local, pose, turns, path_dist, goal_dist)
        heading_dist = math.inf
        h, w = local.costs.shape
        for i, c in enumerate(costs):
            if c < 0 or not (best is None or c <= best_cost) or not (raw[i] > dw or raw[i] < -dw):
                continue
            ex, ey, eth = ends[i]
            cx, cy = local.world_to_cell([(ex + self.heading_lookahead * math.cos(eth),
                                           ey + self.heading_lookahead * math.sin(eth))])[0]
            if not (0 <= cx < w and 0 <= cy < h) or goal_dist[cy, cx] >= heading_dist:
                continue
            # as ROS: a right turn is barred once the robot got stuck turning left, and the other way round
            if (raw[i] < 0 and not self._stuck[1]) or (raw[i] > 0 and not self._stuck[-1]):
                best_cost, best, heading_dist = c, (0.0, float(turns[i, 1])), goal_dist[cy, cx]
        if best is not None:
            self._failing_since = None
            if not best[0] > 0:
                side = 1 if best[1] > 0 else -1
                self._stuck[side] = self._stuck[side] or self._rotating[side]
                self._rotating[side] = True
                self._prev = pose[:2].copy()
                self.stats["rotate"] += 1
            else:
                self.stats["forward"] += 1
            self._reset_flags(pose)
            return best[0], 0.0, best[1]
        # nothing valid: back up, even into an obstacle (ROS turns a footprint hit into cost 1)
        cost, _ = self.score(local, pose, np.array([(self.escape_vel, 0.0)]), path_dist, goal_dist)
        if not self._escaping and cost[0] > NO_PATH:
            self._escaping, self._escape_from = True, pose.copy()
        self._reset_flags(pose)
        if cost[0] == NO_PATH:
            return self._fail(t)
        self._failing_since = None
        self.stats["escape"] += 1
        return self.escape_vel, 0.0, 0.0

    def _reset_flags(self, pose: np.ndarray) -> None:
        """The oscillation flags once the robot has moved away from its last turn in place, and the
        escape once it has moved or turned enough."""
        if self._prev is None or np.hypot(*(pose[:2] - self._prev)) > self.oscillation_reset_dist:
            self._rotating = {1: False, -1: False}
            self._stuck = {1: False, -1: False}
        if self._escape_from is None or np.hypot(*(pose[:2] - self._escape_from[:2])) > self.escape_reset_dist \
                or abs(math.remainder(pose[2] - self._escape_from[2], 2 * math.pi)) > self.escape_reset_theta:
            self._escaping = False

    def _fail(self, t: float):
        """No command this cycle: move_base stops the robot and plans the global path again."""
        self.stats["failed"] += 1
        if self._failing_since is None:
            self._failing_since = t
        self._replan_now = True
        return 0.0, 0.0, 0.0


@CONTROLLERS.register("dwa_barn")
class DWABarn(DWA):
    """DWA with the BARN challenge's move_base settings as defaults.

    From ``the-barn-challenge/jackal_helper/configs/params``: ``base_local_planner_params.yaml``
    (0.5 m/s, 1.57 rad/s, acc 10 / 20, 2 s rollouts at 0.02 m / 0.02 rad, 6 × 20 samples, pdist 0.75,
    gdist 1.0, occdist 0.1, heading_lookahead 0.325, escape at −0.5 m/s reset after 0.1 m or 0.1 rad,
    oscillation reset 0.05 m, xy tolerance 0.25 m, controller_frequency 20 Hz);
    ``costmap_common_params.yaml`` (``footprint_padding`` 0.1 m, inflation 0.30 m; costmap_2d's
    ``cost_scaling_factor`` 10 and 0.05 m cells; an obstacle layer fed by the laser and an inflation
    layer, no static map, hence ``layers='sensor'``); ``local_costmap_params.yaml`` (10 × 10 m rolling
    window); ``move_base_params.yaml`` (``planner_frequency`` 20 Hz, ``controller_patience`` 15 s,
    ``planner_patience`` 5 s, ``oscillation_timeout`` 0: no give-up while commands are found, hence
    a ``stall_window`` longer than any run); ``move_base_DWA.launch`` (``base_global_planner``
    ``navfn/NavfnROS`` with its defaults: :mod:`~navlab.control.move_base_navfn`).
    """

    def __init__(self, max_vel_x: float = 0.5, min_vel_x: float = 0.1, max_vel_theta: float = 1.57,
                 min_in_place_vel_theta: float = 0.314, acc_lim_x: float = 10.0, acc_lim_theta: float = 20.0,
                 sim_time: float = 2.0, sim_granularity: float = 0.02, angular_sim_granularity: float = 0.02,
                 vx_samples: int = 6, vtheta_samples: int = 20, controller_frequency: float = 20.0,
                 pdist_scale: float = 0.75, gdist_scale: float = 1.0, occdist_scale: float = 0.1,
                 heading_lookahead: float = 0.325,
                 escape_vel: float = -0.5, escape_reset_dist: float = 0.1, escape_reset_theta: float = 0.1,
                 oscillation_reset_dist: float = 0.05, xy_goal_tolerance: float = 0.25,
                 local_costmap_size: float = 10.0, planner_frequency: float = 20.0,
                 controller_patience: float = 15.0, planner_patience: float = 5.0,
                 inflation_radius: float = 0.30, cost_scaling_factor: float = 10.0, stall_window: float = 1000.0,
                 stall_progress: float = 0.05, layers: str = "sensor", replan_interval: float = 1.0,
                 footprint_padding: float = 0.1, costmap_resolution: float = 0.05) -> None:
        super().__init__(max_vel_x, min_vel_x, max_vel_theta, min_in_place_vel_theta, acc_lim_x, acc_lim_theta,
                         sim_time, sim_granularity, angular_sim_granularity, vx_samples, vtheta_samples,
                         controller_frequency, pdist_scale, gdist_scale, occdist_scale, heading_lookahead,
                         escape_vel, escape_reset_dist, escape_reset_theta, oscillation_reset_dist,
                         xy_goal_tolerance, local_costmap_size, planner_frequency, controller_patience,
                         planner_patience, inflation_radius, cost_scaling_factor, stall_window, stall_progress,
                         layers, replan_interval, footprint_padding, costmap_resolution)
