"""Hybrid A*: navlab against PythonRobotics' HybridAStar, same map, car and turning radius.

    python benchmarks/bench_hybrid.py [--pythonrobotics PATH] [--repeat 3] [--resolution 1.0]
    python benchmarks/bench_hybrid.py --quick     # PythonRobotics' demo query once, no reference map
    python benchmarks/bench_hybrid.py --reference-only   # navlab alone on the 384 x 384 map, no checkout needed
    python benchmarks/bench_hybrid.py --analytic-max 12 --analytic-ratio 3.5   # Smac's analytic schedule

PythonRobotics (github.com/AtsushiSakai/PythonRobotics) is imported from a
checkout: ``--pythonrobotics``, else $PYTHONROBOTICS, else ./PythonRobotics
(it needs PathPlanning/HybridAStar, PathPlanning/ReedsSheppPath and utils/).
Its map, start and goal are the ones its own ``main()`` builds (a 60 x 60 m
map of obstacle points at 1 m spacing); three more queries run on that map.
Its car (car.py: WB, W, LF, LB, MAX_STEER; the pose is the rear-axle centre)
gives navlab's footprint, the rectangle from -LB to LF by W, and turning
radius WB / tan(MAX_STEER); both planners drive forward and in reverse.

navlab's map blocks every cell that holds an obstacle point, with the grid
shifted by half a cell so each point sits at its cell's centre: a footprint
that contains a point overlaps that point's cell, so navlab is at least as
conservative as PythonRobotics' check (printed below the table).

Queries are interleaved planner by planner, each run ``--repeat`` times; the
medians are printed. navlab's first call loads its compiled kernels and is
timed apart; its per-start-heading footprint lattice is cleared before every
timed call, so each run pays for it as a query with a new start heading does
(the "cached ms" column: the same query again with the lattice kept).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from navlab.grid.hybrid_astar import plan_hybrid
from navlab.grid.occupancy import OccupancyGrid
from navlab.result import Status
from navlab.sampling.footprint_lattice import lattice_for

from conditions import load_line, spread

EXTRA_QUERIES = [  # (name, start, goal) on PythonRobotics' demo map, poses (x [m], y [m], heading [deg])
    ("left to bottom", (10.0, 45.0, 0.0), (30.0, 5.0, 0.0)),
    ("middle to right", (30.0, 50.0, -90.0), (50.0, 10.0, 90.0)),
    ("turn around", (10.0, 10.0, 90.0), (10.0, 30.0, -90.0)),
]


class _Captured(Exception):
    """Stops PythonRobotics' ``main()`` once it has handed its problem to the planner."""


def load_pythonrobotics(root: Path):
    """Import PythonRobotics' ``hybrid_a_star`` and ``car`` modules from a checkout, animation off."""
    package = root / "PathPlanning" / "HybridAStar"
    if not (package / "hybrid_a_star.py").is_file():
        sys.exit(f"no PathPlanning/HybridAStar/hybrid_a_star.py under {root}: give --pythonrobotics PATH "
                 "(or set PYTHONROBOTICS) to a PythonRobotics checkout")
    import matplotlib

    matplotlib.use("Agg")
    sys.path[:0] = [str(package), str(root / "PathPlanning"), str(root)]
    module = importlib.import_module("hybrid_a_star")
    module.show_animation = False
    return module, importlib.import_module("car")


def demo_problem(module):
    """PythonRobotics' own demo: obstacle points ox, oy, start and goal, as its ``main()``
    builds them (its planner is swapped for a stand-in that records the arguments)."""
    captured = {}

    def record(start, goal, ox, oy, *_):
        captured.update(start=tuple(start), goal=tuple(goal), ox=list(ox), oy=list(oy))
        raise _Captured

    planner = module.hybrid_a_star_planning
    module.hybrid_a_star_planning = record
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            module.main()
    except _Captured:
        pass
    finally:
        module.hybrid_a_star_planning = planner
    return captured["ox"], captured["oy"], captured["start"], captured["goal"]


def points_grid(ox, oy, res: float) -> OccupancyGrid:
    """An occupancy grid blocking the cell of every obstacle point; points sit at cell centres."""
    x0, y0 = min(ox), min(oy)
    i = np.round((np.asarray(ox) - x0) / res).astype(int)
    j = np.round((np.asarray(oy) - y0) / res).astype(int)
    blocked = np.zeros((j.max() + 1, i.max() + 1), dtype=bool)
    blocked[j, i] = True
    return OccupancyGrid(blocked, resolution=res, origin=(x0 - res / 2, y0 - res / 2, 0.0))


def run_navlab(grid, start, goal, radius, footprint, options, cleared: bool = True):
    """One navlab query, from a cleared lattice cache unless ``cleared`` is false: (wall time [s], Result)."""
    if cleared:
        lattice_for.cache_clear()
    t0 = time.perf_counter()
    result = plan_hybrid(grid, start, goal, radius, motion="reeds_shepp", footprint=footprint, **options)
    return time.perf_counter() - t0, result


def run_pythonrobotics(module, ox, oy, start, goal):
    """One PythonRobotics query (its prints discarded): (wall time [s], path length [m], or nan if none)."""
    with contextlib.redirect_stdout(io.StringIO()):
        t0 = time.perf_counter()
        path = module.hybrid_a_star_planning(list(start), list(goal), ox, oy, module.XY_GRID_RESOLUTION,
                                             module.YAW_GRID_RESOLUTION)
        elapsed = time.perf_counter() - t0
    if len(path.x_list) < 2:
        return elapsed, math.nan
    return elapsed, float(np.hypot(np.diff(path.x_list), np.diff(path.y_list)).sum())


def compare(module, car, res: float, repeat: int, quick: bool, options) -> None:
    """The side-by-side table on PythonRobotics' demo map."""
    ox, oy, start, goal = demo_problem(module)
    grid = points_grid(ox, oy, res)
    radius = car.WB / math.tan(car.MAX_STEER)
    footprint = [[-car.LB, -car.W / 2], [car.LF, -car.W / 2], [car.LF, car.W / 2], [-car.LB, car.W / 2]]
    queries = [("PythonRobotics demo", start, goal)]
    if not quick:
        queries += [(name, _radians(s), _radians(g)) for name, s, g in EXTRA_QUERIES]
    print(f"map: PythonRobotics demo, {len(ox)} obstacle points; navlab grid {grid.width} x {grid.height} cells "
          f"at {res:g} m; car {car.LB + car.LF:g} x {car.W:g} m, turning radius {radius:.3f} m, reeds_shepp")
    print(f"navlab options: {_described(options)}")
    warm, _ = run_navlab(grid, start, goal, radius, footprint, options)
    print(f"navlab first call (loads compiled kernels): {warm:.3f} s, not counted below")
    print(f"{'query':<20} {'navlab ms':>9} {'range':>16} {'cached ms':>9} {'PyRob s':>8} {'range':>14} "
          f"{'PyRob/nav':>9} {'nav m':>7} {'PyRob m':>8} {'nav<=PyRob':>10} {'expansions':>10}")
    for name, s, g in queries:
        nav_times, cached_times, pr_times = [], [], []
        for _ in range(repeat):
            elapsed, result = run_navlab(grid, s, g, radius, footprint, options)
            nav_times.append(elapsed)
            elapsed, result = run_navlab(grid, s, g, radius, footprint, options, cleared=False)
            cached_times.append(elapsed)
            elapsed, pr_length = run_pythonrobotics(module, ox, oy, s, g)
            pr_times.append(elapsed)
        nav, ref = statistics.median(nav_times), statistics.median(pr_times)
        found = result.status == Status.EXACT
        shorter = "-" if not found or math.isnan(pr_length) else "yes" if result.cost <= pr_length + 0.01 else "no"
        print(f"{name:<20} {1000 * nav:>9.1f} {spread([1000 * t for t in nav_times], 1, ' ms'):>16} "
              f"{1000 * statistics.median(cached_times):>9.1f} {ref:>8.2f} {spread(pr_times, 2, ' s'):>14} {ref / nav:>8.1f}x "
              f"{f'{result.cost:.2f}' if found else 'failed':>7} {pr_length:>8.2f} {shorter:>10} "
              f"{result.stats['expansions']:>10}")
    bubble = math.hypot((car.LF + car.LB) / 2, car.W / 2)
    margin = math.sqrt(2) * res + res / 4 + math.hypot(car.LF, car.W / 2) * math.sin(math.pi / 72)
    notes = (
        f"PyRob/nav: median PythonRobotics time / median navlab time (x faster), {repeat} run(s) per query, "
        "interleaved; navlab ms from a cleared footprint lattice (a robot's first query at that start heading), "
        "cached ms right after with it kept (the map's distance tables are cached by content in both); lengths in metres driven (PythonRobotics': the polyline of its x_list, y_list, whose 0.1 m "
        "chords under-measure its arcs a little, so nav<=PyRob allows 1 cm).",
        f"PythonRobotics' collision check: the obstacle points within {bubble:.2f} m of the car's centre "
        "(kd-tree bubble), then a pose is rejected if its rectangle contains one; poses 0.1 m apart; the points "
        "are the whole map.",
        f"navlab's: no overlap with a blocked cell, so {res / 2:g} m around each point (its cell), plus its "
        f"certified margin up to {margin:.2f} m (sqrt(2) res + res/4 + R sin 2.5 deg): up to "
        f"{res / 2 + margin:.2f} m more clearance than PythonRobotics.",
        f"Search: PythonRobotics {module.XY_GRID_RESOLUTION:g} m / {math.degrees(module.YAW_GRID_RESOLUTION):g} "
        f"deg states, {module.XY_GRID_RESOLUTION * 1.5:g} m arcs, {module.N_STEER + 1} steering values, "
        f"heuristic x{module.H_COST:g}, switch-back cost {module.SB_COST:g};",
        f"navlab {res:g} m / 5 deg states (72 bins), three primitives per direction, admissible heuristic, "
        "Reeds-Shepp shortcut smoothing.",
    )
    for note in notes:
        print(note)


def _radians(pose):
    return pose[0], pose[1], math.radians(pose[2])


def _described(options) -> str:
    return ", ".join(f"{k}={v}" for k, v in options.items()) or "defaults"


def reference_map(options, runs: int = 5) -> None:
    """navlab alone on a 384 x 384 map at 0.05 m (Nav2 Smac's README quotes 2-20 ms for such maps, 72 bins).

    Each run is timed twice, motions interleaved: from a cleared footprint
    lattice (a query with a new start heading) and again with it cached.
    ``solves`` counts the heuristic values the search's lazy queue computed (Reeds–Shepp motion;
    Dubins keys are computed as children are queued, so it is 0 there).
    """
    res, n = 0.05, 384
    blocked = np.zeros((n, n), dtype=bool)
    for x0, y0, x1, y1 in ((6.0, 0.0, 6.2, 12.0), (12.0, 7.0, 12.2, 19.2), (6.0, 15.0, 9.0, 15.2)):  # walls [m]
        blocked[round(y0 / res):round(y1 / res), round(x0 / res):round(x1 / res)] = True
    grid = OccupancyGrid(blocked, resolution=res)
    footprint = [[-0.25, -0.2], [0.25, -0.2], [0.25, 0.2], [-0.25, 0.2]]
    start, goal = (2.0, 2.0, 0.0), (16.0, 8.0, math.pi / 2)
    print(f"reference: {n} x {n} cells ({n * n} cells) at {res:g} m, three walls, robot 0.5 x 0.4 m, turning "
          f"radius 0.4 m, 72 bins, start to goal {math.hypot(goal[0] - start[0], goal[1] - start[1]):.1f} m; "
          f"options: {_described(options)}")
    motions = ("reeds_shepp", "dubins")
    for motion in motions:  # loads the compiled kernels
        plan_hybrid(grid, start, goal, 0.4, motion=motion, footprint=footprint, **options)
    cold = {m: [] for m in motions}
    warm = {m: [] for m in motions}
    results = {}
    for _ in range(runs):
        for motion in motions:
            lattice_for.cache_clear()
            for times in (cold[motion], warm[motion]):
                t0 = time.perf_counter()
                results[motion] = plan_hybrid(grid, start, goal, 0.4, motion=motion, footprint=footprint, **options)
                times.append(time.perf_counter() - t0)
    print(f"{'motion':<12} {'median ms':>9} {'range':>16} {'cached ms':>9} {'range':>16} {'length m':>9} "
          f"{'expansions':>10} {'solves':>7}")
    for motion in motions:
        result = results[motion]
        print(f"{motion:<12} {1000 * statistics.median(cold[motion]):>9.1f} "
              f"{spread([1000 * t for t in cold[motion]], 1, ' ms'):>16} "
              f"{1000 * statistics.median(warm[motion]):>9.1f} "
              f"{spread([1000 * t for t in warm[motion]], 1, ' ms'):>16} "
              f"{result.cost:>9.2f} {result.stats['expansions']:>10} {result.stats['heuristics_solved']:>7}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pythonrobotics", type=Path,
                    default=Path(os.environ.get("PYTHONROBOTICS", "PythonRobotics")),
                    help="PythonRobotics checkout (default: $PYTHONROBOTICS, else ./PythonRobotics)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per query and planner (the median counts)")
    ap.add_argument("--resolution", type=float, default=1.0, choices=(0.25, 0.5, 1.0),
                    help="navlab's cell size [m] (PythonRobotics' points are 1 m apart)")
    ap.add_argument("--quick", action="store_true", help="PythonRobotics' demo query once, no reference map")
    ap.add_argument("--reference-only", action="store_true",
                    help="only navlab on the 384 x 384 reference map (no PythonRobotics checkout needed)")
    ap.add_argument("--analytic-max", type=float, metavar="M",
                    help="navlab's analytic_expansion_max_length [m] (default: the planner's, max(3 m, 3 turning radii))")
    ap.add_argument("--analytic-ratio", type=float, metavar="R",
                    help="navlab's analytic_expansion_ratio (Smac's schedule; default: try at every expansion)")
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error("--repeat must be at least 1")
    options = {}
    if args.analytic_max is not None:
        options["analytic_expansion_max_length"] = args.analytic_max
    if args.analytic_ratio is not None:
        options["analytic_expansion_ratio"] = args.analytic_ratio
    if args.reference_only:
        print(load_line("at start"))
        reference_map(options)
        print(load_line("at end"))
        return
    module, car = load_pythonrobotics(args.pythonrobotics.resolve())
    print(load_line("at start"))
    print(f"PythonRobotics: {args.pythonrobotics.resolve()}")
    compare(module, car, args.resolution, 1 if args.quick else args.repeat, args.quick, options)
    if not args.quick:
        print()
        reference_map(options)
    print(load_line("at end"))


if __name__ == "__main__":
    main()
