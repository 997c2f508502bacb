"""Hybrid A*'s Reeds–Shepp distance table (navlab.grid.hybrid_table): its entries, and that a query's
answer does not depend on what earlier queries (or other threads) wrote into it."""

import math
import threading

import numpy as np
import pytest

from navlab.grid import hybrid_table
from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.occupancy import OccupancyGrid
from navlab.result import Status
from navlab.sampling import reeds_shepp

ROBOT = [[-0.2, -0.15], [0.3, -0.15], [0.3, 0.15], [-0.2, 0.15]]


def _room():
    """A 6 x 4 m room at 0.1 m with two walls to drive around: within the table's reach from any goal
    (169 entries of 0.05 m at 72 bins), so a query asked again solves nothing."""
    blocked = np.zeros((40, 60), bool)
    blocked[0, :] = blocked[-1, :] = blocked[:, 0] = blocked[:, -1] = True
    blocked[:27, 20:22] = True
    blocked[13:, 40:42] = True
    return OccupancyGrid(blocked, resolution=0.1)


QUERIES = [((0.6, 0.6, 0.0), (5.4, 3.4, math.pi / 2)), ((5.4, 0.6, math.pi), (0.6, 3.4, -math.pi / 2)),
           ((3.0, 3.5, 0.3), (1.0, 0.5, 2.0)), ((0.6, 3.4, -1.0), (5.0, 0.8, 0.0))]


def _answer(result):
    return result.status, result.cost, result.stats["expansions"], result.stats["nodes"], result.path.tobytes()


def test_an_entry_is_the_reeds_shepp_length_from_its_lattice_pose_mirrored_or_not():
    """Entry (i, j, k) is the full solver's length from (i·s, j·s, k·step) in the goal's frame; a pose
    below the goal's axis reads its mirror image, whose length the solver also finds equal."""
    radius, res, bins = 0.4, 0.05, 72
    step = 2 * math.pi / bins
    table, spacing, half = hybrid_table.distance_table.__wrapped__(radius, res, bins)
    assert spacing == res / 2 and half >= 1
    rng = np.random.default_rng(7)
    goal = (1.3, -0.7, 0.9)
    gcos, gsin = math.cos(goal[2]), math.sin(goal[2])
    for _ in range(300):
        pose = (goal[0] + rng.uniform(-2, 2), goal[1] + rng.uniform(-2, 2), rng.uniform(-math.pi, math.pi))
        index, px, py, pth, qx, qy, qth = hybrid_table.table_pose(*pose, *goal, gcos, gsin, spacing, step, bins, half)
        assert index >= 0 and (qx, qy, qth) == (0.0, 0.0, 0.0) and py >= 0.0
        # the lattice pose is the relative pose rounded: within half a spacing per axis, half a bin in heading
        dx, dy = pose[0] - goal[0], pose[1] - goal[1]
        lx, ly = gcos * dx + gsin * dy, -gsin * dx + gcos * dy
        rel = pose[2] - goal[2]
        if ly < 0:
            ly, rel = -ly, -rel
        assert abs(px - lx) <= spacing / 2 + 1e-12 and abs(py - ly) <= spacing / 2 + 1e-12
        assert abs(math.remainder(pth - rel, 2 * math.pi)) <= step / 2 + 1e-12
        want = float(reeds_shepp.distances(np.array([[px, py, pth]]), np.zeros((1, 3)), radius)[0])
        got = hybrid_table.reeds_shepp_memo(table, index, px, py, pth, 0.0, 0.0, 0.0, radius, math.inf)
        assert got == pytest.approx(want, rel=1e-12, abs=1e-12) and table[index] == got
        assert hybrid_table.reeds_shepp_memo(table, index, px, py, pth, 0.0, 0.0, 0.0, radius, math.inf) == got
        mirror = float(reeds_shepp.distances(np.array([[px, -py, -pth]]), np.zeros((1, 3)), radius)[0])
        assert mirror == pytest.approx(want, rel=1e-9, abs=1e-12)


def test_a_pose_beyond_the_tables_reach_is_solved_where_it_is():
    radius, res, bins = 0.4, 0.05, 72
    _, spacing, half = hybrid_table.distance_table.__wrapped__(radius, res, bins)
    far = (half + 1) * spacing
    out = hybrid_table.table_pose(far, 0.0, 0.5, 0.0, 0.0, 0.0, 1.0, 0.0, spacing, 2 * math.pi / bins, bins, half)
    assert out == (-1, far, 0.0, 0.5, 0.0, 0.0, 0.0)
    assert hybrid_table.table_pose(0.1, 0.2, 0.3, 0.0, 0.0, 0.0, 1.0, 0.0, spacing, 0.1, bins, -1)[0] == -1


def test_the_table_is_kept_per_robot_and_bounded():
    hybrid_table.distance_table.cache_clear()
    a = hybrid_table.distance_table(0.4, 0.05, 72)
    assert hybrid_table.distance_table(0.4, 0.05, 72) is a
    assert hybrid_table.distance_table(0.5, 0.05, 72) is not a
    # the reach: max(10 m, 20 radii) where 2^22 entries hold it (0.4 m on 1 m cells), else what they hold
    for radius, res, bins, reach in ((0.4, 0.05, 72, 4.225), (4.385, 1.0, 72, 84.5), (0.4, 1.0, 72, 10.0),
                                     (1e-3, 1e-3, 1440, 0.0185), (100.0, 0.01, 4, 3.615)):
        table, spacing, half = hybrid_table.distance_table.__wrapped__(radius, res, bins)
        assert table.size == (2 * half + 1) * (half + 1) * bins <= hybrid_table.MAX_ENTRIES
        assert spacing == res / 2 and half * spacing == pytest.approx(reach)


@pytest.mark.parametrize("res, radius", [(0.07, 0.4), (0.15, 0.4), (0.14, 4.5), (0.05, 0.4), (1.0, 4.385), (0.013, 2.0)])
def test_poses_at_the_reach_read_an_entry_in_the_table_or_none(res, radius):
    """Offsets just inside the float limit (half + 0.5)·spacing once rounded to entry half + 1: the next
    row's entry (j), or past the table's end (i) into memory another robot's table held (review, session
    22: res 0.07 m, an offset of 5.9325 m; res 0.15 m, nextafter(10.0875, 0)). Every index read is now an
    entry of the table whose lattice pose lies within half a spacing of the pose, or −1."""
    bins = 72
    step = 2 * math.pi / bins
    table, spacing, half = hybrid_table.distance_table.__wrapped__(radius, res, bins)
    edge = (half + 0.5) * spacing
    offsets = [edge, math.nextafter(edge, 0.0), math.nextafter(edge, math.inf), half * spacing,
               (half - 0.5) * spacing, math.nextafter((half - 0.5) * spacing, 0.0), 0.0, 5.9325, 10.0875]
    offsets += [math.nextafter(o, 0.0) for o in offsets]
    for ox in offsets:
        for oy in offsets:
            for sx, sy in ((1, 1), (-1, 1), (1, -1), (-1, -1)):
                x, y = sx * ox, sy * oy
                index, px, py, pth, *_ = hybrid_table.table_pose(x, y, 0.3, 0.0, 0.0, 0.0, 1.0, 0.0, spacing, step,
                                                                 bins, half)
                if index < 0:
                    assert max(abs(x), abs(y)) >= (half + 0.5) * spacing - 1e-9 * spacing
                    continue
                assert 0 <= index < table.size
                i, j = round(px / spacing), round(py / spacing)
                assert abs(i) <= half and 0 <= j <= half
                assert index == ((i + half) * (half + 1) + j) * bins + round(pth / step) % bins
                assert abs(px - x) <= spacing / 2 + 1e-12 and abs(py - abs(y)) <= spacing / 2 + 1e-12


def test_a_query_along_the_reach_leaves_other_entries_and_robots_alone():
    """The review's query: nodes driven straight at exactly 5.9325 m from the goal (res 0.07 m, the edge
    of the table's reach) wrote the length of their pose into the entry of a pose 7 cm behind the goal,
    and a later query near the goal then answered otherwise (1.24527 m in 374 expansions against 1.26301 m
    in 45 from an empty table)."""
    grid = OccupancyGrid(np.zeros((100, 100), bool), resolution=0.07)
    kw = dict(robot_radius=0.1, analytic_expansion=False)
    near = ((1.87, 1.46, 0.23), (3.1, 1.53, 0.0))
    hybrid_table.distance_table.cache_clear()
    alone = _answer(plan_hybrid(grid, *near, 0.4, **kw))
    hybrid_table.distance_table.cache_clear()
    other = hybrid_table.distance_table(0.5, 0.05, 72)[0]  # another robot's table, mapped next to it or not
    plan_hybrid(grid, (3.5, 6.4325, 0.0), (3.5, 0.5, 0.0), 0.4, **kw)
    table, spacing, half = hybrid_table.distance_table(0.4, 0.07, 72)
    behind = ((-2 + half) * (half + 1)) * 72  # entry (-2, 0, 0): 0.14 m behind the goal, facing its way
    assert table[behind] in (0.0, pytest.approx(0.14))
    assert _answer(plan_hybrid(grid, *near, 0.4, **kw)) == alone
    assert not other.any()


def test_a_query_answers_the_same_from_an_empty_table_a_filled_one_and_with_the_table_off_it_solves_each_time():
    """The first query solves lengths and keeps them; asked again it reads them all (nothing solved)
    and expands the same nodes to the same path, bit for bit, as it does after other queries wrote
    their entries. With ``distance_table=False`` every query solves as many as the first."""
    grid = _room()
    assert hybrid_table.distance_table(0.4, 0.1, 72)[2] * 0.05 > math.hypot(6.0, 4.0)
    hybrid_table.distance_table.cache_clear()
    first = [plan_hybrid(grid, s, g, 0.4, footprint=ROBOT) for s, g in QUERIES]
    assert all(r.status is Status.EXACT for r in first)
    assert all(r.stats["heuristics_solved"] > 0 for r in first)
    again = [plan_hybrid(grid, s, g, 0.4, footprint=ROBOT) for s, g in reversed(QUERIES)][::-1]
    assert [_answer(r) for r in again] == [_answer(r) for r in first]
    assert all(r.stats["heuristics_solved"] == 0 for r in again)
    hybrid_table.distance_table.cache_clear()
    alone = plan_hybrid(grid, *QUERIES[2], 0.4, footprint=ROBOT)
    assert _answer(alone) == _answer(first[2])
    off = [plan_hybrid(grid, s, g, 0.4, footprint=ROBOT, distance_table=False) for s, g in QUERIES * 2]
    assert [r.stats["heuristics_solved"] for r in off[:4]] == [r.stats["heuristics_solved"] for r in off[4:]]
    assert all(r.status is Status.EXACT for r in off)


def test_smacs_analytic_schedule_answers_the_same_whatever_the_table_holds():
    """With analytic_expansion_ratio the schedule reads the key a node is expanded under, so a read entry
    takes the same path through the lazy queue as a solved one."""
    grid = _room()
    hybrid_table.distance_table.cache_clear()
    kw = dict(footprint=ROBOT, analytic_expansion_ratio=3.5, analytic_expansion_max_length=3.0)
    cold = [_answer(plan_hybrid(grid, s, g, 0.4, **kw)) for s, g in QUERIES]
    warm = [_answer(plan_hybrid(grid, s, g, 0.4, **kw)) for s, g in QUERIES]
    assert cold == warm


def test_threads_filling_one_table_get_the_single_threaded_answers():
    """8 threads, 40 queries, one robot's table filled by whichever thread needs an entry first."""
    grid = _room()
    hybrid_table.distance_table.cache_clear()
    want = [_answer(plan_hybrid(grid, s, g, 0.4, footprint=ROBOT, distance_table=False)) for s, g in QUERIES]
    # the table's answers may differ from the exact lengths' (rounded poses); the reference is the table's
    # own from a single thread, on an empty table
    hybrid_table.distance_table.cache_clear()
    single = [_answer(plan_hybrid(grid, s, g, 0.4, footprint=ROBOT)) for s, g in QUERIES]
    assert [a[0] for a in single] == [a[0] for a in want]
    hybrid_table.distance_table.cache_clear()
    got = {}

    def work(t):
        for i in range(5):
            q = (t + i) % len(QUERIES)
            got[(t, i)] = (q, _answer(plan_hybrid(grid, *QUERIES[q], 0.4, footprint=ROBOT)))

    threads = [threading.Thread(target=work, args=(t,)) for t in range(8)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert len(got) == 40 and all(answer == single[q] for q, answer in got.values())
