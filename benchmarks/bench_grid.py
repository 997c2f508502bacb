"""Grid A* / JPS per-query time against pyastar2d on the shared Moving AI maps.

    pip install -e '.[bench]'          # adds pyastar2d (C++ core)
    python benchmarks/bench_grid.py [--every 5] [--repeat 3]

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
    args = ap.parse_args()
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


if __name__ == "__main__":
    main()
