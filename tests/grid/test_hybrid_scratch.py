"""Hybrid A* reuses each thread's search arrays between queries: the answers must
not depend on what the thread searched before, nor on other threads."""

import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.occupancy import OccupancyGrid

ROBOT = [[-0.3, -0.2], [-0.3, 0.2], [0.3, 0.2], [0.3, -0.2]]


def walled(n, res=0.1):
    """An n x n map with a wall across its middle, open for 1.5 m at one end."""
    blocked = np.zeros((n, n), bool)
    blocked[n // 2, : n - round(1.5 / res)] = True
    return OccupancyGrid(blocked, resolution=res)


def queries():
    """Queries on maps of three sizes, two heading counts and both motions, found and failed:
    what one thread's scratch arrays see in turn (a large search, then others on other maps)."""
    big, small, tiny = walled(80), walled(50), walled(30)
    out = []
    for grid in (big, small, tiny, big):
        far = grid.width * grid.resolution - 0.4
        for motion in ("reeds_shepp", "dubins"):
            for bins in (72, 16):
                out.append((grid, (0.4, 0.4, 0.0), (far, far, 1.5), motion, bins, 5_000))
                out.append((grid, (far, far, 3.0), (0.4, 0.4, -1.5), motion, bins, 5_000))
                out.append((grid, (0.4, 0.4, 0.0), (far, far, 1.5), motion, bins, 300))  # FAILED: the budget
    return out


def answer(query):
    grid, start, goal, motion, bins, budget = query
    r = plan_hybrid(grid, start, goal, 0.5, motion=motion, footprint=ROBOT, heading_bins=bins,
                    max_expansions=budget)
    return r.status, r.cost, r.stats["expansions"], None if r.path is None else r.path.tobytes()


def in_new_thread(query):
    """The answer from a thread of its own: its first search, on new scratch arrays."""
    out = []
    t = threading.Thread(target=lambda: out.append(answer(query)))
    t.start()
    t.join()
    return out[0]


def test_a_thread_answers_each_query_as_a_new_thread_would():
    qs = queries()
    fresh = [in_new_thread(q) for q in qs]
    statuses = {a[0].name for a in fresh}
    assert statuses == {"EXACT", "FAILED"} and len({a[2] for a in fresh}) > 10  # the queries differ
    assert [answer(q) for q in qs] == fresh


def test_threads_searching_at_once_give_the_single_threaded_answers():
    qs = queries() * 3
    alone = [answer(q) for q in qs]
    with ThreadPoolExecutor(8) as pool:
        assert list(pool.map(answer, qs)) == alone
