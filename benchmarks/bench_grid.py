"""Grid A* / JPS per-query time against pyastar2d on the shared Moving AI maps.

    pip install -e '.[bench]'          # adds pyastar2d (C++ core)
    python benchmarks/bench_grid.py [--every 5] [--repeat 3]
    python benchmarks/bench_grid.py --large [--repeat 3]   # issue 22's maps: 4096² random 20 %, 1001² maze

Same scenarios, same process, interleaved query by query. pyastar2d's
8-connected mode cuts corners and prices diagonals at 1, so it solves an
easier problem; its path lengths are scored against the stored optima too.
Prints the median per-query time of each planner and navlab's ratio.
"""

from __future__ import annotations

import argparse
import math
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
    ap.add_argument("--repeat", type=int, default=3, help="runs per query (the fastest counts)")
    ap.add_argument("--large", action="store_true",
                    help="corner-to-corner queries on a 4096x4096 random map (20%% blocked) and a 1001x1001 maze, "
                         "first query on a fresh grid timed apart, bytes per expanded cell")
    args = ap.parse_args()
    if args.large:
        large_maps(args.repeat)
        return
    try:
        import pyastar2d
    except ImportError:
        pyastar2d = None
        print("pyastar2d not installed (pip install -e '.[bench]'): navlab figures only")
    print(f"{'map':<14} {'queries':>7} {'astar ms':>9} {'jps ms':>8} {'pyastar2d ms':>13} "
          f"{'astar/pya':>10} {'pya/jps':>8} {'pya excess':>11}")
    for map_name, scen_name in MAPS:
        grid = load_map(DATA / map_name)
        scenarios = read_scen(DATA / scen_name)[::args.every]
        weights = np.where(grid.blocked, np.inf, 1.0).astype(np.float32)
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


def large_maps(repeat: int) -> None:
    """A* (8-connected, octile, no corner cutting), JPS and 4-connected A*
    against pyastar2d on big maps, corner to corner. The first query on a
    fresh grid (kernels already loaded) is timed apart from repeated ones.
    Bytes per expanded cell: the search state the query touched over the
    cells it expanded, counted two ways: cells written (their 8-byte state,
    4 more for JPS's parent, and the padded grid's byte) and whole 4 KB pages
    of the state array written (what a first query pays to map)."""
    import pyastar2d

    from conditions import load_line, spread

    print(load_line("at start"))
    for kw in ({}, {"algorithm": "jps"}, {"connectivity": 4, "heuristic": "manhattan"}):
        plan(load_map_free(8), (0, 0), (7, 7), **kw)  # kernels loaded before any timing
    print(f"{'map':<16} {'planner':<10} {'first s':>8} {'repeat s':>9} {'range':>12} {'pyastar2d s':>12} "
          f"{'first/pya':>9} {'rep/pya':>8} {'expanded':>9} {'B/exp cells':>11} {'B/exp pages':>11}")
    for name, make in _large_maps():
        grid = make()
        free = np.argwhere(~grid.blocked)
        s, t = tuple(int(v) for v in free[0][::-1]), tuple(int(v) for v in free[-1][::-1])
        weights = np.where(grid.blocked, np.inf, 1.0).astype(np.float32)
        for label, kw, diagonal in (("astar", {}, True), ("jps", {"algorithm": "jps"}, True),
                                    ("astar-4", {"connectivity": 4, "heuristic": "manhattan"}, False)):
            fresh = grid.replace()  # same cells, empty cache: the first query pays for its search state
            t0 = time.perf_counter()
            r = plan(fresh, s, t, **kw)
            first = time.perf_counter() - t0
            reps, pya = [], []
            for _ in range(repeat):  # interleaved with pyastar2d
                t0 = time.perf_counter()
                plan(fresh, s, t, **kw)
                reps.append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                pyastar2d.astar_path(weights, (s[1], s[0]), (t[1], t[0]), allow_diagonal=diagonal)
                pya.append(time.perf_counter() - t0)
            rep, ref = statistics.median(reps), statistics.median(pya)
            cells_b, pages_b = touched_bytes(fresh, label == "jps")
            expanded = max(r.stats["expanded"], 1)
            print(f"{name:<16} {label:<10} {first:>8.3f} {rep:>9.3f} {spread(reps, 3, ' s'):>12} {ref:>12.3f} "
                  f"{first / ref:>9.2f} {rep / ref:>8.2f} {r.stats['expanded']:>9} "
                  f"{cells_b / expanded:>11.1f} {pages_b / expanded:>11.1f}")
    print("pyastar2d's 8-connected mode cuts corners and prices diagonals at 1 (an easier problem than astar's);")
    print("astar-4 and pyastar2d's 4-connected mode solve the same problem. B/expanded: search-state bytes per")
    print("expanded cell: the cells the last query wrote (8 B of state each, +4 for JPS's parent, +1 grid byte),")
    print("and the 4 KB pages of the state array it wrote.")
    print(load_line("at end"))


def touched_bytes(grid, parents: bool):
    """(bytes of the cells, bytes of the 4 KB pages) of search state the
    grid's last query wrote, read from its idle searcher."""
    from navlab.grid.planner import pool_for

    (searcher,) = pool_for(grid, False)._idle
    written = searcher.g != 0
    per_cell = 8 + (4 if parents else 0) + 1
    page = 4096 // searcher.g.itemsize
    pages = np.count_nonzero(np.add.reduceat(written, np.arange(0, written.size, page)))
    return int(np.count_nonzero(written)) * per_cell, pages * 4096


def load_map_free(n: int):
    from navlab.grid import OccupancyGrid

    return OccupancyGrid(np.zeros((n, n), bool))


if __name__ == "__main__":
    main()
