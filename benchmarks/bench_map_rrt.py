"""RRT* on real occupancy maps: speed against the `pythonrobotics` scene, and path quality.

    python benchmarks/bench_map_rrt.py [--runs 5] [--seeds 10] [--iters 20000] [--part speed|quality|all]

Speed (issue 15: "RRT* on a real map"): RRT*, uniform sampling, the same
iteration count on `pythonrobotics` and on a 1000 x 1000-cell map, interleaved
run by run in one process after a warm-up; prints the median times and their
ratio (goal: map ≤ 2x). The map is the Willow Garage office SLAM map
(tests/data/maps/willow-full.pgm, 0.1 m) at 0.05 m per cell (each cell split
in four, as the ROS tutorials also serve it), cropped to its central
1000 x 1000 cells; the origin moves with the crop, so metric coordinates stay
those of the full map. Robot radius 0.2 m.

Quality (issue 15: "Quality on real SLAM maps"): the full Willow map (58.4 m x
52.6 m at 0.1 m), robot radius 0.2 m, start (10.0, 9.6) and goal (31.5, 20.5)
(24.1 m apart, the path runs along two corridors). For `uniform` and
`integration` sampling and ``--seeds`` seeds: how many runs return EXACT, the
median path length, and the reference: the 8-connected octile A* path on the
map inflated by the radius (unknown cells counted as blocked, as the planner
does), joined to the exact start and goal. Every RRT* path is validated
independently: shapely distances from each edge to the blocked/unknown cell
squares (found through an STRtree) must exceed the radius.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import shapely
from tqdm import tqdm

import navlab
from navlab.grid import planner as grid_planner
from navlab.grid.mapio import load_map
from navlab.grid.occupancy import OccupancyGrid
from navlab.sampling.planners import RRTStar
from navlab.world import World

MAP = Path(__file__).resolve().parent.parent / "tests" / "data" / "maps" / "willow-full.yaml"
RADIUS = 0.2  # [m]
START, GOAL = (10.0, 9.6), (31.5, 20.5)  # [m] 24.1 m apart


def willow() -> OccupancyGrid:
    return load_map(MAP)


def willow_1000() -> OccupancyGrid:
    """Willow at 0.05 m per cell, the central 1000 x 1000 cells."""
    g = willow()
    blocked = np.kron(g.blocked, np.ones((2, 2), dtype=bool))
    unknown = np.kron(g.unknown, np.ones((2, 2), dtype=bool))
    y0, x0 = (blocked.shape[0] - 1000) // 2, (blocked.shape[1] - 1000) // 2
    res = g.resolution / 2
    origin = (g.origin[0] + x0 * res, g.origin[1] + y0 * res, 0.0)
    return OccupancyGrid(blocked[y0:y0 + 1000, x0:x0 + 1000], res, origin,
                         unknown[y0:y0 + 1000, x0:x0 + 1000], "willow-0.05-1000x1000")


def octile_reference(grid: OccupancyGrid, start, goal, radius: float) -> float:
    """Length (m) of the 8-connected octile A* path on the map inflated by ``radius``."""
    closed = OccupancyGrid(grid.blocked | grid.unknown, grid.resolution, grid.origin, name=grid.name)
    result = grid_planner.plan_world(closed.inflate(radius), start, goal, algorithm="astar",
                                     heuristic="octile", connectivity=8)
    if result.status.name != "EXACT":
        raise RuntimeError(f"no grid reference path: {result.status.name} {result.reason}")
    path = np.vstack((start, result.path, goal))
    return float(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1)))


class SquareCheck:
    """Independent path validation: shapely distances to the blocked cells' squares."""

    def __init__(self, grid: OccupancyGrid) -> None:
        j, i = np.nonzero(grid.blocked | grid.unknown)
        res, (ox, oy, _) = grid.resolution, grid.origin
        self.boxes = shapely.box(ox + i * res, oy + j * res, ox + (i + 1) * res, oy + (j + 1) * res)
        self.tree = shapely.STRtree(self.boxes)
        w, h = grid.width * res, grid.height * res
        self.extent = shapely.box(ox, oy, ox + w, oy + h)

    def min_clearance(self, path: np.ndarray, radius: float) -> float:
        """Smallest distance from the path to a blocked square (checked near ``radius`` only)."""
        line = shapely.LineString(path)
        if not self.extent.covers(line):
            return -1.0
        near = self.tree.query(line, predicate="dwithin", distance=radius + 1.0)
        return float(shapely.distance(line, self.boxes[near]).min()) if len(near) else np.inf


def speed(runs: int, iters: int) -> dict:
    scene = navlab.load_world("pythonrobotics")
    grid = willow_1000()
    on_map = World.from_grid(grid, START, GOAL, robot_radius=RADIUS)
    planners = {"pythonrobotics": scene, f"map {grid.width}x{grid.height}": on_map}
    for world in planners.values():  # compile / load the kernels first
        RRTStar(max_iter=200).plan(world, 0)
    times = {k: [] for k in planners}
    for run in tqdm(range(runs), desc="speed", file=sys.stderr, disable=not sys.stderr.isatty()):
        for name, world in planners.items():
            t = time.perf_counter()
            RRTStar(sampler="uniform", max_iter=iters).plan(world, run)
            times[name].append(time.perf_counter() - t)
    med = {k: statistics.median(v) for k, v in times.items()}
    names = list(planners)
    print(f"RRT* uniform, {iters} iterations, median of {runs} interleaved runs:")
    for k in names:
        print(f"  {k:24s} {med[k]:7.3f} s   ({1e6 * med[k] / iters:.1f} µs/iteration)  runs: "
              + ", ".join(f"{t:.3f}" for t in times[k]))
    ratio = med[names[1]] / med[names[0]]
    print(f"  ratio map / pythonrobotics: {ratio:.2f}x (goal ≤ 2x)")
    return {"times": times, "ratio": ratio}


def quality(seeds: int, iters: int) -> dict:
    grid = willow()
    world = World.from_grid(grid, START, GOAL, robot_radius=RADIUS)
    reference = octile_reference(grid, START, GOAL, RADIUS)
    check = SquareCheck(grid)
    print(f"Willow office map {grid.width}x{grid.height} @ {grid.resolution} m, radius {RADIUS} m, "
          f"start {START} goal {GOAL} ({np.hypot(GOAL[0] - START[0], GOAL[1] - START[1]):.1f} m apart)")
    print(f"  octile 8-connected grid path (inflated map): {reference:.3f} m")
    out = {"reference": reference}
    for sampler in ("uniform", "integration"):
        costs, exact, times, worst = [], 0, [], np.inf
        for seed in tqdm(range(seeds), desc=sampler, file=sys.stderr, disable=not sys.stderr.isatty()):
            t = time.perf_counter()
            result = RRTStar(sampler=sampler, max_iter=iters).plan(world, seed)
            times.append(time.perf_counter() - t)
            if result.status.name == "EXACT":
                exact += 1
                costs.append(result.cost)
                worst = min(worst, check.min_clearance(result.path, RADIUS))
        med = statistics.median(costs) if costs else float("nan")
        print(f"  {sampler:11s} EXACT {exact}/{seeds}  median cost {med:.3f} m "
              f"({100 * (med / reference - 1):+.1f}% vs grid)  costs: " + ", ".join(f"{c:.2f}" for c in costs))
        print(f"  {'':11s} median time {statistics.median(times):.2f} s; smallest clearance of any path "
              f"{worst:.9f} m = radius + {worst - RADIUS:.3g} m (independent check; must exceed {RADIUS} m)")
        out[sampler] = {"exact": exact, "median_cost": med, "costs": costs, "min_clearance": worst}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--iters", type=int, default=20000)
    parser.add_argument("--part", choices=("speed", "quality", "all"), default="all")
    args = parser.parse_args(argv)
    if args.part in ("speed", "all"):
        speed(args.runs, args.iters)
    if args.part in ("quality", "all"):
        quality(args.seeds, args.iters)
    return 0


if __name__ == "__main__":
    sys.exit(main())
