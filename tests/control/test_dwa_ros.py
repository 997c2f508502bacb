"""DWA as ROS 1 base_local_planner's TrajectoryPlanner (dwa: true) under move_base: a plain re-reading
of its rules, cell by cell, against the compiled planner; footprint cells against shapely; a gap the
rectangle clears by centimetres, judged with shapely; move_base's patience."""

import math
from collections import deque

import numpy as np
import pytest
import shapely

from navlab.control import make_controller
from navlab.control.base import RUNNING, STALLED
from navlab.control.dwa import footprint_cells
from navlab.robots import make_robot
from navlab.sim import Simulation
from navlab.world import Bounds, Circle, World
from navlab.world.costmap import build_costmap
from navlab.world.footprint import Footprint

JACKAL = Footprint.polygon([[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]])
POSTS = World("posts", Bounds(-1, 6, -2, 2), (0, 0), (5, 0), (Circle((1.8, 0.05), 0.15), Circle((3.3, -0.5), 0.1)))


def _bfs(passable, sources):
    """4-connected unit-step distances: sources at 0 whatever their cost, spreading through passable cells."""
    h, w = passable.shape
    d = np.full((h, w), np.inf)
    queue = deque()
    for x, y in sources:
        if 0 <= x < w and 0 <= y < h and d[y, x] != 0:
            d[y, x] = 0
            queue.append((x, y))
    while queue:
        x, y = queue.popleft()
        for nx, ny in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)):
            if 0 <= nx < w and 0 <= ny < h and passable[ny, nx] and d[ny, nx] > d[y, x] + 1:
                d[ny, nx] = d[y, x] + 1
                queue.append((nx, ny))
    return d


def _ros_choice(dwa, local, pose, path_cells, path_dist, goal_dist):
    """TrajectoryPlanner::createTrajectories for a fresh planner (no oscillation or escape flags), written
    out plainly: the forward costs and the command it returns."""
    res = local.resolution
    v0, w0 = dwa.velocity[0], dwa.velocity[2]
    end_xy = local.cell_to_world(path_cells[-1:])[0]
    top = min(dwa.max_vel_x, math.hypot(*(end_xy - pose[:2])) / dwa.sim_time)
    vmax = max(min(top, v0 + dwa.acc_lim_x * dwa.period), dwa.min_vel_x)
    vmin = max(dwa.min_vel_x, v0 - dwa.acc_lim_x * dwa.period)
    wmax = min(dwa.max_vel_theta, w0 + dwa.acc_lim_theta * dwa.period)
    wmin = max(-dwa.max_vel_theta, w0 - dwa.acc_lim_theta * dwa.period)
    dv, dw = (vmax - vmin) / (dwa.vx_samples - 1), (wmax - wmin) / (dwa.vtheta_samples - 1)

    def rollout(vs, ws):
        n = max(int(max(abs(vs) * dwa.sim_time / dwa.sim_granularity, abs(ws) / dwa.angular_sim_granularity) + 0.5),
                1)
        dt = dwa.sim_time / n
        x, y, th, v, om = *pose, v0, w0
        occ, last = 0.0, None
        for _ in range(n):
            cell = local.world_to_cell([(x, y)])[0]
            if int(local.footprint_cost([(x, y, th)], JACKAL)[0]) >= 254:  # LETHAL (or unknown) on the outline
                return -1.0, None
            occ = max(occ, float(local.footprint_cost([(x, y, th)], JACKAL)[0]),
                      float(local.costs[cell[1], cell[0]]))
            pd, gd = path_dist[cell[1], cell[0]], goal_dist[cell[1], cell[0]]
            if not (np.isfinite(pd) and np.isfinite(gd)):
                return -2.0, None
            last = (x, y, th)
            v = min(vs, v + dwa.acc_lim_x * dt) if vs >= v else max(vs, v - dwa.acc_lim_x * dt)
            om = min(ws, om + dwa.acc_lim_theta * dt) if ws >= om else max(ws, om - dwa.acc_lim_theta * dt)
            x, y, th = x + v * math.cos(th) * dt, y + v * math.sin(th) * dt, th + om * dt
        return (dwa.pdist_scale * pd + dwa.gdist_scale * gd + dwa.occdist_scale * occ) * res, last

    costs, best, best_cost = [], None, -1.0
    for i in range(dwa.vx_samples):
        for ws in [0.0] + [wmin + j * dw for j in range(dwa.vtheta_samples - 1)]:
            c, _ = rollout(vmin + i * dv, ws)
            costs.append(c)
            if c >= 0 and (best is None or c < best_cost):
                best, best_cost = (vmin + i * dv, ws), c
    heading = math.inf
    for i in range(dwa.vtheta_samples):
        raw = wmin + i * dw
        limited = max(raw, dwa.min_in_place_vel_theta) if raw > 0 else min(raw, -dwa.min_in_place_vel_theta)
        c, last = rollout(0.0, limited)
        if c < 0 or not (best is None or c <= best_cost) or not abs(raw) > dw:
            continue
        cx, cy = local.world_to_cell([(last[0] + dwa.heading_lookahead * math.cos(last[2]),
                                       last[1] + dwa.heading_lookahead * math.sin(last[2]))])[0]
        ahead = goal_dist[cy, cx] if np.isfinite(goal_dist[cy, cx]) else 1e18
        if ahead < heading:
            best, best_cost, heading = (0.0, limited), c, ahead
    return np.array(costs), best


@pytest.mark.parametrize("pose, path_y, velocity, kind", [
    ((0.9, 0.1, 0.15), 0.425, (0.3, 0.0, 0.2), "forward"),
    # facing the post with a clear outline, every rollout ahead meets its inflation: a turn in place is
    # no dearer and wins (as in the BARN gaps)
    ((1.1, 0.025, 0.3), 0.025, (0.0, 0.0, 0.0), "rotate"),
])
def test_dwa_barn_chooses_what_the_ros_rules_choose(pose, path_y, velocity, kind):
    costmap = build_costmap(POSTS, JACKAL, inflation_radius=0.30, cost_scaling_factor=10.0)
    dwa = make_controller("dwa_barn", layers="static", planner_frequency=0.0)
    # a path along cell centres (every cell, so any densification gives the same cells), inside 5 m
    xs = np.arange(0.025, 4.0, 0.05)
    path = np.column_stack((xs, np.full(len(xs), path_y)))
    path = path[xs > pose[0] - 0.2]
    dwa.reset((4.0, path[-1, 1]), path)
    dwa.set_costmap(costmap, JACKAL)
    dwa.velocity = np.array(velocity, float)
    pose = np.array(pose, float)
    vx, _, w = dwa.plan(0.0, pose)
    local = costmap.window(pose[:2], 10.0, 10.0)
    passable = local.costs < 253
    cells = local.world_to_cell(path)
    goal_dist = _bfs(passable, cells[-1:])
    under = local.world_to_cell(np.array([c.centroid.coords[0] for c in _cells_inside(local, pose)]))
    passable_path = passable.copy()
    passable_path[under[:, 1], under[:, 0]] = True  # the robot's own cells (MapGrid's within_robot)
    path_dist = _bfs(passable_path, cells)
    costs, choice = _ros_choice(dwa, local, pose, cells, path_dist, goal_dist)
    np.testing.assert_allclose(dwa.last_scores, costs, atol=1e-9)
    assert choice is not None and (vx, w) == pytest.approx(choice, abs=1e-12)
    assert (vx > 0) == (kind == "forward")


def _cells_inside(costmap, pose):
    """Squares of the cells whose centres lie inside the footprint (shapely)."""
    body = shapely.Polygon(JACKAL.at(pose))
    x0, y0, x1, y1 = body.bounds
    c0, c1 = costmap.world_to_cell([(x0, y0), (x1, y1)])
    out = []
    for cx in range(c0[0], c1[0] + 1):
        for cy in range(c0[1], c1[1] + 1):
            centre = costmap.cell_to_world([(cx, cy)])[0]
            if body.contains(shapely.Point(centre)):
                out.append(shapely.box(*(centre - 0.025), *(centre + 0.025)))
    return out


@pytest.mark.parametrize("theta", [0.0, 0.3, 1.2, -2.5])
def test_footprint_cells_cover_the_rectangle(theta):
    costmap = build_costmap(POSTS, JACKAL)
    pose = (1.013, 0.377, theta)
    got = {tuple(c) for c in footprint_cells(costmap, np.asarray(JACKAL.vertices), pose)}
    inside = {tuple(costmap.world_to_cell([c.centroid.coords[0]])[0]) for c in _cells_inside(costmap, pose)}
    assert inside <= got  # every cell whose centre is under the body
    body = shapely.Polygon(JACKAL.at(pose))
    for cx, cy in got:  # and nothing a cell's diagonal away from it
        assert body.distance(shapely.Point(costmap.cell_to_world([(cx, cy)])[0])) <= 0.05 * math.sqrt(2)


def test_a_gap_a_few_centimetres_wider_than_the_padded_rectangle_is_driven_through():
    # two posts 0.60 m apart (surface to surface) across the way: the 0.53 m wide padded Jackal fits with
    # 3.5 cm a side; its outline meets INSCRIBED cells in the gap, which ROS allows, and no LETHAL one
    gap = World("gap", Bounds(-1, 5, -2, 2), (0, 0), (4, 0),
                (Circle((2.0, 0.4), 0.1), Circle((2.0, -0.4), 0.1), Circle((2.0, 1.0), 0.3),
                 Circle((2.0, -1.0), 0.3)))
    robot = make_robot("jackal")
    from navlab.sensors.lidar import Lidar
    from navlab.sim.runner import costmap_path

    ctrl = make_controller("dwa_barn")
    sim = Simulation(gap, robot, ctrl, (0, 0, 0), (4, 0), path=np.array(((0, 0), (4, 0))), max_time=60,
                     lidar=Lidar(**robot.laser))
    sim.path = costmap_path(gap, robot, ctrl, (0, 0, 0), (4, 0))
    result = sim.run(seed=1)
    assert result.status.name == "REACHED", result.reason
    body = [shapely.Polygon(JACKAL.at(p)) for p in result.true_poses]
    clearance = min(b.distance(shapely.Point(o.center)) - o.radius for b in body for o in gap.obstacles)
    assert 0.0 < clearance < 0.2  # it went through the gap, not round the posts


def test_move_base_gives_up_after_its_patience():
    # a post inside the body: no LETHAL cell on the outline (ROS lets it be), the centre's cell LETHAL, so no
    # rollout (each starts there) has a path to the goal, and no global path starts there
    pin = World("pin", Bounds(-1, 6, -2, 2), (0, 0), (5, 0), (Circle((1.0, 0.0), 0.02),))
    costmap = build_costmap(pin, JACKAL, inflation_radius=0.30, cost_scaling_factor=10.0)
    pose = np.array((1.0, 0.0, 0.0))
    assert costmap.cost_at([pose[:2]])[0] == 254 and costmap.footprint_cost([pose], JACKAL)[0] == 253
    for planner_patience, expected in ((5.0, 5.0), (30.0, 15.0)):
        dwa = make_controller("dwa_barn", layers="static", planner_patience=planner_patience)
        dwa.reset((5.0, 0.0), np.array(((0.0, 0.0), (5.0, 0.0))))
        dwa.set_costmap(costmap, JACKAL)
        statuses = []
        for k in range(800):
            cmd = dwa.command(k * 0.05, pose)
            statuses.append((k * 0.05, cmd.status, cmd.vx, cmd.omega))
            if cmd.status != RUNNING:
                break
        assert statuses[-1][1] == STALLED and statuses[-1][0] == pytest.approx(expected)
        assert all(s == RUNNING and vx == 0.0 and w == 0.0 for _, s, vx, w in statuses[:-1])
        # the run's reason says which patience ran out (it said "a local minimum?" for every controller)
        what = "no global path for 5 s" if planner_patience == 5.0 else "no valid command for 15 s"
        assert dwa.why_stalled() == f"move_base would abort: {what}"
        dwa.reset((5.0, 0.0), np.array(((0.0, 0.0), (5.0, 0.0))))
        assert dwa.why_stalled() == "no progress along its path (blocked, or a path the robot cannot follow)"
