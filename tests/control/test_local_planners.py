"""DWA, MPPI and RPP: against brute force and hand-derived values, and driving a Jackal past obstacles."""

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import shortest_path

from navlab.control import make_controller
from navlab.control.rpp import carrot_on_path
from navlab.robots import make_robot
from navlab.sim import Simulation
from navlab.world import Bounds, Circle, World
from navlab.world.costmap import LETHAL_OBSTACLE, Costmap, build_costmap
from navlab.world.footprint import Footprint

JACKAL = Footprint.polygon([[-0.21, -0.165], [-0.21, 0.165], [0.21, 0.165], [0.21, -0.165]])
POSTS = World("posts", Bounds(-1, 6, -2, 2), (0, 0), (5, 0), (Circle((1.8, 0.05), 0.15), Circle((3.3, -0.5), 0.1)))


def _bfs_truth(passable, sources):
    """4-connected unit-step distances from the source cells, by scipy's shortest paths."""
    h, w = passable.shape
    idx = np.arange(h * w).reshape(h, w)
    rows, cols = [], []
    for dy, dx in ((0, 1), (1, 0)):
        a = passable[: h - dy, : w - dx] & passable[dy:, dx:]
        rows += list(idx[: h - dy, : w - dx][a])
        cols += list(idx[dy:, dx:][a])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(h * w, h * w))
    src = [idx[y, x] for x, y in sources if passable[y, x]]
    d = shortest_path(graph, directed=False, indices=src, unweighted=True).min(axis=0)
    return d.reshape(h, w)


def test_dwa_picks_what_brute_force_scoring_picks():
    costmap = build_costmap(POSTS, JACKAL, inflation_radius=0.5, cost_scaling_factor=5.0)
    dwa = make_controller("dwa_barn")
    path = np.column_stack((np.linspace(0, 5, 60), 0.3 * np.sin(np.linspace(0, 5, 60))))
    dwa.reset((5, 0), path)
    dwa.set_costmap(costmap, JACKAL)
    dwa.velocity = np.array((0.3, 0.0, 0.2))
    pose = np.array((0.9, 0.1, 0.15))
    vx, _, w = dwa.plan(0.0, pose)
    # brute force: every sample scored by a plain loop over its rollout with the public costmap calls
    passable = costmap.costs < 253
    cells = costmap.world_to_cell(path)
    from navlab.control.dwa import _densify_cells

    dense = _densify_cells(cells)
    path_d = _bfs_truth(passable, dense)
    goal_d = _bfs_truth(passable, dense[-1:])
    best, choice = math.inf, None
    for v, om in dwa.samples():
        steps = int(max(math.ceil(max(abs(v) * 2.0 / 0.02, abs(om) * 2.0 / 0.02)), 1))
        x, y, th = pose
        occ, ok = 0, True
        for k in range(1, steps + 1):
            t = 2.0 * k / steps
            if abs(om) < 1e-9:
                p = (x + v * t * math.cos(th), y + v * t * math.sin(th), th)
            else:
                p = (x + v / om * (math.sin(th + om * t) - math.sin(th)),
                     y - v / om * (math.cos(th + om * t) - math.cos(th)), th + om * t)
            c = int(costmap.footprint_cost([p], JACKAL)[0])
            if c >= 253:
                ok = False
                break
            occ = max(occ, c)
        if not ok:
            continue
        cx, cy = costmap.world_to_cell([p[:2]])[0]
        if not np.isfinite(path_d[cy, cx]) or not np.isfinite(goal_d[cy, cx]):
            continue
        score = 0.75 * path_d[cy, cx] * 0.05 + 1.0 * goal_d[cy, cx] * 0.05 + 0.1 * occ
        if score < best - 1e-9:
            best, choice = score, (v, om)
    assert choice is not None
    assert (vx, w) == pytest.approx(choice, abs=1e-12)
    # the window: reachable within one 50 ms period under acc 10 m/s² and 20 rad/s², inside the limits
    s = dwa.samples()
    assert s[:, 0].min() == pytest.approx(0.1) and s[:, 0].max() == pytest.approx(0.5)
    assert s[:, 1].min() == pytest.approx(0.2 - 1.0) and s[:, 1].max() == pytest.approx(0.2 + 1.0)


def test_mppi_with_zero_noise_keeps_its_nominal_sequence():
    mppi = make_controller("mppi", vx_std=0.0, wz_std=0.0, batch_size=64, time_steps=20)
    costmap = build_costmap(POSTS, JACKAL)
    mppi.reset((5, 0), np.array(((0, 0), (5, 0))))
    mppi.set_costmap(costmap, JACKAL)
    nominal = np.column_stack((np.linspace(0.1, 0.4, 20), np.zeros(20), np.linspace(-0.2, 0.2, 20)))
    mppi.sequence = nominal.copy()
    mppi.velocity = np.array((0.1, 0.0, -0.2))
    out = mppi.optimize(np.array((0.0, 0.0, 0.0)))
    np.testing.assert_allclose(out, nominal, atol=1e-12)


def test_mppi_is_deterministic_under_a_seed_and_prefers_the_free_side():
    def run(seed):
        mppi = make_controller("mppi", batch_size=400)
        mppi.seed(np.random.default_rng(seed))
        mppi.reset((5, 0), np.array(((0, 0), (5, 0))))
        mppi.set_costmap(build_costmap(POSTS, JACKAL), JACKAL)
        return [mppi.plan(0.05 * k, np.array((0.0, 0.0, 0.0))) for k in range(3)]

    assert run(1) == run(1)
    assert run(1) != run(2)


def test_rpp_curvature_on_a_circle_is_one_over_r():
    radius = 2.0
    phi = np.linspace(0, math.pi, 400)
    path = np.column_stack((radius * np.sin(phi), radius - radius * np.cos(phi)))  # from (0,0) heading +x, turning left
    rpp = make_controller("rpp", lookahead_dist=0.6, use_cost_regulated_linear_velocity_scaling=False,
                          regulated_linear_scaling_min_radius=0.1, max_linear_accel=100.0)
    rpp.reset(path[-1], path)
    rpp.set_costmap(Costmap(np.zeros((200, 200), np.uint8), 0.05, (-5, -5)), JACKAL)
    v, _, w = rpp.plan(0.0, np.array((0.0, 0.0, 0.0)))
    assert w / v == pytest.approx(1 / radius, rel=1e-3)
    carrot = carrot_on_path(path, (0, 0, 0), 0.6)
    assert np.hypot(*carrot) == pytest.approx(0.6, abs=1e-9)


@pytest.mark.parametrize("name, params", [("dwa", {}), ("dwa_barn", {}), ("rpp", {}),
                                           ("mppi", {"batch_size": 300})])
def test_each_drives_a_jackal_past_the_posts(name, params):
    robot = make_robot("jackal")
    ctrl = make_controller(name, **params)
    sim = Simulation(POSTS, robot, ctrl, (0, 0, 0), (5, 0), path=np.array(((0, 0), (5, 0))), max_time=60)
    # the straight line runs through the first post: the costmap feed's global path goes around it
    from navlab.sim.runner import costmap_path

    sim.path = costmap_path(POSTS, robot, ctrl, (0, 0, 0), (5, 0))
    result = sim.run(seed=3)
    assert result.status.name == "REACHED", result.reason
    # independent check: the footprint kept off both posts all the way (shapely)
    import shapely

    body = [shapely.Polygon(JACKAL.at(p)) for p in result.true_poses]
    for post in POSTS.obstacles:
        disc = shapely.Point(post.center)
        assert min(b.distance(disc) for b in body) > post.radius


@pytest.mark.parametrize("name, params, words", [
    ("dwa", {"vx_samples": 0}, "vx_samples must be an integer"),
    ("dwa", {"max_vel_x": -1}, "max_vel_x must be > 0"),
    ("dwa", {"min_vel_x": 2.0}, "min_vel_x must be"),
    ("mppi", {"temperature": 0}, "temperature must be > 0"),
    ("mppi", {"motion_model": "car"}, "motion_model must be diff or omni"),
    ("rpp", {"max_lookahead_dist": 0.1}, "max_lookahead_dist"),
    ("rpp", {"layers": "lidar"}, "layers must be one of"),
    ("rpp", {"inflation_radius": float("nan")}, "inflation_radius must be finite"),
])
def test_bad_settings_name_the_field(name, params, words):
    with pytest.raises(ValueError, match=words):
        make_controller(name, **params)


def test_inflation_below_the_footprint_is_refused_when_the_run_is_built():
    with pytest.raises(ValueError, match="inflation_radius = 0.1 m is below the footprint's inscribed radius"):
        Simulation(POSTS, make_robot("jackal"), make_controller("rpp", inflation_radius=0.1), (0, 0, 0), (5, 0),
                   path=np.array(((0, 0), (5, 0))))
    assert LETHAL_OBSTACLE == 254
