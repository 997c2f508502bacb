"""Grid A* / JPS per-query time against pyastar2d on the shared Moving AI maps.

    pip install -e '.[bench]'          # adds pyastar2d (C++ core)
    python benchmarks/bench_grid.py [--every 5] [--repeat 3]
    python benchmarks/bench_grid.py --large [--repeat 3]   # issue 22's maps: 4096² random 20 %, 1001² maze
    python benchmarks/bench_grid.py --large --scipy        # and Dijkstra against scipy's on them
    python benchmarks/bench_grid.py --large --bound        # could a bidirectional search expand fewer cells?
    python benchmarks/bench_grid.py --threads [--repeat 3] # random4096 queries on 1 and on 2 threads at once
    python benchmarks/bench_grid.py --alternate 21         # random4096 one call at a time: first query vs pyastar2d

Same scenarios, same process, interleaved query by query. pyastar2d's
8-connected mode cuts corners and prices diagonals at 1, so it solves an
easier problem; its path lengths are scored against the stored optima too.
Prints the median per-query time of each planner and navlab's ratio.
"""

from __future__ import annotations

import argparse
import math
import resource
import statistics
import time
from pathlib import Path

import numpy as np

from navlab.grid import load_map, plan, read_scen

DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "movingai"
MAPS = [("den312d.map", "den312d.map.scen"), ("Berlin_1_256.map", "Berlin_1_256.map.scen"),
        ("maze512-32-9.map", "maze512-32-9.map.scen")]
ANCHORS_MS = {"den312d": 0.05, "Berlin_1_256": 0.35, "maze512-32-9": 12.3}  # issue 3, measured on this machine


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--every", type=int, default=5, help="use every k-th scenario")
    ap.add_argument("--repeat", type=int, default=3,
                    help="runs per query: the fastest counts (default mode); rounds, of which medians "
                         "(--large, --threads)")
    ap.add_argument("--large", action="store_true",
                    help="corner-to-corner queries on a 4096x4096 random map (20%% blocked) and a 1001x1001 maze, "
                         "first query on a fresh grid timed apart, bytes per expanded cell")
    ap.add_argument("--scipy", action="store_true",
                    help="with --large: navlab's Dijkstra against scipy's on the explicit graph "
                         "(builds it first: about 35 s and 3.3 GB on the 4096x4096 map)")
    ap.add_argument("--bound", action="store_true",
                    help="with --large: the fewest cells any front-to-end bidirectional search must expand on "
                         "each map (from two Dijkstra fields; no timing; peaks at about 2 GB on the 4096x4096 map)")
    ap.add_argument("--alternate", type=int, metavar="PAIRS",
                    help="the 4096x4096 random map's A* query one call at a time: a fresh grid's first query and "
                         "pyastar2d's call, alternating, PAIRS times; medians, the fastest, pairs at 0.5 or under")
    ap.add_argument("--threads", action="store_true",
                    help="the 4096x4096 random map's corner-to-corner A* query alone, then two at once on two "
                         "threads (each on its own grid, and both on one grid): do the searches run in parallel?")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    if args.every < 1:
        ap.error("--every must be at least 1")
    if args.threads and (args.large or args.scipy or args.bound):
        ap.error("--threads runs on its own: not with --large, --scipy or --bound")
    if args.alternate is not None:
        if args.alternate < 1:
            ap.error("--alternate must be at least 1")
        if args.threads or args.large or args.scipy or args.bound:
            ap.error("--alternate runs on its own: not with --threads, --large, --scipy or --bound")
        if not has_pyastar2d():
            ap.error(f"--alternate times pyastar2d, which is not installed: {PYASTAR2D_INSTALL}")
        alternate(args.alternate)
        return
    for flag in ("scipy", "bound"):
        if getattr(args, flag) and not args.large:
            ap.error(f"--{flag} goes with --large")
    if args.threads:
        threads(args.repeat)
        return
    if args.large and args.bound:
        for name, make in _large_maps():
            bidirectional_bound(name, make())
        return
    if args.large:
        if not has_pyastar2d():
            ap.error(f"--large times pyastar2d, which is not installed: {PYASTAR2D_INSTALL} (--bound needs "
                     "no pyastar2d)")
        large_maps(args.repeat, args.scipy)
        return
    try:
        import pyastar2d
    except ImportError:
        pyastar2d = None
        print(f"pyastar2d not installed ({PYASTAR2D_INSTALL}): navlab figures only")
    print(f"{'map':<14} {'queries':>7} {'astar ms':>9} {'jps ms':>8} {'pyastar2d ms':>13} "
          f"{'astar/pya':>10} {'pya/jps':>8} {'pya excess':>11}")
    for map_name, scen_name in MAPS:
        grid = load_map(DATA / map_name)
        scenarios = read_scen(DATA / scen_name)[::args.every]
        weights = pyastar2d_weights(grid)
        times = {"astar": [], "jps": [], "pya": []}
        excess = []
        for algo in ("astar", "jps"):
            plan(grid, scenarios[0].start, scenarios[0].goal, algorithm=algo)  # load kernels
        for sc in scenarios:
            for algo in ("astar", "jps"):
                best = math.inf
                for _ in range(args.repeat):
                    t0 = time.perf_counter()
                    plan(grid, sc.start, sc.goal, algorithm=algo)
                    best = min(best, time.perf_counter() - t0)
                times[algo].append(best)
            if pyastar2d is not None:
                best = math.inf
                for _ in range(args.repeat):
                    t0 = time.perf_counter()
                    path = pyastar2d.astar_path(weights, (sc.start[1], sc.start[0]), (sc.goal[1], sc.goal[0]),
                                                allow_diagonal=True)
                    best = min(best, time.perf_counter() - t0)
                times["pya"].append(best)
                steps = np.abs(np.diff(path, axis=0))
                length = float(np.sum(np.where(steps.sum(axis=1) == 2, math.sqrt(2), 1.0)))
                if sc.optimal > 0:
                    excess.append(length / sc.optimal - 1)
        med = {k: statistics.median(v) * 1000 if v else float("nan") for k, v in times.items()}
        print(f"{grid.name:<14} {len(scenarios):>7} {med['astar']:>9.3f} {med['jps']:>8.3f} {med['pya']:>13.3f} "
              f"{med['astar'] / med['pya']:>10.2f} {med['pya'] / med['jps']:>8.2f} "
              f"{100 * statistics.mean(excess) if excess else float('nan'):>10.1f}%")
    print("astar/pya < 1 means navlab's exact A* is faster; pya/jps is JPS's speed-up over pyastar2d;")
    print("'pya excess' is how much longer pyastar2d's corner-cutting paths are than the true optimum.")


def _large_maps():
    from navlab.grid import OccupancyGrid
    from navlab.grid.maze import make_maze

    rng = np.random.default_rng(0)
    blocked = rng.random((4096, 4096)) < 0.2
    blocked[0, 0] = blocked[-1, -1] = False
    yield "random4096-20%", lambda: OccupancyGrid(blocked.copy(), name="random4096")
    yield "maze1001", lambda: make_maze(100, 100, seed=1, cell_size=0.5, wall=0.05, resolution=0.05)


def corners(free: np.ndarray):
    """The first and last free cells (x, y) of ``np.argwhere(~blocked)``: the corner-to-corner query."""
    return tuple(int(v) for v in free[0][::-1]), tuple(int(v) for v in free[-1][::-1])


def faulted(fn):
    """(minor page faults, system CPU seconds) this thread took in one call of ``fn``: what a first
    query pays to map fresh memory (pyastar2d's arrays come on 4 KB pages, navlab's state on huge
    ones), the part of a time that moves most from host to host."""
    r0 = resource.getrusage(resource.RUSAGE_THREAD)
    fn()
    r1 = resource.getrusage(resource.RUSAGE_THREAD)
    return r1.ru_minflt - r0.ru_minflt, r1.ru_stime - r0.ru_stime


PYASTAR2D_INSTALL = "pip install -e '.[bench]'"


def has_pyastar2d() -> bool:
    """Whether the anchor pyastar2d can be imported (the ``bench`` extra)."""
    import importlib.util

    return importlib.util.find_spec("pyastar2d") is not None


def pyastar2d_weights(grid) -> np.ndarray:
    """pyastar2d's cost array for ``grid``: 1 on a free cell, infinite on a blocked one (float32)."""
    return np.where(grid.blocked, np.inf, 1.0).astype(np.float32)


def pyastar2d_query(weights: np.ndarray, start, goal, diagonal: bool):
    """pyastar2d's call for the query from cell ``start`` to ``goal`` (x, y; it takes (row, column)),
    as a function of no arguments to time."""
    import pyastar2d

    return lambda: pyastar2d.astar_path(weights, (start[1], start[0]), (goal[1], goal[0]), allow_diagonal=diagonal)


def timed(fn):
    """(wall seconds, this thread's CPU seconds, result) of one call: on a
    shared machine the CPU time is what other jobs' load inflates least."""
    w0, c0 = time.perf_counter(), time.thread_time()
    out = fn()
    return time.perf_counter() - w0, time.thread_time() - c0, out


def large_maps(repeat: int, with_scipy: bool) -> None:
    """A* (8-connected, octile, no corner cutting), JPS and 4-connected A*
    against pyastar2d on big maps, corner to corner. The first query on a
    fresh grid (kernels already loaded; a new grid object each time, so the
    query builds its tables and search state) is timed apart from repeated
    queries on one grid; each round runs a fresh-grid query, a repeat and
    pyastar2d's call (which keeps nothing between calls), and the table
    gives medians over ``repeat`` rounds, in wall and CPU time (``cpu``
    ratios). Before the rounds, each tool's query runs once untimed on its
    own fresh grid: on this VM a process's first large allocation costs
    0.1-0.4 s more than any later one (the host backs the pages then; a
    process's first 134 MB array, whoever allocates it), which would land on
    whichever tool runs first; that figure is printed apart. Bytes per expanded
    cell: the search state the query touched over the cells it expanded,
    counted two ways: cells written (their 4-byte state and the
    legal-move byte) and whole 4 KB pages of the state
    array written (what a first query pays to map); below each row, the minor page faults and system
    time of one more first query and one more pyastar2d call (:func:`faulted`). With ``with_scipy``,
    navlab's Dijkstra against scipy's on the explicit graph (built apart,
    untimed; scipy has no goal, so it settles every reachable cell)."""
    from conditions import load_line, spread

    print(load_line("at start"))
    for kw in ({}, {"algorithm": "jps"}, {"algorithm": "dijkstra"}, {"connectivity": 4, "heuristic": "manhattan"}):
        plan(load_map_free(8), (0, 0), (7, 7), **kw)  # kernels loaded before any timing
    print(f"{'map':<16} {'planner':<10} {'first s':>8} {'range':>12} {'repeat s':>9} {'range':>12} "
          f"{'pyastar2d s':>12} {'range':>12} "
          f"{'first/pya':>9} {'rep/pya':>8} {'cpu f/pya':>9} {'cpu r/pya':>9} {'expanded':>9} "
          f"{'B/exp cells':>11} {'B/exp pages':>11}")
    process_warm = False
    for name, make in _large_maps():
        grid = make()
        free = np.argwhere(~grid.blocked)
        s, t = corners(free)
        weights = pyastar2d_weights(grid)
        for label, kw, diagonal in (("astar", {}, True), ("jps", {"algorithm": "jps"}, True),
                                    ("astar-4", {"connectivity": 4, "heuristic": "manhattan"}, False)):
            pya_call = pyastar2d_query(weights, s, t, diagonal)
            if not process_warm:  # the process's first large allocation, apart from the table (see above)
                once, _, _ = timed(lambda: plan(grid.replace(), s, t, **kw))
                pya_call()
                print(f"(the process's first {name} {label} query, untimed in the table: {once:.3f} s)")
                process_warm = True
            firsts, runs, pya = [], [], []
            for k in range(repeat):  # interleaved: a fresh grid's first query and a repeat, and pyastar2d
                if k % 2:  # before navlab in every other round, so neither side always follows the other
                    pya.append(timed(pya_call)[:2])
                fresh = grid.replace()  # same cells, empty cache: the first query pays for its tables and state
                wall, cpu, r = timed(lambda: plan(fresh, s, t, **kw))
                firsts.append((wall, cpu))
                runs.append(timed(lambda: plan(fresh, s, t, **kw))[:2])
                if not k % 2:
                    pya.append(timed(pya_call)[:2])
            first, first_cpu = statistics.median(w for w, _ in firsts), statistics.median(c for _, c in firsts)
            reps = [w for w, _ in runs]
            rep, rep_cpu = statistics.median(reps), statistics.median(c for _, c in runs)
            ref, ref_cpu = statistics.median(w for w, _ in pya), statistics.median(c for _, c in pya)
            another = grid.replace()  # (made outside: the copy of the cells is not the query's)
            page_faults = [faulted(lambda: plan(another, s, t, **kw)), faulted(pya_call)]
            cells_b, pages_b = touched_bytes(fresh)
            expanded = max(r.stats["expanded"], 1)
            print(f"{name:<16} {label:<10} {first:>8.3f} {spread([w for w, _ in firsts], 3, ' s'):>12} "
                  f"{rep:>9.3f} {spread(reps, 3, ' s'):>12} {ref:>12.3f} {spread([w for w, _ in pya], 3, ' s'):>12} "
                  f"{first / ref:>9.2f} {rep / ref:>8.2f} {first_cpu / ref_cpu:>9.2f} {rep_cpu / ref_cpu:>9.2f} "
                  f"{r.stats['expanded']:>9} {cells_b / expanded:>11.1f} {pages_b / expanded:>11.1f}")
            print(f"{'':<16} {'':<10} page faults, one call each: navlab first query {page_faults[0][0]} "
                  f"({page_faults[0][1]:.3f} s system), pyastar2d {page_faults[1][0]} ({page_faults[1][1]:.3f} s)")
        if with_scipy:
            scipy_dijkstra(name, grid, s, t, repeat)
    print("pyastar2d's 8-connected mode cuts corners and prices diagonals at 1 (an easier problem than astar's);")
    print("astar-4 and pyastar2d's 4-connected mode solve the same problem. 'cpu' ratios: the same medians in")
    print("CPU time. B/expanded: search-state bytes per expanded cell: the cells the last query wrote (4 B of")
    print("state each, +1 legal-move byte), and the 4 KB pages of the state array it wrote.")
    print(load_line("at end"))


def threads(repeat: int) -> None:
    """Wall time of random4096's corner-to-corner A* query on one thread, and of two such queries
    started together on two threads, on two grids and on one grid (each thread leases its own
    searcher); medians over ``repeat`` rounds. With the search releasing the GIL, two queries take
    about the time of one on a machine with two idle cores; holding it, twice that."""
    from concurrent.futures import ThreadPoolExecutor

    from conditions import load_line, spread

    from navlab.grid.planner import pool_for

    print(load_line("at start"))
    name, make = next(iter(_large_maps()))
    grids = [make(), make()]
    free = np.argwhere(~grids[0].blocked)
    s, t = corners(free)
    layouts = {"one query": [grids[0]], "two threads, two grids": grids,
               "two threads, one grid": [grids[0], grids[0]]}
    for grid in grids:  # every grid's tables and searchers built before timing
        plan(grid, s, t)
    with pool_for(grids[0], False).lease():  # one searcher kept busy: this query builds the grid's second
        plan(grids[0], s, t)
    with ThreadPoolExecutor(2) as pool:
        times = {label: [] for label in layouts}
        for _ in range(repeat):
            for label, batch in layouts.items():
                wall = time.perf_counter()
                results = list(pool.map(lambda g: plan(g, s, t), batch))
                times[label].append(time.perf_counter() - wall)
                assert all(r.cost == results[0].cost for r in results)
    alone = statistics.median(times["one query"])
    for label, walls in times.items():
        print(f"{name} astar, {label:<24} {statistics.median(walls):.3f} s wall ({spread(walls, 3, ' s')}; "
              f"{statistics.median(walls) / alone:.2f}x one query)")
    print(load_line("at end"))


def alternate(pairs: int) -> None:
    """Issue 22's A* query on the 4096x4096 random map one call at a time: a fresh grid's first query
    (the grid copied outside the timing) and pyastar2d's call, alternating, which goes first swapped
    every pair. Printed: medians and minima of each, their ratios, and how many pairs have navlab at
    0.5 of pyastar2d's time or less."""
    from conditions import load_line

    print(load_line("at start"))
    name, make = next(iter(_large_maps()))
    grid = make()
    s, t = corners(np.argwhere(~grid.blocked))
    pya_call = pyastar2d_query(pyastar2d_weights(grid), s, t, True)
    plan(grid.replace(), s, t)  # the kernels loaded, and each tool's first large allocation in the process
    pya_call()
    navlab, pya = [], []
    for k in range(pairs):
        fresh = grid.replace()
        calls = [(navlab, lambda: plan(fresh, s, t)), (pya, pya_call)]
        for times, call in calls if k % 2 else calls[::-1]:
            times.append(timed(call)[0])
    nav_med, pya_med = statistics.median(navlab), statistics.median(pya)
    under = sum(a <= 0.5 * b for a, b in zip(navlab, pya))
    print(f"{name} astar, one call at a time, {pairs} pairs: navlab's first query {nav_med:.3f} s "
          f"(fastest {min(navlab):.3f}), pyastar2d {pya_med:.3f} s (fastest {min(pya):.3f}); "
          f"ratio of medians {nav_med / pya_med:.3f}, of the fastest {min(navlab) / min(pya):.3f}; "
          f"pairs at 0.5 or under: {under} of {pairs}")
    print(load_line("at end"))


def grid_graph(blocked: np.ndarray):
    """The explicit graph of 8-connected moves without corner cutting (CSR,
    cell y * W + x), built with array operations."""
    from scipy.sparse import csr_matrix

    h, w = blocked.shape
    free = ~blocked
    index = np.arange(h * w, dtype=np.int32).reshape(h, w)
    rows, cols, costs = [], [], []
    for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1)):
        ys, yd = (slice(0, h - dy), slice(dy, h)) if dy >= 0 else (slice(-dy, h), slice(0, h + dy))
        xs, xd = (slice(0, w - dx), slice(dx, w)) if dx >= 0 else (slice(-dx, w), slice(0, w + dx))
        ok = free[ys, xs] & free[yd, xd]
        if dx and dy:  # both cells beside a diagonal move free
            ok &= free[ys, xd] & free[yd, xs]
        rows.append(index[ys, xs][ok])
        cols.append(index[yd, xd][ok])
        costs.append(np.full(rows[-1].size, math.sqrt(2) if dx and dy else 1.0))
    return csr_matrix((np.concatenate(costs), (np.concatenate(rows), np.concatenate(cols))), shape=(h * w, h * w))


def scipy_dijkstra(name: str, grid, s, t, repeat: int) -> None:
    """navlab's Dijkstra against scipy.sparse.csgraph.dijkstra from the same
    start (medians, interleaved), with both distances to the goal."""
    from scipy.sparse.csgraph import dijkstra

    graph = grid_graph(grid.blocked)
    source, target = s[1] * grid.width + s[0], t[1] * grid.width + t[0]
    ours, theirs = [], []
    for _ in range(repeat):
        wall, cpu, r = timed(lambda: plan(grid, s, t, algorithm="dijkstra"))
        ours.append((wall, cpu))
        wall, cpu, dist = timed(lambda: dijkstra(graph, indices=source))
        theirs.append((wall, cpu))
    med = [statistics.median(v) for v in zip(*ours)] + [statistics.median(v) for v in zip(*theirs)]
    print(f"{name:<16} {'dijkstra':<10} {'':>8} {med[0]:>9.3f} {'scipy':>12} {med[2]:>12.3f} {'':>9} "
          f"{med[0] / med[2]:>8.2f} {'':>9} {med[1] / med[3]:>9.2f} {r.stats['expanded']:>9}  "
          f"cost {r.stats['cost_cells']:.9f} scipy {dist[target]:.9f}")


def bidirectional_bound(name: str, grid) -> None:
    """The fewest expansions any front-to-end bidirectional search can make,
    against forward A*'s, on the corner-to-corner query.

    A pair (u forward, v backward) must be expanded on one side when
    max(f_F(u), f_B(v), g_F(u) + g_B(v) + eps) < C* (eps = 1, the cheapest
    move), and the fewest expansions is the minimum vertex cover of those
    pairs (Eckerle et al., ICAPS 2017; Shaham et al., SoCS 2017). The pair condition is a
    threshold on g_F + g_B, so the cover is the k cells of smallest g_F plus
    every backward cell paired with the next one, minimised over k. Exact
    g_F and g_B come from two Dijkstra searches, which close every cell with
    g < C*. Also printed: how many cells MM (Holte et al. 2016), which
    expands u while max(f, 2 g) < C*, would expand.
    """
    from navlab.grid import kernels as K
    from navlab.grid.planner import SearcherPool

    free = np.argwhere(~grid.blocked)
    s, t = corners(free)
    pool = SearcherPool(grid.blocked, grid.unknown)
    fields = []
    for a, b in ((s, t), (t, s)):
        with pool.lease() as searcher:
            searcher.search("dijkstra", a, b, 8, K.H_ZERO, 1.0)
            fields.append(K.state_costs(searcher.written_rows().ravel()))  # (closed, exact distances)
    with pool.lease() as searcher:
        expanded = searcher.search("astar", s, t, 8, K.H_OCTILE, 1.0)[1]
    stride = grid.width + 2
    xs, ys = np.divmod(np.arange(fields[0][0].size), stride)[::-1]

    def octile(x, y):
        dx, dy = np.abs(xs - 1 - x), np.abs(ys - 1 - y)
        return np.maximum(dx, dy) + (math.sqrt(2) - 1) * np.minimum(dx, dy)

    (closed_f, g_f), (closed_b, g_b) = fields
    cost = g_f[(t[1] + 1) * stride + t[0] + 1]
    tie = 1e-9
    fwd = closed_f & (g_f + octile(*t) < cost - tie)
    bwd = closed_b & (g_b + octile(*s) < cost - tie)
    gf, gb = np.sort(g_f[fwd]), np.sort(g_b[bwd])
    cover = np.arange(gf.size) + np.searchsorted(gb, cost - tie - 1.0 - gf)
    mm = sum(int(np.count_nonzero(c & (np.maximum(g + octile(*x), 2 * g) < cost - tie)))
             for (c, g), x in zip(fields, (t, s)))
    print(f"{name:<16} C* {cost:.3f}  A* expanded {expanded}  f_F < C*: {gf.size}  f_B < C*: {gb.size}  "
          f"bidirectional at least {min(gf.size, int(cover.min()))}  MM {mm}")


def touched_bytes(grid):
    """(bytes of the cells, bytes of the 4 KB pages) of search state the
    grid's last query wrote, read from its idle searcher."""
    from navlab.grid.planner import pool_for

    (searcher,) = pool_for(grid, False)._idle
    state = searcher.written  # the packed uint32 state of A*, Dijkstra (strip layout) or JPS (rows)
    written = state != 0
    per_cell = state.itemsize + 1  # and the legal-move byte (A* and JPS build no padded copy of the grid)
    page = 4096 // state.itemsize
    pages = np.count_nonzero(np.add.reduceat(written, np.arange(0, written.size, page)))
    return int(np.count_nonzero(written)) * per_cell, pages * 4096


def load_map_free(n: int):
    from navlab.grid import OccupancyGrid

    return OccupancyGrid(np.zeros((n, n), bool))


if __name__ == "__main__":
    main()
