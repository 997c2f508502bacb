"""RRT* between poses (Reeds–Shepp or Dubins steering) against OMPL's native C++ RRTstar, side by side.

    apt-get install -y libompl-dev g++     # OMPL 1.5 headers and library (Debian)
    python benchmarks/bench_se2_rrt_star.py                          # 10⁴ and 10⁵ iterations, 0.2 s and 1 s budgets
    python benchmarks/bench_se2_rrt_star.py --sizes 10000 --runs 3 --budgets 0.2 --scenes trap_car

Same state space, same scenes, same validity check on both sides. navlab
plans with ``navlab.plan(scene, planner="rrt_star", motion=...)``; OMPL runs
``ReedsSheppStateSpace`` / ``DubinsStateSpace`` with the scene's turning radius
in a small C++ program built here against the system's OMPL. Its state validity
checker is navlab's certified footprint check, re-implemented in the driver on
the very cells navlab uses (the footprint's cells per heading bin on the
scene's raster, written to a file by this script); its motion validator is
OMPL's discrete one with the resolution set so that the states it checks along
a curve are as far apart as navlab's (``ds`` of arc length). The step (range)
is navlab's default η for the scene; every other OMPL setting is its default
(k-nearest rewiring with rewire factor 1.1, goal bias 0.05), as navlab's are
(radius rewiring with factor 1.1; uniform positions; a goal connection tried
from each new node within η).

Part 1, speed at equal iterations (10⁴, 10⁵): medians of ``--runs`` runs,
alternating navlab / OMPL; the ratio OMPL / navlab is "× faster".
Part 2, anytime quality at equal wall-clock budgets (0.2 s, 1 s): median gap
of the returned path to the scene's best known cost (docs/scenes.md) and how
many runs found a path (navlab's clock includes its set-up, OMPL's covers
``solve`` only).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import statistics
import struct
import sys
import tempfile
from typing import List, Optional

import numpy as np

import navlab
from conditions import load_line
from navlab.grid.rasterize import rasterize
from navlab.pose_queries import query_footprint, query_poses
from navlab.sampling.footprint_lattice import lattice_for, robot_outline

#: the best known costs of the heading scenes (docs/scenes.md)
BEST_KNOWN = {"narrow_aisle": 5.3779, "parking": 21.2248, "trap_car": 20.7484}  # docs/scenes.md (session 15)

DRIVER_SOURCE = r"""
// OMPL 1.5 driver for bench_se2_rrt_star.py: RRTstar in a Reeds-Shepp or Dubins space,
// validity = navlab's footprint cells per heading bin on the scene's raster.
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/DubinsStateSpace.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace ob = ompl::base;
namespace og = ompl::geometric;

struct Lattice {
    int64_t w = 0, h = 0, bins = 0;
    double res = 0, theta0 = 0, step = 0;
    std::vector<uint8_t> blocked;
    std::vector<int64_t> start, cells;
};
static Lattice L;

static bool load(const char *path) {
    FILE *f = std::fopen(path, "rb");
    if (!f) return false;
    int64_t ncells = 0;
    bool ok = std::fread(&L.w, 8, 1, f) == 1 && std::fread(&L.h, 8, 1, f) == 1 && std::fread(&L.bins, 8, 1, f) == 1 &&
              std::fread(&ncells, 8, 1, f) == 1 && std::fread(&L.res, 8, 1, f) == 1 &&
              std::fread(&L.theta0, 8, 1, f) == 1 && std::fread(&L.step, 8, 1, f) == 1;
    if (ok) {
        L.blocked.resize(L.w * L.h);
        L.start.resize(L.bins + 1);
        L.cells.resize(2 * ncells);
        ok = std::fread(L.blocked.data(), 1, L.blocked.size(), f) == L.blocked.size() &&
             std::fread(L.start.data(), 8, L.start.size(), f) == L.start.size() &&
             std::fread(L.cells.data(), 8, L.cells.size(), f) == L.cells.size();
    }
    std::fclose(f);
    return ok;
}

// navlab.sampling.footprint_lattice.pose_free, line for line
static bool pose_free(double x, double y, double th) {
    int64_t cx = (int64_t)std::floor(x / L.res), cy = (int64_t)std::floor(y / L.res);
    int64_t b = (int64_t)std::nearbyint((th - L.theta0) / L.step) % L.bins;
    if (b < 0) b += L.bins;
    for (int64_t i = L.start[b]; i < L.start[b + 1]; ++i) {
        int64_t X = cx + L.cells[2 * i], Y = cy + L.cells[2 * i + 1];
        if (X < 0 || Y < 0 || X >= L.w || Y >= L.h || L.blocked[Y * L.w + X]) return false;
    }
    return true;
}

int main(int argc, char **argv) {
    // lattice seed iterations seconds range radius reverse ds xmin xmax ymin ymax sx sy st gx gy gt
    if (argc != 19) { std::fprintf(stderr, "bad arguments\n"); return 2; }
    if (!load(argv[1])) { std::fprintf(stderr, "cannot read %s\n", argv[1]); return 2; }
    ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
    ompl::RNG::setSeed(std::strtoul(argv[2], nullptr, 10));
    unsigned long iterations = std::strtoul(argv[3], nullptr, 10);
    double seconds = std::atof(argv[4]), range = std::atof(argv[5]), radius = std::atof(argv[6]);
    bool reverse = std::atoi(argv[7]) != 0;
    double ds = std::atof(argv[8]);
    double v[10];
    for (int i = 0; i < 10; ++i) v[i] = std::atof(argv[9 + i]);

    std::shared_ptr<ob::SE2StateSpace> space;
    if (reverse) space = std::make_shared<ob::ReedsSheppStateSpace>(radius);
    else space = std::make_shared<ob::DubinsStateSpace>(radius);
    ob::RealVectorBounds bounds(2);
    bounds.setLow(0, v[0]); bounds.setHigh(0, v[1]);
    bounds.setLow(1, v[2]); bounds.setHigh(1, v[3]);
    space->setBounds(bounds);
    auto si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([](const ob::State *s) {
        auto *p = s->as<ob::SE2StateSpace::StateType>();
        return pose_free(p->getX(), p->getY(), p->getYaw());
    });
    // states along a curve no more than ds of arc length apart, as navlab traces them
    si->setStateValidityCheckingResolution(ds / space->getMaximumExtent());
    si->setup();
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    ob::ScopedState<ob::SE2StateSpace> start(space), goal(space);
    start->setXY(v[4], v[5]); start->setYaw(v[6]);
    goal->setXY(v[7], v[8]); goal->setYaw(v[9]);
    pdef->setStartAndGoalStates(start, goal, 1e-9);
    pdef->setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));
    auto planner = std::make_shared<og::RRTstar>(si);
    planner->setRange(range);
    planner->setProblemDefinition(pdef);
    planner->setup();

    auto t0 = std::chrono::steady_clock::now();
    auto deadline = t0 + std::chrono::duration<double>(seconds > 0.0 ? seconds : 1e9);
    planner->solve(ob::PlannerTerminationCondition([&] {
        return (iterations > 0 && (unsigned long)planner->numIterations() >= iterations) ||
               std::chrono::steady_clock::now() >= deadline;
    }));
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double cost = INFINITY;
    if (pdef->hasExactSolution())
        cost = std::static_pointer_cast<og::PathGeometric>(pdef->getSolutionPath())->length();
    std::printf("%.9f %.17g %lu\n", elapsed, cost, (unsigned long)planner->numIterations());
    return 0;
}
"""


class Scene:
    """A heading scene as both sides see it: its raster, footprint cells and query in the raster's frame."""

    def __init__(self, name: str, motion: str) -> None:
        self.name, self.motion = name, motion
        self.world = navlab.load_world(name)
        self.radius = float(self.world.meta["turning_radius"])
        grid = rasterize(dataclasses.replace(self.world, robot_radius=0.0))  # as navlab.pose_queries does
        vertices, disc = robot_outline(query_footprint(self.world, None))
        self.lattice = lattice_for(tuple(map(tuple, vertices.tolist())), disc, self.radius, grid.resolution, 72,
                                   motion == "reeds_shepp", 0.0)
        self.grid = grid
        b = self.world.bounds
        self.eta = min(0.2 * math.hypot(b.xmax - b.xmin, b.ymax - b.ymin), 2.0 * self.radius)
        ox, oy, _ = grid.origin
        start, goal = query_poses(self.world)
        self.start = (start[0] - ox, start[1] - oy, start[2])
        self.goal = (goal[0] - ox, goal[1] - oy, goal[2])
        self.bounds = (b.xmin - ox, b.xmax - ox, b.ymin - oy, b.ymax - oy)
        self.file = os.path.join(tempfile.mkdtemp(prefix="navlab-se2-"), f"{name}.lattice")
        lat = self.lattice
        with open(self.file, "wb") as f:
            blocked = np.ascontiguousarray(grid.blocked | grid.unknown, dtype=np.uint8)
            f.write(struct.pack("<4q3d", grid.width, grid.height, lat.bins, len(lat.pose_cells), lat.resolution,
                                lat.theta0, lat.step))
            f.write(blocked.tobytes())
            f.write(np.ascontiguousarray(lat.pose_start, dtype=np.int64).tobytes())
            f.write(np.ascontiguousarray(lat.pose_cells, dtype=np.int64).tobytes())


def build_driver() -> Optional[str]:
    """The OMPL driver, built as bench_rrt_star builds its own (cached by source), or None with the reason printed."""
    import bench_rrt_star as r2

    try:
        return r2.build_driver(DRIVER_SOURCE, "se2_rrt_star_driver")
    except r2._BuildFailed:
        return None


class OmplCache:
    """OMPL's runs at equal iterations, kept in a JSON file between bench runs (``--ompl-cache``): they do not
    depend on navlab's code, and at 10⁵ iterations they take most of an hour (trap_car: ~170 s at 10⁴).
    Keyed by the driver binary (its name holds the hash of its source), scene, motion, seed and iterations;
    each entry keeps the load it was measured under. Budget runs (part 2) always run live."""

    def __init__(self, path: Optional[str]) -> None:
        import json

        self.path, self.entries = path, {}
        if path and os.path.exists(path):
            with open(path) as f:
                self.entries = json.load(f)
        self.hits = 0

    def run(self, binary: str, scene: Scene, seed: int, iterations: int):
        import json

        key = f"{binary}|{scene.name}|{scene.motion}|{seed}|{iterations}"
        if key in self.entries:
            self.hits += 1
            return tuple(self.entries[key][:3])
        result = run_ompl(binary, scene, seed, iterations=iterations)
        if self.path:
            self.entries[key] = [*result, os.getloadavg()[0]]
            with open(self.path, "w") as f:
                json.dump(self.entries, f, indent=0)
        return result


def run_ompl(binary: str, scene: Scene, seed: int, iterations: int = 0, seconds: float = 0.0):
    import subprocess

    args = [binary, scene.file, str(seed + 1), str(iterations), repr(seconds), repr(scene.eta), repr(scene.radius),
            "1" if scene.motion == "reeds_shepp" else "0", repr(scene.lattice.ds),
            *map(repr, (*scene.bounds, *scene.start, *scene.goal))]
    out = subprocess.run(args, capture_output=True, text=True, check=True).stdout.split()
    return float(out[0]), float(out[1]), int(out[2])


def run_navlab(scene: Scene, seed: int, iterations: int = 0, seconds: float = 0.0):
    kwargs = {"max_iter": iterations} if iterations else {"max_iter": 10_000_000, "max_time": seconds}
    r = navlab.plan(scene.name, planner="rrt_star", motion=scene.motion, seed=seed, **kwargs)
    return r.stats["time_s"], r.cost, r.stats["iterations"]


def speed(scenes: List[Scene], driver: Optional[str], sizes: List[int], runs: int, cache: OmplCache) -> None:
    print(f"\nPart 1: RRT* at equal iterations, median of {runs} runs (OMPL / navlab = × faster)")
    print(f"{'scene':14s} {'motion':12s} {'iterations':>10s} {'navlab s':>9s} {'OMPL s':>9s} {'× faster':>8s} "
          f"{'navlab cost':>11s} {'OMPL cost':>10s}")
    for scene in scenes:
        for n in sizes:
            ours, theirs = [], []
            for seed in range(runs):
                ours.append(run_navlab(scene, seed, iterations=n))
                if driver:
                    theirs.append(cache.run(driver, scene, seed, n))
            t_ours = statistics.median(t for t, _, _ in ours)
            c_ours = statistics.median(c for _, c, _ in ours)
            line = f"{scene.name:14s} {scene.motion:12s} {n:10d} {t_ours:9.3f} "
            if theirs:
                t_theirs = statistics.median(t for t, _, _ in theirs)
                c_theirs = statistics.median(c for _, c, _ in theirs)
                line += f"{t_theirs:9.3f} {t_theirs / t_ours:8.1f} {c_ours:11.3f} {c_theirs:10.3f}"
            else:
                line += f"{'-':>9s} {'-':>8s} {c_ours:11.3f} {'-':>10s}"
            print(line, flush=True)


def anytime(scenes: List[Scene], driver: Optional[str], budgets: List[float], runs: int) -> None:
    print(f"\nPart 2: RRT* at equal wall-clock budgets, {runs} runs: median gap to the best known cost (solved/runs)")
    print(f"{'scene':14s} {'budget s':>8s} {'navlab gap':>12s} {'OMPL gap':>12s}")
    for scene in scenes:
        best = BEST_KNOWN[scene.name]
        for budget in budgets:
            ours, theirs = [], []
            for seed in range(runs):
                ours.append(run_navlab(scene, seed, seconds=budget)[1])
                if driver:
                    theirs.append(run_ompl(driver, scene, seed, seconds=budget)[1])

            def gap(costs):
                solved = [c for c in costs if math.isfinite(c)]
                text = f"{100 * (statistics.median(costs) / best - 1):+.1f}%" if len(solved) > len(costs) / 2 \
                    else "no median"
                return f"{text} ({len(solved)}/{len(costs)})"

            print(f"{scene.name:14s} {budget:8.2f} {gap(ours):>12s} {gap(theirs) if theirs else '-':>12s}",
                  flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenes", default="trap_car,parking,narrow_aisle")
    parser.add_argument("--motion", default="reeds_shepp", choices=("reeds_shepp", "dubins"))
    parser.add_argument("--sizes", default="10000,100000", help="iteration counts of part 1")
    parser.add_argument("--runs", type=int, default=3, help="runs per cell of part 1")
    parser.add_argument("--budgets", default="0.2,1.0", help="seconds per run in part 2")
    parser.add_argument("--anytime-runs", type=int, default=10)
    parser.add_argument("--ompl-cache", metavar="FILE",
                        help="keep OMPL's part-1 runs in FILE (JSON) and reuse them from there (they do not depend "
                             "on navlab; the times are those of the run that stored them, under its load: OMPL's "
                             "narrow_aisle 10^5 took 64-89 s at load 6-8 and 29 s at load 2.7, so compare ratios only "
                             "against runs stored under a like load)")
    args = parser.parse_args()
    cache = OmplCache(args.ompl_cache)
    print(load_line("at start"))
    driver = build_driver()
    navlab.plan("trap_car", planner="rrt_star", motion=args.motion, max_iter=64)  # warm navlab's kernels
    scenes = [Scene(name, args.motion) for name in args.scenes.split(",") if name]
    sizes = [int(float(v)) for v in args.sizes.split(",") if v]
    if sizes:
        speed(scenes, driver, sizes, args.runs, cache)
        if cache.hits:
            print(f"({cache.hits} OMPL runs of part 1 reused from {args.ompl_cache})")
    budgets = [float(v) for v in args.budgets.split(",") if v]
    if budgets:
        anytime(scenes, driver, budgets, args.anytime_runs)
    print(load_line("at end"))


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    main()
