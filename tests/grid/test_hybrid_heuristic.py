"""Hybrid A*'s heuristic, holonomic field and smoother against plain references:
the fast paths must give the very values the direct computations give."""

import heapq
import math

import numpy as np
import pytest

from navlab.grid import hybrid_astar
from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.hybrid_field import holonomic_field
from navlab.grid.hybrid_search import _heuristic
from navlab.grid.occupancy import OccupancyGrid
from navlab.sampling import dubins, reeds_shepp


def random_pairs(rng, n, spread):
    starts = np.column_stack([rng.uniform(-spread, spread, (n, 2)), rng.uniform(-math.pi, math.pi, n)])
    goals = np.column_stack([rng.uniform(-spread, spread, (n, 2)), rng.uniform(-math.pi, math.pi, n)])
    return starts, goals


@pytest.mark.parametrize("spread", [0.5, 3.0, 30.0])
def test_the_dubins_length_bounds_the_reeds_shepp_length_from_above(spread):
    """The premise of the gate: every Dubins path is a Reeds–Shepp path."""
    starts, goals = random_pairs(np.random.default_rng(7), 2000, spread)
    fwd, both = dubins.distances(starts, goals, 0.8), reeds_shepp.distances(starts, goals, 0.8)
    assert (both <= fwd * (1 + 1e-12) + 1e-12).all()


@pytest.mark.parametrize("reverse", [True, False])
def test_the_heuristic_is_the_larger_of_the_field_and_the_exact_distance(reverse):
    """Fields drawn around the exact distance, so both branches of the gate and its edge are hit."""
    rng = np.random.default_rng(11)
    starts, goals = random_pairs(rng, 3000, 4.0)
    radius = 0.6
    exact = (reeds_shepp if reverse else dubins).distances(starts, goals, radius)
    fields = exact * rng.choice([0.5, 1 - 1e-12, 1.0, 1 + 1e-12, 2.0], len(exact))
    got = np.array([_heuristic(f, *s, *g, radius, reverse)
                    for f, s, g in zip(fields, starts, goals)])
    assert got == pytest.approx(np.maximum(fields, exact), rel=1e-12, abs=1e-12)
    assert (got >= fields).all()


def test_no_table_of_exact_distances_at_cell_centres_minus_a_position_slack_is_a_lower_bound():
    """Why the robot's distance table (hybrid_table) rounds, as Smac's does, and is not a lower bound
    with a |Δp| slack: the distances are not Lipschitz in position. A sideways shift of 1 mm costs a Reeds–Shepp
    path of about 9 cm, and for Dubins a pose 1 mm to the side of the goal needs
    more than half a loop while the goal itself is 0 away. The heading bound
    r·|Δθ| holds for Reeds–Shepp (L+ R− L+ turns on the spot at that cost) but
    not for Dubins, which cannot turn on the spot."""
    r, shift = 1.0, 0.001
    assert reeds_shepp.distance((0, 0, 0), (0, shift, 0), r) > 50 * shift
    assert dubins.distance((0, shift, 0), (0, 0, 0), r) > math.pi * r
    assert reeds_shepp.distance((0, 0, 0), (0, 0, 0.01), r) == pytest.approx(r * 0.01, rel=1e-9)
    assert dubins.distance((0, 0, 0), (0, 0, 0.01), r) > math.pi * r


def heap_field(passable, gx, gy, res):
    """The field by textbook Dijkstra with a binary heap."""
    h, w = passable.shape
    dist = np.full((h, w), np.inf)
    dist[gy, gx] = 0.0
    heap = [(0.0, gy, gx)]
    while heap:
        d, y, x = heapq.heappop(heap)
        if d > dist[y, x]:
            continue
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                ny, nx = y + dy, x + dx
                if (dx, dy) == (0, 0) or not (0 <= nx < w and 0 <= ny < h) or not passable[ny, nx]:
                    continue
                if dx and dy and not (passable[y, nx] and passable[ny, x]):
                    continue
                nd = d + (math.sqrt(2.0) * res if dx and dy else res)
                if nd < dist[ny, nx]:
                    dist[ny, nx] = nd
                    heapq.heappush(heap, (nd, ny, nx))
    return dist


def random_field_problems(rng, count):
    """``count`` random (passable, gx, gy, res): maps of 1-29 cells a side, up to half blocked, the goal free."""
    for _ in range(count):
        h, w = rng.integers(1, 30, 2)
        passable = rng.random((h, w)) > rng.uniform(0.0, 0.5)
        gy, gx = rng.integers(0, h), rng.integers(0, w)
        passable[gy, gx] = True
        yield passable, gx, gy, rng.uniform(0.01, 2.0)


def test_the_bucket_queue_field_equals_heap_dijkstra_bit_for_bit():
    for passable, gx, gy, res in random_field_problems(np.random.default_rng(3), 60):
        assert np.array_equal(holonomic_field(passable, gx, gy, res), heap_field(passable, gx, gy, res))


def reference_shortcut(kinds, lengths, start, r, motion, blocked, clear, lattice, common):
    """The smoother with the public solvers, one Python call per candidate (as before it was compiled),
    reading every pose's cells (no clearance map: ``clear`` unused), poses they reject checked exactly."""
    smoothed = _reference_shortcut(list(zip(kinds.tolist(), lengths.tolist())), start, r, motion, blocked, lattice,
                                   common)
    return np.array([k for k, _ in smoothed], dtype=np.int64), np.array([s for _, s in smoothed], dtype=float)


def _reference_shortcut(segments, start, r, motion, blocked, lattice, common):
    """:func:`reference_shortcut` on a list of (kind, length) segments."""
    from navlab.sampling.curves import LETTERS, CurvePath
    from navlab.grid.hybrid_astar import exact_grow
    from navlab.sampling.footprint_lattice import NO_CLEARANCE, curve_free

    solver = reeds_shepp if motion == "reeds_shepp" else dubins
    poses = [start]
    for kind, s in segments:
        poses.append(CurvePath(poses[-1], LETTERS[kind], (s,), r).end)
    acc = np.concatenate([[0.0], np.cumsum([abs(s) for _, s in segments])])
    out, i, n = [], 0, len(poses) - 1
    while i < n:
        for j in range(n, i + 1, -1):
            path = solver.shortest(poses[i], poses[j], r)
            if path.length >= acc[j] - acc[i] - 1e-9:
                continue
            kinds, lengths = path._codes()
            if curve_free(blocked, common[0], *poses[i], kinds, lengths, r, lattice.ds, *common[1:], *NO_CLEARANCE,
                          lattice.vertices, lattice.disc, exact_grow(lattice)):
                out.extend(zip(kinds.tolist(), lengths.tolist()))
                i = j
                break
        else:
            out.append(segments[i])
            i += 1
    return out


@pytest.mark.parametrize("motion", ["reeds_shepp", "dubins"])
def test_the_compiled_smoother_makes_the_same_path_as_the_public_solvers(motion, monkeypatch):
    blocked = np.ones((120, 120), bool)
    blocked[20:42, 10:92] = False
    blocked[20:110, 70:92] = False
    grid = OccupancyGrid(blocked, resolution=0.05)
    robot = [[-0.45, -0.31], [-0.45, 0.31], [0.45, 0.31], [0.45, -0.31]]
    query = (grid, (1.2, 1.55, 0.0), (4.05, 4.6, math.pi / 2), 0.5)
    fast = plan_hybrid(*query, motion=motion, footprint=robot)
    monkeypatch.setattr(hybrid_astar, "_shortcut", reference_shortcut)
    slow = plan_hybrid(*query, motion=motion, footprint=robot)
    assert fast.stats["segments"] == slow.stats["segments"] and np.array_equal(fast.path, slow.path)


def test_the_smoothers_compiled_wrap_is_curves_wrap_bit_for_bit():
    from navlab.sampling.curves import _wrap_compiled
    from navlab.sampling.curves import _wrap

    rng = np.random.default_rng(4)
    angles = np.concatenate([rng.uniform(-50.0, 50.0, 20000), np.arange(-8, 9) * math.pi,
                             np.arange(-8, 9) * math.pi + 1e-15, [0.0, -0.0, 1e-300, 3.0 * math.pi / 2]])
    for a in angles.tolist():
        assert _wrap_compiled(a) == _wrap(a), a


def test_the_same_query_gives_the_same_path_bit_for_bit():
    blocked = np.zeros((160, 160), bool)
    blocked[40:120, 70:74] = True
    grid = OccupancyGrid(blocked, resolution=0.05)
    runs = [plan_hybrid(grid, (1.0, 4.0, 0.0), (6.5, 4.0, math.pi), 0.5, robot_radius=0.2) for _ in range(2)]
    assert np.array_equal(runs[0].path, runs[1].path) and runs[0].stats["segments"] == runs[1].stats["segments"]


def test_the_search_queue_pops_in_heapq_tuple_order():
    """The compiled heap must give the (key, node) order a heapq of tuples gives, ties included,
    so the search expands the nodes it did with heapq."""
    from navlab.grid.hybrid_search import _pop, _push

    rng = np.random.default_rng(5)
    n = 3000
    key = rng.integers(0, 40, n).astype(float)  # many equal keys
    node = rng.integers(0, 500, n)
    hkey, hnode, hentry = np.empty(n), np.empty(n, np.int64), np.empty(n, np.int64)
    size, reference = 0, []
    for e in range(n):
        _push(hkey, hnode, hentry, size, key[e], node[e], e)
        size += 1
        heapq.heappush(reference, (key[e], node[e]))
        if rng.random() < 0.4:
            k, v, out = _pop(hkey, hnode, hentry, size)
            size -= 1
            assert (k, v) == heapq.heappop(reference) == (key[out], node[out])
    while size:
        k, v, out = _pop(hkey, hnode, hentry, size)
        size -= 1
        assert (k, v) == heapq.heappop(reference) == (key[out], node[out])
