"""Dubins and Reeds–Shepp shortest paths against OMPL, hand-derived optima and
their own geometry (every path reaches its goal and never turns tighter than r)."""

import math

import numpy as np
import pytest

from navlab.angles import HeadingWarning
from navlab.sampling import dubins, reeds_shepp

SOLVERS = [dubins, reeds_shepp]


def random_pairs(n, seed=0, span=10.0):
    rng = np.random.default_rng(seed)
    a = np.column_stack([rng.uniform(-span, span, (n, 2)), rng.uniform(-math.pi, math.pi, n)])
    b = np.column_stack([rng.uniform(-span, span, (n, 2)), rng.uniform(-math.pi, math.pi, n)])
    return a, b


@pytest.mark.parametrize("name", ["DubinsStateSpace", "ReedsSheppStateSpace"])
@pytest.mark.parametrize("radius", [0.5, 1.0, 3.0])
def test_lengths_equal_ompl_on_10000_random_pairs(name, radius):
    ob = pytest.importorskip("ompl.base")
    ours_module = dubins if name.startswith("Dubins") else reeds_shepp
    space = getattr(ob, name)(radius)
    s1, s2 = space.allocState(), space.allocState()
    a, b = random_pairs(10_000, seed=int(radius * 10))
    ref = np.empty(len(a))
    for i in range(len(a)):
        s1.setX(a[i, 0]), s1.setY(a[i, 1]), s1.setYaw(a[i, 2])
        s2.setX(b[i, 0]), s2.setY(b[i, 1]), s2.setYaw(b[i, 2])
        ref[i] = space.distance(s1, s2)
    ours = ours_module.distances(a, b, radius)
    np.testing.assert_allclose(ours, ref, rtol=1e-9, atol=0)


@pytest.mark.parametrize("solver", SOLVERS)
def test_every_path_reaches_its_goal_within_the_curvature_bound(solver):
    a, b = random_pairs(400, seed=3, span=4.0)
    radius = 0.8
    words = set()
    for start, goal in zip(a, b):
        path = solver.shortest(start, goal, radius)
        words.add(path.word)
        end = np.array(path.end)
        assert np.hypot(*(end[:2] - goal[:2])) < 1e-9 * max(1.0, path.length)
        assert abs((end[2] - goal[2] + math.pi) % (2 * math.pi) - math.pi) < 1e-9
        poses, direction = path.sample(0.05)
        steps = np.hypot(*np.diff(poses[:, :2], axis=0).T)
        assert steps.max() <= 0.05 + 1e-12
        assert np.allclose(poses[0], start) and np.allclose(poses[-1, :2], goal[:2])
        # curvature: an arc of chord c turning by Δθ has radius c / (2 sin(Δθ/2)) ≥ r
        turn = np.abs(np.diff(poses[:, 2]))
        arcs = turn > 1e-12
        radii = steps[arcs] / (2 * np.sin(turn[arcs] / 2))
        assert radii.size == 0 or radii.min() >= radius * (1 - 1e-9)
        if solver is dubins:
            assert (direction == 1).all()
    # the random pairs exercise most words, not one family
    assert len(words) >= (5 if solver is dubins else 12)


def test_reeds_shepp_is_never_longer_than_dubins_nor_shorter_than_the_straight_line():
    a, b = random_pairs(2000, seed=5)
    rs, db = reeds_shepp.distances(a, b, 1.0), dubins.distances(a, b, 1.0)
    line = np.hypot(*(b[:, :2] - a[:, :2]).T)
    assert (rs <= db * (1 + 1e-12)).all()
    assert (rs >= line * (1 - 1e-12)).all() and (db >= line * (1 - 1e-12)).all()
    assert (rs < db - 1e-6).mean() > 0.3  # reversing pays off often


@pytest.mark.parametrize("solver", SOLVERS)
def test_hand_derived_optima(solver):
    r = 2.0
    # straight ahead: the distance itself
    assert solver.distance((0, 0, 0), (5, 0, 0), r) == pytest.approx(5.0, rel=1e-12)
    # a left half turn onto the parallel lane 2r to the left: half a circle, π r
    path = solver.shortest((0, 0, 0), (0, 2 * r, math.pi), r)
    assert path.length == pytest.approx(math.pi * r, rel=1e-12) and path.word == "L"
    # the same pose: nothing to drive
    assert solver.distance((1, 2, 0.3), (1, 2, 0.3), r) == pytest.approx(0.0, abs=1e-9)


def test_reeds_shepp_reverses_straight_back_and_dubins_must_loop():
    r = 1.0
    back = reeds_shepp.shortest((0, 0, 0), (-1.5, 0, 0), r)
    assert back.word == "S" and back.segments[0] == pytest.approx(-1.5) and back.cusps == 0
    # forward only, the shortest way to a pose 1.5 m behind is a loop: longer than 2πr
    assert dubins.distance((0, 0, 0), (-1.5, 0, 0), r) > 2 * math.pi * r


def test_a_sideways_shift_needs_a_cusp():
    path = reeds_shepp.shortest((0, 0, 0), (0, 0.5, 0), 1.0)
    assert path.cusps >= 1
    _, direction = path.sample(0.01)
    assert (direction == 1).any() and (direction == -1).any()


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("radius,field", [(0, "turning_radius"), (-1, "turning_radius"),
                                          (float("nan"), "turning_radius"), ("1", "turning_radius")])
def test_a_bad_turning_radius_is_named(solver, radius, field):
    with pytest.raises(ValueError, match=field):
        solver.shortest((0, 0, 0), (1, 1, 0), radius)


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("goal,field", [((1, 1, float("nan")), "goal theta"), ((1, float("inf"), 0), "goal y"),
                                        ((1, 1), "goal"), (None, "goal")])
def test_a_bad_pose_is_named(solver, goal, field):
    with pytest.raises(ValueError, match=field):
        solver.shortest((0, 0, 0), goal, 1.0)


@pytest.mark.parametrize("heading", [1e8, -1e16, 7.0, 1e300])
def test_any_finite_heading_is_the_heading_it_wraps_to(heading):
    """Headings beyond ±1e7 rad were refused here and by plan_hybrid while navlab.plan and the
    command line wrapped them (session 15's left-alone list): every one now plans as the heading
    math.remainder gives, bit for bit, in the solvers and in Hybrid A*."""
    from navlab.grid import OccupancyGrid
    from navlab.grid.hybrid_astar import plan_hybrid

    wrapped = math.remainder(heading, 2 * math.pi)
    assert -math.pi <= wrapped <= math.pi
    for solver in SOLVERS:  # (no warning: the solvers' callers pass θ + s/r on purpose)
        assert solver.shortest((0, 0, heading), (3, 1, 0.5), 1.0).length == \
            solver.shortest((0, 0, wrapped), (3, 1, 0.5), 1.0).length
    grid = OccupancyGrid(np.zeros((30, 30), dtype=bool), 0.1)
    with pytest.warns(HeadingWarning):
        far = plan_hybrid(grid, (0.5, 0.5, heading), (2.5, 2.0, 1.0), 0.4)
    near = plan_hybrid(grid, (0.5, 0.5, wrapped), (2.5, 2.0, 1.0), 0.4)
    assert far.status == near.status and far.cost == near.cost and np.array_equal(far.path, near.path)


def test_a_heading_in_degrees_is_warned_about_at_the_callers_line():
    """Headings beyond ±2π were planned silently through the API (the CLI printed a note; session 15's
    left-alone list): a planner's HeadingWarning names the caller's line, with the degrees reading."""
    import warnings

    import navlab

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        navlab.plan("trap", "rrt", max_iter=50, seed=1, goal=(16.0, 6.0, 90))
        dubins.shortest((0, 0, 3.0), (2, 1, 9.0), 1.0)  # a solver: θ + s/r beyond a turn is no mistake
    (one,) = [w for w in caught if issubclass(w.category, HeadingWarning)]
    assert str(one.message) == ("goal theta 90 is beyond ±2π: headings are radians (90° would be 1.5708 rad; "
                                f"it is planned as {math.remainder(90, 2 * math.pi):.4f})")
    assert one.filename == __file__


def test_the_dubins_length_alone_is_the_full_solve_bit_for_bit():
    """dubins.length skips words that cannot be shorter than the best found (Hybrid A*'s heuristic,
    SE(2) nearest neighbours); it must return solve's t + p + q exactly, on random inputs and on
    the edge cases: zero distance, zero and full-turn headings, the CCC range."""
    from navlab.sampling import dubins

    rng = np.random.default_rng(5)
    d = np.concatenate([rng.uniform(0, 0.1, 3000), rng.uniform(0, 4, 3000), rng.uniform(0, 40, 3000),
                        np.zeros(200), np.full(200, 2.0), np.full(200, 4.0)])
    alpha = rng.uniform(0, 2 * np.pi, d.size)
    beta = rng.uniform(0, 2 * np.pi, d.size)
    alpha[::7], beta[::11], beta[::13] = 0.0, 0.0, np.pi
    for i in range(d.size):
        _, t, p, q = dubins.solve(d[i], alpha[i], beta[i])
        assert dubins.length(d[i], alpha[i], beta[i]) == t + p + q, (d[i], alpha[i], beta[i])


@pytest.mark.parametrize("radius", [0.5, 1.0, 100.0])
def test_a_goal_on_the_start_circle_is_one_arc_for_dubins(radius):
    """A goal on the start's left (right) turning circle, heading along it, is one left (right) arc
    forward: the LSL (RSR) word's straight part is then rounding noise, whose direction must not turn
    either arc into a near-full loop (which added 2π·r to Hybrid A*'s paths one arc from the goal)."""
    rng = np.random.default_rng(int(radius))
    for turn in np.concatenate([rng.uniform(0.01, 2 * np.pi - 0.01, 200), [0.5, 1.0, np.pi / 2, 3.0]]):
        for side in (1, -1):
            start = (rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-np.pi, np.pi))
            x, y, th = start
            # the point `turn` rad along the circle of radius r to the start's left (side 1) or right
            goal = (x + side * radius * (math.sin(th + side * turn) - math.sin(th)),
                    y - side * radius * (math.cos(th + side * turn) - math.cos(th)), th + side * turn)
            path = dubins.shortest(start, goal, radius)
            # (the straight part, at most 2e-7 radii here, is counted: dubins._centres_apart)
            assert path.length == pytest.approx(radius * turn, rel=1e-9, abs=1e-6 * radius), (start, turn, side)
            end = path.sample(radius * 1e-3)[0][-1]
            assert np.hypot(*(end[:2] - goal[:2])) < 1e-6 * (1 + radius)
            assert dubins.distance(start, goal, radius) == pytest.approx(radius * turn, rel=1e-9, abs=1e-6 * radius)
