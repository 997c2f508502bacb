"""Hybrid A*: navlab against PythonRobotics' HybridAStar, same map, car and turning radius.

    python benchmarks/bench_hybrid.py [--pythonrobotics PATH] [--repeat 3] [--resolution 1.0]
    python benchmarks/bench_hybrid.py --quick     # PythonRobotics' demo query once, no reference map
    python benchmarks/bench_hybrid.py --reference-only   # navlab alone on the 384 x 384 map, no checkout needed
    python benchmarks/bench_hybrid.py --analytic-max 12 --analytic-ratio 3.5   # Smac's analytic schedule
    python benchmarks/bench_hybrid.py --weight 1.5   # navlab at weight 1.5 (and at PythonRobotics' own 5)
    python benchmarks/bench_hybrid.py --smac-maps    # navlab on five 384 x 384 maps against Smac's README figure
    python benchmarks/bench_hybrid.py --smac-maps --smac-driver build-smac/smac_driver   # and Nav2 Smac itself

PythonRobotics (github.com/AtsushiSakai/PythonRobotics) is imported from a
checkout: ``--pythonrobotics``, else $PYTHONROBOTICS, else ./PythonRobotics
(it needs PathPlanning/HybridAStar, PathPlanning/ReedsSheppPath and utils/).
Its map, start and goal are the ones its own ``main()`` builds (a 60 x 60 m
map of obstacle points at 1 m spacing); three more queries run on that map.
Its car (car.py: WB, W, LF, LB, MAX_STEER; the pose is the rear-axle centre)
gives navlab's footprint, the rectangle from -LB to LF by W, and turning
radius WB / tan(MAX_STEER); both planners drive forward and in reverse.
PythonRobotics weighs its heuristic by its H_COST (5): each query runs navlab
unweighted (or at ``--weight``) and at that same weight (``weight=5``), each
timed right after a PythonRobotics run.

navlab's map blocks every cell that holds an obstacle point, with the grid
shifted by half a cell so each point sits at its cell's centre: a footprint
that contains a point overlaps that point's cell, so navlab is at least as
conservative as PythonRobotics' check (printed below the table).

Queries are interleaved planner by planner, each run ``--repeat`` times; the
medians are printed. navlab's first call loads its compiled kernels and is
timed apart. Its footprint lattice (the primitives' swept cells, built as
searches ask for them) is one per robot, whatever the start heading, and kept
between queries, as the map's tables are: "navlab ms" is a query with the
robot's lattice and Reeds–Shepp distance table kept, right after a
PythonRobotics run (which evicts navlab's code and data from the CPU's
caches); "again ms" the same query at once again (caches warm, as a planner
replanning in a tight loop); "first ms" the query with the lattice and table
cleared (a robot's first query, which builds what it needs).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from navlab.grid.hybrid_astar import _map_tables, plan_hybrid
from navlab.grid.hybrid_certify import first_overlap_exact
from navlab.grid.maze import maze_walls
from navlab.grid.occupancy import OccupancyGrid
from navlab.result import Status
from navlab.grid.hybrid_table import distance_table
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


def forget_robot() -> None:
    """Clear what navlab keeps per robot between queries: its footprint lattice (the primitives' swept
    cells) and its Reeds–Shepp distance table (:mod:`navlab.grid.hybrid_table`), both filled as queries
    need them. The next query is a robot's first."""
    lattice_for.cache_clear()
    distance_table.cache_clear()


def run_navlab(grid, start, goal, radius, footprint, options, cleared: bool = True):
    """One navlab query, from a cleared lattice cache unless ``cleared`` is false: (wall time [s], Result)."""
    if cleared:
        forget_robot()
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
    # navlab's own weight (1 unless --weight), then PythonRobotics' H_COST: the same weighted search as its own
    weights = list(dict.fromkeys([options.get("weight", 1.0), float(module.H_COST)]))
    print(f"navlab options: {_described(options)}; each query at heuristic weight "
          f"{' and '.join(f'{w:g}' for w in weights)} (PythonRobotics' H_COST is {module.H_COST:g})")
    warm, _ = run_navlab(grid, start, goal, radius, footprint, options)
    print(f"navlab first call (loads compiled kernels): {warm:.3f} s, not counted below")
    print(f"{'query':<20} {'weight':>6} {'navlab ms':>9} {'range':>16} {'first ms':>9} {'again ms':>9} {'PyRob s':>8} "
          f"{'range':>14} {'PyRob/nav':>9} {'PyRob/again':>11} {'nav m':>7} {'PyRob m':>8} {'nav<=PyRob':>10} "
          f"{'expansions':>10}")
    for name, s, g in queries:
        rows = {w: ([], [], []) for w in weights}  # navlab after PythonRobotics, again, first
        pr_times = []
        results = {}

        def keep_robot():
            """Each weight's query once, untimed: the lattice and table then hold what its kept runs read."""
            for w in weights:
                results[w] = run_navlab(grid, s, g, radius, footprint, {**options, "weight": w}, cleared=False)[1]

        keep_robot()
        for _ in range(repeat):  # each weight's kept run right after a PythonRobotics one, then at once again
            for w in weights:
                elapsed, pr_length = run_pythonrobotics(module, ox, oy, s, g)
                pr_times.append(elapsed)
                for times in rows[w][:2]:
                    times.append(run_navlab(grid, s, g, radius, footprint, {**options, "weight": w},
                                            cleared=False)[0])
            for w in weights:  # a robot's first query: lattice and table cleared
                rows[w][2].append(run_navlab(grid, s, g, radius, footprint, {**options, "weight": w})[0])
            keep_robot()  # (a cleared run keeps only its own weight's entries)
        ref = statistics.median(pr_times)
        for w in weights:
            nav_times, again_times, first_times = rows[w]
            result = results[w]
            nav, again = statistics.median(nav_times), statistics.median(again_times)
            found = result.status == Status.EXACT
            shorter = "-" if not found or math.isnan(pr_length) else "yes" if result.cost <= pr_length + 0.01 \
                else "no"
            print(f"{name:<20} {w:>6g} {1000 * nav:>9.2f} {spread([1000 * t for t in nav_times], 2, ' ms'):>16} "
                  f"{1000 * statistics.median(first_times):>9.1f} {1000 * again:>9.2f} {ref:>8.2f} "
                  f"{spread(pr_times, 2, ' s'):>14} {ref / nav:>8.1f}x {ref / again:>10.1f}x "
                  f"{f'{result.cost:.2f}' if found else 'failed':>7} {pr_length:>8.2f} {shorter:>10} "
                  f"{result.stats['expansions']:>10}")
    bubble = math.hypot((car.LF + car.LB) / 2, car.W / 2)
    distances = "solved at each pose" if options.get("distance_table") is False else \
        "from the robot's table at half-cell and 5-degree spacing"
    margin = math.sqrt(2) * res + res / 4 + math.hypot(car.LF, car.W / 2) * math.sin(math.pi / 72)
    notes = (
        f"weight: navlab's heuristic weight; the row at PythonRobotics' own (H_COST {module.H_COST:g}) compares "
        "like with like, the other is navlab's own search (1: unweighted).",
        f"PyRob/nav: median PythonRobotics time / median navlab time (x faster), {repeat} navlab run(s) per query "
        "and weight, interleaved, each right after a PythonRobotics run of the query (PyRob s: the median of all "
        "of them, the same on both of a query's rows); navlab ms with the robot's footprint "
        "lattice and Reeds-Shepp distance table kept from its "
        "earlier queries (one of each for every start heading and goal), first ms with them cleared (a robot's "
        "first query), again ms the kept query at once again (its code and data still in the CPU's caches, as "
        "in a planner replanning in a tight loop; navlab ms follows a PythonRobotics run, which evicts them); "
        "the map's "
        "distance tables are cached by content in both; lengths in metres driven (PythonRobotics': the polyline of its x_list, y_list, whose 0.1 m "
        "chords under-measure its arcs a little, so nav<=PyRob allows 1 cm).",
        f"PythonRobotics' collision check: the obstacle points within {bubble:.2f} m of the car's centre "
        "(kd-tree bubble), then a pose is rejected if its rectangle contains one; poses 0.1 m apart; the points "
        "are the whole map.",
        f"navlab's: no overlap with a blocked cell, so {res / 2:g} m around each point (its cell), plus a "
        f"margin: up to {margin:.2f} m (sqrt(2) res + res/4 + R sin 2.5 deg) where its cell lists decide, "
        f"{res / 2:g} m (res/2) where its exact re-check does (analytic and smoothed curves, and the primitives "
        "of a search that exhausted its space on the lists).",
        f"Search: PythonRobotics {module.XY_GRID_RESOLUTION:g} m / {math.degrees(module.YAW_GRID_RESOLUTION):g} "
        f"deg states, {module.XY_GRID_RESOLUTION * 1.5:g} m arcs, {module.N_STEER + 1} steering values, "
        f"heuristic x{module.H_COST:g}, switch-back cost {module.SB_COST:g};",
        f"navlab {res:g} m / 5 deg states (72 bins), three primitives per direction, heuristic x the weight "
        f"(the larger of the obstacle-free Reeds-Shepp length, {distances}, and an 8-connected field, which exceeds the "
        "straight line by up to 8%: off 45-degree multiples, so not strictly admissible), Reeds-Shepp shortcut smoothing.",
    )
    for note in notes:
        print(note)


def _cpu_model() -> str:
    """The CPU's model name as lscpu gives it."""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return "CPU: (lscpu not available)"
    return next((line.strip() for line in out.splitlines() if line.startswith("Model name")), "CPU: unknown")


def _radians(pose):
    return pose[0], pose[1], math.radians(pose[2])


def _described(options) -> str:
    return ", ".join(f"{k}={v}" for k, v in options.items()) or "defaults"


def reference_map(options, runs: int = 5) -> None:
    """navlab alone on a 384 x 384 map at 0.05 m (Nav2 Smac's README quotes 2-20 ms for such maps, 72 bins).

    Each run is timed twice, motions interleaved: from a cleared footprint
    lattice and distance table (a robot's first query: they are one per robot, for every
    start heading and goal) and again with them kept.
    ``solves`` counts the Reeds–Shepp lengths the search's lazy queue solved (not read from the
    robot's table; Dubins keys are computed as children are queued, so it is 0 there).
    """
    res, n = SMAC_RES, SMAC_CELLS
    grid = OccupancyGrid(three_walls(), resolution=res)
    footprint = ROBOT
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
            forget_robot()
            for times in (cold[motion], warm[motion]):
                t0 = time.perf_counter()
                results[motion] = plan_hybrid(grid, start, goal, 0.4, motion=motion, footprint=footprint, **options)
                times.append(time.perf_counter() - t0)
    print(f"{'motion':<12} {'first ms':>9} {'range':>16} {'warm ms':>9} {'range':>16} {'length m':>9} "
          f"{'expansions':>10} {'solves':>7}")
    for motion in motions:
        result = results[motion]
        print(f"{motion:<12} {1000 * statistics.median(cold[motion]):>9.1f} "
              f"{spread([1000 * t for t in cold[motion]], 1, ' ms'):>16} "
              f"{1000 * statistics.median(warm[motion]):>9.1f} "
              f"{spread([1000 * t for t in warm[motion]], 1, ' ms'):>16} "
              f"{result.cost:>9.2f} {result.stats['expansions']:>10} {result.stats['heuristics_solved']:>7}")
    print(f"first ms: a robot's first query (footprint lattice and distance table cleared), warm ms: the same query "
          f"again with them kept; medians of {runs} run(s), wall time; solves: Reeds-Shepp lengths the lazy queue "
          "solved (not read from the table)")

# ---------------------------------------------------------------------------
# --smac-maps: Nav2 Smac's README figure ("2-20 ms for planning across 147,456 cell maps with 72 angular
# bins") on maps of that size of the kinds its users plan on
# ---------------------------------------------------------------------------
SMAC_RES, SMAC_CELLS = 0.05, 384  # [m], cells a side: 147 456 cells, 19.2 m square
ROBOT = [[-0.25, -0.2], [0.25, -0.2], [0.25, 0.2], [-0.25, 0.2]]  # [m] 0.5 x 0.4 m, the pose at its centre
TURNING_RADIUS = 0.4  # [m] Smac README's example minimum_turning_radius
SMAC_SEED = 21  # issue 21; maps and queries were fixed with it before any timing was seen
QUERIES_PER_MAP = 6
QUERY_DISTANCE = (8.0, 18.0)  # [m] start to goal, straight line
#: Smac README's example parameters that navlab has (its cost_penalty has no counterpart: navlab's maps
#: are binary); angle_quantization_bins is 72 as in its metric, navlab's default too
SMAC_README = {"analytic_expansion_ratio": 3.5, "analytic_expansion_max_length": 3.0, "reverse_penalty": 2.1,
               "change_penalty": 0.20, "non_straight_penalty": 1.25}
SMAC_SETTINGS = (  # (label, motion, options): the same for every map and query
    ("navlab defaults, dubins", "dubins", {}),
    ("navlab defaults, reeds_shepp", "reeds_shepp", {}),
    ("Smac README, dubins", "dubins", SMAC_README),
)


def _box(blocked, x0, y0, x1, y1, res=SMAC_RES):
    """Block the cells whose centres lie in the rectangle [x0, x1] x [y0, y1] [m] (clipped to the map)."""
    h, w = blocked.shape
    i0, i1 = max(0, math.ceil(x0 / res - 0.5)), min(w, math.floor(x1 / res - 0.5) + 1)
    j0, j1 = max(0, math.ceil(y0 / res - 0.5)), min(h, math.floor(y1 / res - 0.5) + 1)
    blocked[j0:j1, i0:i1] = True


def three_walls() -> np.ndarray:
    """The hand-made reference map: three walls on a 384^2 map at 0.05 m (blocked cells, row = y)."""
    res, n = SMAC_RES, SMAC_CELLS
    blocked = np.zeros((n, n), dtype=bool)
    for x0, y0, x1, y1 in ((6.0, 0.0, 6.2, 12.0), (12.0, 7.0, 12.2, 19.2), (6.0, 15.0, 9.0, 15.2)):  # walls [m]
        blocked[round(y0 / res):round(y1 / res), round(x0 / res):round(x1 / res)] = True
    return blocked


def office(rng: np.random.Generator, rooms: int = 6, wall: float = 0.1, door: float = 1.0,
           extra_doors: float = 0.3) -> np.ndarray:
    """Rooms and doors: a 6 x 6 grid of 3.2 m rooms, 0.1 m walls; the walls a perfect maze opens
    (:func:`navlab.grid.maze.maze_walls`, so every room is reachable) get a 1 m door at a random place,
    each other inner wall one with probability ``extra_doors`` (loops, as offices have)."""
    n, size = SMAC_CELLS, SMAC_CELLS * SMAC_RES / rooms
    blocked = np.zeros((n, n), dtype=bool)
    east, north = maze_walls(rooms, rooms, rng)
    for k in range(1, rooms):  # the wall lines x = k size (vertical) and y = k size (horizontal)
        _box(blocked, k * size - wall / 2, 0.0, k * size + wall / 2, n * SMAC_RES)
        _box(blocked, 0.0, k * size - wall / 2, n * SMAC_RES, k * size + wall / 2)
    for vertical, stands in ((True, east), (False, north)):
        for a in range(rooms - 1):  # the line between room a and a + 1
            for b in range(rooms):  # the room along it
                if stands[b, a] if vertical else stands[a, b]:
                    if rng.random() >= extra_doors:
                        continue
                lo = b * size + wall / 2 + rng.uniform(0.2, size - wall - door - 0.2)  # [m] the door's near edge
                across = (a + 1) * size
                x0, y0, x1, y1 = (across - wall, lo, across + wall, lo + door) if vertical else \
                    (lo, across - wall, lo + door, across + wall)
                j0, j1 = round(y0 / SMAC_RES), round(y1 / SMAC_RES)
                i0, i1 = round(x0 / SMAC_RES), round(x1 / SMAC_RES)
                blocked[j0:j1, i0:i1] = False
    return blocked


def warehouse(shelf: float = 1.0, aisle: float = 1.6, margin: float = 2.0, cross: float = 2.0) -> np.ndarray:
    """Shelf rows: back-to-back racks 1 m deep in rows 1.6 m apart (the aisles), each row split by a 2 m
    cross aisle in the middle, 2 m of open floor around (the docks)."""
    extent = SMAC_CELLS * SMAC_RES
    blocked = np.zeros((SMAC_CELLS, SMAC_CELLS), dtype=bool)
    half = (extent - 2 * margin - cross) / 2
    y = margin
    while y + shelf <= extent - margin:
        _box(blocked, margin, y, margin + half, y + shelf)
        _box(blocked, extent - margin - half, y, extent - margin, y + shelf)
        y += shelf + aisle
    return blocked


def clutter(rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` obstacles at uniform places: half discs (radius 0.15-0.5 m), half axis-aligned boxes
    (sides 0.3-1.2 m)."""
    blocked = np.zeros((SMAC_CELLS, SMAC_CELLS), dtype=bool)
    extent = SMAC_CELLS * SMAC_RES
    centres = (np.arange(SMAC_CELLS) + 0.5) * SMAC_RES
    for k in range(count):
        x, y = rng.uniform(0.0, extent, 2)
        if k % 2:
            w, h = rng.uniform(0.3, 1.2, 2)
            _box(blocked, x - w / 2, y - h / 2, x + w / 2, y + h / 2)
        else:
            r = rng.uniform(0.15, 0.5)
            blocked |= (centres[None, :] - x) ** 2 + (centres[:, None] - y) ** 2 <= r * r
    return blocked


def smac_maps(seed: int = SMAC_SEED):
    """The fixed map set: (name, blocked cells), every map 384 x 384 at 0.05 m, from one seeded Generator."""
    rng = np.random.default_rng(seed)
    return [("office (6x6 rooms, 1 m doors)", office(rng)), ("warehouse (1.6 m aisles)", warehouse()),
            ("clutter, 40 obstacles", clutter(rng, 40)), ("clutter, 120 obstacles", clutter(rng, 120)),
            ("three walls (reference)", three_walls())]


def smac_queries(blocked: np.ndarray, rng: np.random.Generator, count: int = QUERIES_PER_MAP, tries: int = 100_000):
    """``count`` (start, goal) poses [m, m, rad], uniform places and headings, 8-18 m apart, drawn with
    ``rng`` among poses where the robot fits (no blocked cell under its footprint, exactly) whose centre
    has clearance >= the robot's circumscribed radius; start and goal are joined by cells with that
    clearance (so a disc the robot fits in at any heading can drive between them; a car still may not)."""
    from scipy.ndimage import distance_transform_edt, label

    vertices = np.array(ROBOT, dtype=float)
    reach = float(np.hypot(vertices[:, 0], vertices[:, 1]).max())
    roomy = distance_transform_edt(~blocked) * SMAC_RES >= reach
    parts, _ = label(roomy, structure=np.ones((3, 3)))
    extent = SMAC_CELLS * SMAC_RES

    def pose():
        while True:
            x, y = rng.uniform(0.0, extent, 2)
            p = (float(x), float(y), float(rng.uniform(-math.pi, math.pi)))
            part = parts[int(y / SMAC_RES), int(x / SMAC_RES)]
            if part and first_overlap_exact(blocked, SMAC_RES, vertices, 0.0, np.array([p]), 0.0) is None:
                return p, part

    queries = []
    for _ in range(tries):
        (start, a), (goal, b) = pose(), pose()
        if a == b and QUERY_DISTANCE[0] <= math.hypot(goal[0] - start[0], goal[1] - start[1]) <= QUERY_DISTANCE[1]:
            queries.append((start, goal))
            if len(queries) == count:
                return queries
    raise RuntimeError(f"found only {len(queries)} queries in {tries} tries")


def _timed(grid, start, goal, motion, options, **more):
    """One plan: (wall [s], CPU [s], Result)."""
    w0, c0 = time.perf_counter(), time.process_time()
    result = plan_hybrid(grid, start, goal, TURNING_RADIUS, motion=motion, footprint=ROBOT, **options, **more)
    return time.perf_counter() - w0, time.process_time() - c0, result


def _ms(values) -> str:
    """median (min-max) in ms."""
    values = [1000 * v for v in values]
    return f"{statistics.median(values):.1f} ({spread(values, 1)})" if values else "-"


def smac_benchmark(seed: int = SMAC_SEED) -> None:
    """Hybrid A* on the fixed map set against Smac's README figure (2-20 ms, 147 456 cells, 72 bins).

    Per query and setting, interleaved setting by setting: ``first`` from a cleared footprint
    lattice and distance table (a robot's first query: it traces the swept cells and solves the
    Reeds–Shepp lengths it needs as it goes; both are one per robot, for every start heading and
    goal), then ``warm``, the same query again with them kept (a replanning robot's query), then
    ``floor``, the same query stopped after one expansion: what every query pays before its search
    (pose checks and the holonomic field from the goal as far as the start's cell, the search settling
    more of it lazily as it reads it: :mod:`navlab.grid.hybrid_field`). The map's
    tables (:func:`navlab.grid.hybrid_astar._map_tables`: clearance and distance transforms) are kept
    per map, as Smac keeps its per-map collision data: only the first query on a map pays them; that
    cost is timed apart and printed per map. A failed query counts, its time included.
    """
    maps = smac_maps(seed)
    rng = np.random.default_rng([seed, 1])
    queries = [smac_queries(blocked, rng) for _, blocked in maps]
    print(f"Smac maps: {len(maps)} maps of {SMAC_CELLS} x {SMAC_CELLS} cells ({SMAC_CELLS ** 2} cells) at "
          f"{SMAC_RES:g} m, {QUERIES_PER_MAP} queries each {QUERY_DISTANCE[0]:g}-{QUERY_DISTANCE[1]:g} m apart "
          f"(seed {seed}); robot 0.5 x 0.4 m, turning radius {TURNING_RADIUS:g} m, 72 heading bins")
    for label_, motion, options in SMAC_SETTINGS:
        print(f"  {label_}: motion={motion}, {_described(options)}")
    grid0 = OccupancyGrid(maps[0][1], resolution=SMAC_RES)
    t0 = time.perf_counter()
    for motion in ("dubins", "reeds_shepp"):  # loads (or compiles) the kernels
        plan_hybrid(grid0, *queries[0][0], TURNING_RADIUS, motion=motion, footprint=ROBOT, max_expansions=2000)
    print(f"first calls (load compiled kernels): {time.perf_counter() - t0:.2f} s, not counted")
    rows = {label_: [] for label_, _, _ in SMAC_SETTINGS}  # (map, new wall, cpu, warm wall, cpu, result, floor)
    table_s = {}
    for (name, blocked), pairs in zip(maps, queries):
        grid = OccupancyGrid(blocked, resolution=SMAC_RES)
        _map_tables.cache_clear()
        packed = np.packbits(blocked).tobytes()
        t = time.perf_counter()
        _map_tables(blocked.shape, SMAC_RES, packed)
        table_s[name] = time.perf_counter() - t
        for start, goal in pairs:
            for label_, motion, options in SMAC_SETTINGS:
                forget_robot()
                new_w, new_c, _ = _timed(grid, start, goal, motion, options)
                warm_w, warm_c, result = _timed(grid, start, goal, motion, options)
                floor_w, _, _ = _timed(grid, start, goal, motion, options, max_expansions=1)
                rows[label_].append((name, new_w, new_c, warm_w, warm_c, result, floor_w))
    print(f"{'map':<30} {'blocked':>7} {'tables ms':>9} {'d median m':>10}")
    for (name, blocked), pairs in zip(maps, queries):
        d = statistics.median(math.hypot(g[0] - s[0], g[1] - s[1]) for s, g in pairs)
        print(f"{name:<30} {blocked.mean():>6.1%} {1000 * table_s[name]:>9.1f} {d:>10.1f}")
    header = (f"{'map':<30} {'ok':>4} {'first ms (range)':>23} {'CPU ms':>8} {'warm ms (range)':>20} "
              f"{'CPU ms':>8} {'found ms':>8} {'floor ms':>8} {'expansions (range)':>22} {'length m':>8}")
    for label_, _, _ in SMAC_SETTINGS:
        print(f"\n{label_}: median (min-max) over queries; found ms: warm, found queries only")
        print(header)
        for name in [m for m, _ in maps] + ["all maps"]:
            sel = [r for r in rows[label_] if name in (r[0], "all maps")]
            ok = [r[5] for r in sel if r[5].status == Status.EXACT]
            exp = [r[5].stats["expansions"] for r in sel]
            length = f"{statistics.median(r.cost for r in ok):.2f}" if ok else "-"
            print(f"{name:<30} {len(ok):>2}/{len(sel):<1} {_ms([r[1] for r in sel]):>23} "
                  f"{1000 * statistics.median(r[2] for r in sel):>8.1f} {_ms([r[3] for r in sel]):>20} "
                  f"{1000 * statistics.median(r[4] for r in sel):>8.1f} "
                  f"{f'{1000 * statistics.median(r[3] for r in sel if r[5].status == Status.EXACT):.1f}' if ok else '-':>8} "
                  f"{1000 * statistics.median(r[6] for r in sel):>8.1f} "
                  f"{f'{statistics.median(exp):.0f} ({min(exp)}-{max(exp)})':>22} {length:>8}")
        fails = [(r[0], r[5].reason) for r in rows[label_] if r[5].status != Status.EXACT]
        for name, reason in fails:
            print(f"  failed on {name}: {reason}")
    within = {label_: sum(0.002 <= r[3] <= 0.020 for r in rows[label_]) for label_ in rows}
    print("\nwarm queries within 2-20 ms: " + ", ".join(f"{k} {v}/{len(rows[k])}" for k, v in within.items()))
    print("ok: found / queries; a failed query counts in every median but length (its time: until max_expansions "
          "or an exhausted search). Smac's figure gives no success rate, query set or hardware.")


# ---------------------------------------------------------------------------
# --smac-maps --smac-driver PATH: Nav2 Smac's own Hybrid-A* (benchmarks/smac) on the same maps and
# queries, interleaved with navlab query by query
# ---------------------------------------------------------------------------
#: Nav2's defaults for the parameters navlab shares (SmacPlannerHybrid::configure at a3a97043)
NAV2_DEFAULTS = {"analytic_expansion_ratio": 3.5, "analytic_expansion_max_length": 3.0, "reverse_penalty": 2.0,
                 "change_penalty": 0.0, "non_straight_penalty": 1.2}
SMAC_PAIRS = (  # (label, navlab motion, the shared parameters, Smac's motion model)
    ("DUBIN, Smac README settings", "dubins", SMAC_README, "DUBIN"),
    ("REEDS_SHEPP, Nav2 defaults", "reeds_shepp", NAV2_DEFAULTS, "REEDS_SHEPP"),
)
#: Smac's parameters besides the shared ones; the rest are SmacPlannerHybrid's defaults
SMAC_COMMON = {"angle_quantization_bins": 72, "minimum_turning_radius": TURNING_RADIUS,
               "max_iterations": 1_000_000, "max_planning_time": 1000.0}
#: Smac's variants: (label, costmap, Smac parameters besides SMAC_COMMON and the pair's). "binary" is
#: navlab's map as it is (blocked cells lethal, no inflation layer): the one comparable to navlab.
SMAC_VARIANTS = (
    ("binary", "binary", {}),
    ("binary, full-res heuristic", "binary", {"downsample_obstacle_heuristic": "false"}),
    ("inflated", "inflated", {}),
)
#: navlab's search budget in the side by side: Smac's max_iterations
NAVLAB_BUDGET = {"max_expansions": SMAC_COMMON["max_iterations"]}


def _median(values, scale=1.0, digits=1) -> str:
    values = [scale * v for v in values if not math.isnan(v)]
    return f"{statistics.median(values):.{digits}f}" if values else "-"


def _smac_drivers(driver, blocked, query, inscribed):
    """The map's Smac processes, one per (pair, variant), each having answered ``query`` once untimed."""
    from smac.compare import INFLATION_RADIUS, COST_SCALING_FACTOR, SmacDriver, binary_costs, inflated_costs

    costs = {"binary": binary_costs(blocked), "inflated": inflated_costs(blocked, SMAC_RES, inscribed)}
    drivers = {}
    for label_, _, shared, model in SMAC_PAIRS:
        for variant, costmap, extra in SMAC_VARIANTS:
            params = {"motion_model_for_search": model, **SMAC_COMMON, **shared, **extra}
            inflation = (INFLATION_RADIUS, COST_SCALING_FACTOR) if costmap == "inflated" else None
            drivers[label_, variant] = d = SmacDriver(driver, costs[costmap], SMAC_RES, ROBOT, params, inflation)
            d.plan(*query)
    return drivers


def smac_side_by_side(driver: Path, seed: int = SMAC_SEED) -> None:
    """navlab and Nav2 Smac's Hybrid-A* on the --smac-maps maps and queries, query by query.

    Per map: navlab's map tables and Smac's plugin set-up (its distance lookup table) are paid
    and timed before the queries, then each Smac process answers the map's first query once
    untimed. Per query and setting pair: navlab from a cleared footprint lattice and distance
    table ("first"; Smac builds its table at set-up),
    navlab again ("warm", the headline), then Smac's variants (SMAC_VARIANTS). Smac's time is its
    createPlan without the smoother (Smac smooths afterwards; navlab's time includes its own
    shortcut smoothing). Both get Smac's default budget, 10^6 expansions. A failed query counts,
    its time included. Smac's poses are checked against the blocked cells with shapely (the robot
    rectangle at each pose, and at 1 cm steps on the straight segments between poses).
    """
    import shapely  # noqa: F401  (fail early: the overlap check needs it)

    from smac.compare import INFLATION_RADIUS, COST_SCALING_FACTOR, BlockedCells, densified

    maps = smac_maps(seed)
    rng = np.random.default_rng([seed, 1])
    queries = [smac_queries(blocked, rng) for _, blocked in maps]
    inscribed = float(np.abs(np.array(ROBOT)).min())  # [m] the centred rectangle's half width
    head = subprocess.run(["git", "-C", str(Path(__file__).resolve().parent), "log", "-1", "--format=%h %cI"],
                          capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", str(Path(__file__).resolve().parent), "status", "--porcelain", "--", "../src"],
                           capture_output=True, text=True).stdout.split()
    import navlab

    print(f"navlab: imported from {Path(navlab.__file__).parent}; benchmark's repository at commit {head or '?'}"
          + (f", its src/ with uncommitted changes ({', '.join(dirty[1::2])})" if dirty else ""))
    print(f"Smac side by side: {len(maps)} maps of {SMAC_CELLS} x {SMAC_CELLS} cells at {SMAC_RES:g} m, "
          f"{QUERIES_PER_MAP} queries each (seed {seed}); robot 0.5 x 0.4 m, turning radius {TURNING_RADIUS:g} m, "
          "72 heading bins")
    print(f"Smac driver: {driver}")
    for label_, motion, shared, model in SMAC_PAIRS:
        print(f"  {label_}: navlab motion={motion}, Smac motion_model_for_search={model}; both: {_described(shared)}")
    print(f"  navlab also: {_described(NAVLAB_BUDGET)}; Smac also: {_described(SMAC_COMMON)}, other parameters "
          "SmacPlannerHybrid's defaults (tolerance 0.25 m, allow_primitive_interpolation true, "
          "downsample_obstacle_heuristic true, cost_penalty 2.0, retrospective_penalty 0.015, lookup_table_size 20 m; "
          "smoother not run)")
    print("  Smac variants: binary = navlab's map (254 blocked, 0 free, no inflation layer); binary, full-res "
          "heuristic = the same with downsample_obstacle_heuristic false; inflated = Nav2's inflation layer defaults "
          f"(inflation_radius {INFLATION_RADIUS} m, cost_scaling_factor {COST_SCALING_FACTOR}, inscribed radius "
          f"{inscribed} m)")
    grid0 = OccupancyGrid(maps[0][1], resolution=SMAC_RES)
    for _, motion, shared, _ in SMAC_PAIRS:  # loads (or compiles) navlab's kernels
        plan_hybrid(grid0, *queries[0][0], TURNING_RADIUS, motion=motion, footprint=ROBOT, max_expansions=2000,
                    **shared)
    rows, setup = [], []
    variants = [v for v, _, _ in SMAC_VARIANTS]
    for (name, blocked), pairs in zip(maps, queries):
        grid = OccupancyGrid(blocked, resolution=SMAC_RES)
        _map_tables.cache_clear()
        t = time.perf_counter()
        _map_tables(blocked.shape, SMAC_RES, np.packbits(blocked).tobytes())
        tables_ms = 1000 * (time.perf_counter() - t)
        drivers = _smac_drivers(driver, blocked, pairs[0], inscribed)
        setup.append((name, tables_ms, statistics.median(d.config["configure_ms"] for d in drivers.values()),
                      {v: drivers[SMAC_PAIRS[0][0], v].config["circumscribed_cost"] for v in variants}))
        cells = BlockedCells(blocked, SMAC_RES)
        for q, (start, goal) in enumerate(pairs):
            for label_, motion, shared, _ in SMAC_PAIRS:
                row = {"map": name, "query": q, "pair": label_}
                forget_robot()
                row["new_w"], _, _ = _timed(grid, start, goal, motion, {**shared, **NAVLAB_BUDGET})
                row["nav_w"], row["nav_c"], result = _timed(grid, start, goal, motion, {**shared, **NAVLAB_BUDGET})
                row["nav_ok"] = result.status == Status.EXACT
                row["nav_exp"] = result.stats["expansions"]
                row["nav_len"] = result.cost if row["nav_ok"] else math.nan
                for variant in variants:
                    answer = row[variant] = drivers[label_, variant].plan(start, goal)
                    if answer["found"]:
                        answer["at_poses"] = cells.overlaps(ROBOT, answer["poses"])
                        answer["between"] = cells.overlaps(ROBOT, densified(answer["poses"]))
                rows.append(row)
        for d in drivers.values():
            d.close()
    _print_side_by_side(rows, setup, [m for m, _ in maps], variants)


def _print_within_smacs_figure(rows, variant) -> None:
    """navlab on the queries where Smac itself meets its README's figure: a collision-free path (no
    overlap at its poses or between them) in 2-20 ms. Smac's README names no map or query, so these
    queries are the comparable ones by its own measure, on this machine."""
    meets = [r for r in rows if r[variant]["found"] and not r[variant]["between"][0]
             and 2.0 <= r[variant]["wall_ms"] <= 20.0]
    if not meets:
        print(f"  Smac {variant} met 2-20 ms with a collision-free path on no query")
        return
    nav_ms = [1000 * r["nav_w"] for r in meets]  # a failed query with its time until it gave up
    found_ms = [1000 * r["nav_w"] for r in meets if r["nav_ok"]]
    ratios = [1000 * r["nav_w"] / r[variant]["wall_ms"] for r in meets]
    print(f"  where Smac {variant} met 2-20 ms collision-free ({len(meets)} queries): navlab found "
          f"{len(found_ms)}, {sum(t <= 20.0 for t in found_ms)} of them within 20 ms "
          f"({sum(t < 2.0 for t in found_ms)} below 2 ms); navlab ms median {statistics.median(nav_ms):.1f} "
          f"max {max(nav_ms):.1f}; navlab/Smac per query median {statistics.median(ratios):.2f} "
          f"max {max(ratios):.2f}")


def _print_side_by_side(rows, setup, map_names, variants) -> None:
    print(f"\n{'map':<30} {'navlab tables ms':>16} {'Smac configure ms':>17}  Smac circumscribed cost")
    for name, tables_ms, configure_ms, circumscribed in setup:
        print(f"{name:<30} {tables_ms:>16.1f} {configure_ms:>17.1f}  "
              + ", ".join(f"{v} {c:g}" for v, c in circumscribed.items()))
    print("(navlab's tables: once per map; Smac's configure: once per plugin, its Dubins/Reeds-Shepp distance table; "
          "circumscribed cost -1: no inflation layer, so every pose gets Smac's full footprint check)")
    short = {"binary": "bin", "binary, full-res heuristic": "bin-fullH", "inflated": "infl"}
    for label_, _, _, _ in SMAC_PAIRS:
        print(f"\n{label_}: medians over queries, ms (min-max); nav/Smac: median over queries of navlab warm / "
              "Smac binary wall time")
        print(f"{'map':<30} {'ok nav/' + '/'.join(short[v] for v in variants):>24} {'navlab warm':>18} {'CPU':>6} "
              f"{'first':>7} {'Smac bin':>19} {'CPU':>6} {'nav/Smac':>8} {'Smac bin-fullH':>19} "
              f"{'Smac infl':>18} {'nav exp':>8} {'Smac it ' + '/'.join(short[v] for v in variants):>24} "
              f"{'nav m':>6} {'Smac m':>6}")
        for name in map_names + ["all maps"]:
            sel = [r for r in rows if r["pair"] == label_ and name in (r["map"], "all maps")]
            ok = [sum(r["nav_ok"] for r in sel)] + [sum(r[v]["found"] for r in sel) for v in variants]
            both = [r for r in sel if r["nav_ok"] and r["binary"]["found"]]
            ratio = statistics.median(1000 * r["nav_w"] / r["binary"]["wall_ms"] for r in sel)
            iters = "/".join(_median([r[v]["iterations"] for r in sel], digits=0) for v in variants)
            print(f"{name:<30} {'/'.join(map(str, ok)) + f' of {len(sel)}':>24} "
                  f"{_ms([r['nav_w'] for r in sel]):>18} {_median([r['nav_c'] for r in sel], 1000):>6} "
                  f"{_median([r['new_w'] for r in sel], 1000):>7} "
                  f"{_ms([r['binary']['wall_ms'] / 1000 for r in sel]):>19} "
                  f"{_median([r['binary']['cpu_ms'] for r in sel]):>6} {ratio:>7.2f}x "
                  f"{_ms([r['binary, full-res heuristic']['wall_ms'] / 1000 for r in sel]):>19} "
                  f"{_ms([r['inflated']['wall_ms'] / 1000 for r in sel]):>18} "
                  f"{_median([r['nav_exp'] for r in sel], digits=0):>8} {iters:>24} "
                  f"{_median([r['nav_len'] for r in both], digits=2):>6} "
                  f"{_median([r['binary']['length_m'] for r in both], digits=2):>6}")
        sel = [r for r in rows if r["pair"] == label_]
        print(f"within 2-20 ms: navlab warm {sum(0.002 <= r['nav_w'] <= 0.020 for r in sel)}/{len(sel)}, "
              + ", ".join(f"Smac {v} {sum(2 <= r[v]['wall_ms'] <= 20 for r in sel)}/{len(sel)}" for v in variants))
        for v in variants:
            found = [r for r in sel if r[v]["found"]]
            at = [r for r in found if r[v]["at_poses"][0]]
            between = [r for r in found if r[v]["between"][0]]
            worst = max((r[v]["between"][1] for r in between), default=0.0)
            print(f"Smac {v}: paths whose robot rectangle overlaps a blocked cell: {len(at)}/{len(found)} at its "
                  f"poses, {len(between)}/{len(found)} counting 1 cm steps between them"
                  + (f" (largest overlap {1e4 * worst:.1f} cm^2; a cell is 25 cm^2)" if between else ""))
            for r in sel:
                if not r[v]["found"]:
                    print(f"  failed on {r['map']} query {r['query']}: {r[v]['reason']} after "
                          f"{r[v]['iterations']} iterations")
        fails = [f"{r['map']} query {r['query']}" for r in sel if not r["nav_ok"]]
        if fails:
            print(f"navlab failed on: {'; '.join(fails)}")
        for v in variants:
            _print_within_smacs_figure(sel, v)
    print("\nok: found / queries; a failed query counts in every time median (its time until it gave up), lengths "
          "over queries both navlab and Smac binary found (navlab: its path's length; Smac: the polyline of its "
          "unsmoothed poses). Smac it: A* iterations (expansions).")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pythonrobotics", type=Path,
                    default=Path(os.environ.get("PYTHONROBOTICS", "PythonRobotics")),
                    help="PythonRobotics checkout (default: $PYTHONROBOTICS, else ./PythonRobotics)")
    ap.add_argument("--repeat", type=int, help="runs per query and planner (the median counts; default 3, "
                                               "5 on the reference map)")
    ap.add_argument("--resolution", type=float, default=1.0, choices=(0.25, 0.5, 1.0),
                    help="navlab's cell size [m] (PythonRobotics' points are 1 m apart)")
    ap.add_argument("--quick", action="store_true", help="PythonRobotics' demo query once, no reference map")
    ap.add_argument("--reference-only", action="store_true",
                    help="only navlab on the 384 x 384 reference map (no PythonRobotics checkout needed)")
    ap.add_argument("--analytic-max", type=float, metavar="M",
                    help="navlab's analytic_expansion_max_length [m] (default: the planner's, max(3 m, 3 turning radii))")
    ap.add_argument("--analytic-ratio", type=float, metavar="R",
                    help="navlab's analytic_expansion_ratio (Smac's schedule; default: try at every expansion)")
    ap.add_argument("--weight", type=float, metavar="W",
                    help="navlab's heuristic weight beside PythonRobotics' own H_COST (default 1: its search "
                         "unweighted)")
    ap.add_argument("--exact-distances", action="store_true",
                    help="navlab's distance_table=false: the Reeds-Shepp distance solved at every pose, no table")
    ap.add_argument("--smac-maps", action="store_true",
                    help="only navlab on the fixed 384 x 384 map set against Nav2 Smac's README figure (2-20 ms)")
    ap.add_argument("--smac-driver", type=Path, metavar="PATH",
                    help="with --smac-maps: Nav2 Smac's Hybrid-A* (benchmarks/smac/build.sh builds it) side by side "
                         "with navlab on the same maps and queries")
    args = ap.parse_args()
    if args.repeat is not None and args.repeat < 1:
        ap.error("--repeat must be at least 1")
    options = {}
    if args.analytic_max is not None:
        options["analytic_expansion_max_length"] = args.analytic_max
    if args.analytic_ratio is not None:
        options["analytic_expansion_ratio"] = args.analytic_ratio
    if args.exact_distances:
        options["distance_table"] = False
    if args.weight is not None:
        options["weight"] = args.weight
    if args.smac_maps and (options or args.repeat is not None or args.quick or args.reference_only):
        ap.error("--smac-maps runs its fixed settings (navlab's defaults and Smac's README ones) once per query: "
                 "--analytic-max, --analytic-ratio, --exact-distances, --weight, --repeat, --quick and "
                 "--reference-only do not apply")
    if args.smac_driver is not None and not args.smac_maps:
        ap.error("--smac-driver goes with --smac-maps")
    if args.reference_only and args.quick:
        ap.error("--quick is PythonRobotics' demo query alone; --reference-only runs no PythonRobotics query")
    if args.smac_maps and args.smac_driver is not None:
        if not args.smac_driver.is_file():
            sys.exit(f"no Smac driver at {args.smac_driver}: build it with benchmarks/smac/build.sh NAV2_CHECKOUT")
        print(load_line("at start"))
        print(_cpu_model())
        smac_side_by_side(args.smac_driver.resolve())
        print(load_line("at end"))
        return
    if args.smac_maps:
        print(load_line("at start"))
        smac_benchmark()
        print(load_line("at end"))
        return
    if args.reference_only:
        print(load_line("at start"))
        reference_map(options, args.repeat or 5)
        print(load_line("at end"))
        return
    module, car = load_pythonrobotics(args.pythonrobotics.resolve())
    print(load_line("at start"))
    print(f"PythonRobotics: {args.pythonrobotics.resolve()}")
    compare(module, car, args.resolution, 1 if args.quick else args.repeat or 3, args.quick, options)
    if not args.quick:
        print()
        reference_map(options, args.repeat or 5)
    print(load_line("at end"))


if __name__ == "__main__":
    main()
