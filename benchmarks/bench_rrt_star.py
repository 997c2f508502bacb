"""RRT* on `pythonrobotics` against OMPL's native C++ planners, side by side.

    apt-get install -y libompl-dev g++     # OMPL 1.5 headers and library (Debian)
    python benchmarks/bench_rrt_star.py                       # everything (about 15 min)
    python benchmarks/bench_rrt_star.py --sizes 5000,10000 --runs 5 --budgets 0.2

Part 1, speed: navlab's RRT* (uniform sampling) and OMPL's RRTstar run the
same scene for the same number of iterations with the same step (OMPL's
default range, 20% of the diagonal, which is also navlab's default
``expand_dis``). OMPL runs as a small C++ program built in this script's
set-up against the system's OMPL, with an exact validity checker (point in an
inflated circle) and an exact motion validator (segment–circle distance), as
navlab checks edges; every other OMPL setting is its default. Runs alternate
navlab / OMPL; the table gives medians, the ratio and microseconds per
iteration, and navlab's per-iteration time at the largest size over that at
10 000 iterations.

Part 2, anytime quality: navlab's RRT* and Informed RRT* against OMPL C++'s
RRTstar, InformedRRTstar and BITstar with the same wall-clock budgets (navlab's
clock includes its set-up, OMPL's covers ``solve`` only); median gap of the
returned path to the scene's optimum (21.9987 m) and how many runs found one.

Without a C++ compiler or OMPL's headers the OMPL columns are skipped with one
line. OMPL seeds its generator per process (the driver gets the run's seed).
"""

from __future__ import annotations

import argparse
import glob
import hashlib
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from typing import Dict, List, Optional, Tuple

import numpy as np

import navlab
from conditions import load_line, spread
from navlab.atomic import atomic_path
from navlab.world.geometry import point_segment_dist2

OPTIMUM = 21.9987  # issue 2: the true optimum of this scene

DRIVER_SOURCE = r"""
// OMPL 1.5 driver for bench_rrt_star.py: one planner, one query, exact checks.
#include <ompl/base/MotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace ob = ompl::base;
namespace og = ompl::geometric;

struct Circle { double x, y, r2; };  // r2: (radius + robot radius)^2
static std::vector<Circle> circles;

static double segment_dist2(double px, double py, double ax, double ay, double bx, double by) {
    double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy, t = 0.0;
    if (len2 > 0.0) {
        t = ((px - ax) * dx + (py - ay) * dy) / len2;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    }
    double ex = ax + t * dx - px, ey = ay + t * dy - py;
    return ex * ex + ey * ey;
}

static bool segment_free(double ax, double ay, double bx, double by) {
    for (const Circle &c : circles)
        if (segment_dist2(c.x, c.y, ax, ay, bx, by) < c.r2) return false;
    return true;
}

static const double *xy(const ob::State *s) { return s->as<ob::RealVectorStateSpace::StateType>()->values; }

class ExactMotionValidator : public ob::MotionValidator {
public:
    using ob::MotionValidator::MotionValidator;
    bool checkMotion(const ob::State *a, const ob::State *b) const override {
        bool ok = segment_free(xy(a)[0], xy(a)[1], xy(b)[0], xy(b)[1]);
        (ok ? valid_ : invalid_)++;
        return ok;
    }
    bool checkMotion(const ob::State *a, const ob::State *b, std::pair<ob::State *, double> &last) const override {
        bool ok = checkMotion(a, b);
        if (!ok) {
            if (last.first != nullptr) si_->copyState(last.first, a);
            last.second = 0.0;
        }
        return ok;
    }
};

int main(int argc, char **argv) {
    // planner seed iterations seconds range xmin xmax ymin ymax sx sy gx gy [cx cy r2]...
    if (argc < 14 || (argc - 14) % 3 != 0) { std::fprintf(stderr, "bad arguments\n"); return 2; }
    std::string name = argv[1];
    ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
    ompl::RNG::setSeed(std::strtoul(argv[2], nullptr, 10));
    unsigned long iterations = std::strtoul(argv[3], nullptr, 10);
    double seconds = std::atof(argv[4]), range = std::atof(argv[5]);
    double v[8];
    for (int i = 0; i < 8; ++i) v[i] = std::atof(argv[6 + i]);
    for (int i = 14; i < argc; i += 3) circles.push_back({std::atof(argv[i]), std::atof(argv[i + 1]), std::atof(argv[i + 2])});

    auto space = std::make_shared<ob::RealVectorStateSpace>(2);
    ob::RealVectorBounds bounds(2);
    bounds.setLow(0, v[0]); bounds.setHigh(0, v[1]);
    bounds.setLow(1, v[2]); bounds.setHigh(1, v[3]);
    space->setBounds(bounds);
    auto si = std::make_shared<ob::SpaceInformation>(space);
    si->setStateValidityChecker([](const ob::State *s) { return segment_free(xy(s)[0], xy(s)[1], xy(s)[0], xy(s)[1]); });
    si->setMotionValidator(std::make_shared<ExactMotionValidator>(si));
    si->setup();
    auto pdef = std::make_shared<ob::ProblemDefinition>(si);
    ob::ScopedState<> start(space), goal(space);
    start[0] = v[4]; start[1] = v[5]; goal[0] = v[6]; goal[1] = v[7];
    pdef->setStartAndGoalStates(start, goal, 1e-9);
    pdef->setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(si));

    std::shared_ptr<ob::Planner> planner;
    std::function<unsigned long()> count;
    if (name == "RRTstar" || name == "InformedRRTstar") {
        auto p = name == "RRTstar" ? std::make_shared<og::RRTstar>(si) : std::make_shared<og::InformedRRTstar>(si);
        p->setRange(range);
        count = [p] { return (unsigned long)p->numIterations(); };
        planner = p;
    } else if (name == "BITstar") {
        auto p = std::make_shared<og::BITstar>(si);
        count = [p] { return (unsigned long)p->numIterations(); };
        planner = p;
    } else { std::fprintf(stderr, "unknown planner %s\n", name.c_str()); return 2; }
    planner->setProblemDefinition(pdef);
    planner->setup();

    auto t0 = std::chrono::steady_clock::now();
    auto deadline = t0 + std::chrono::duration<double>(seconds > 0.0 ? seconds : 1e9);
    planner->solve(ob::PlannerTerminationCondition([&] {
        return (iterations > 0 && count() >= iterations) || std::chrono::steady_clock::now() >= deadline;
    }));
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double cost = INFINITY;
    if (pdef->hasExactSolution())
        cost = std::static_pointer_cast<og::PathGeometric>(pdef->getSolutionPath())->length();
    std::printf("%.9f %.17g %lu\n", elapsed, cost, count());
    return 0;
}
"""


def build_driver(source: str = DRIVER_SOURCE, name: str = "rrt_star_driver") -> Optional[str]:
    """Compile the OMPL driver (cached by its source); None, with one line
    saying why, when there is no compiler or no OMPL headers."""
    compiler = shutil.which(os.environ.get("CXX", "g++")) or shutil.which("c++")
    headers = sorted(glob.glob("/usr/include/ompl-*/ompl/geometric/planners/rrt/RRTstar.h")
                     + glob.glob("/usr/local/include/ompl-*/ompl/geometric/planners/rrt/RRTstar.h"))
    if compiler is None:
        print("OMPL C++ anchor skipped: no C++ compiler (g++ / c++) on PATH")
        return None
    if not headers:
        print("OMPL C++ anchor skipped: no OMPL headers (apt-get install libompl-dev)")
        return None
    include = headers[-1].split("/ompl/geometric/")[0]
    key = hashlib.sha1((source + compiler + include).encode()).hexdigest()[:12]
    folder = os.path.join(tempfile.gettempdir(), f"navlab-bench-ompl-{key}")
    binary = os.path.join(folder, name)
    if os.path.exists(binary):
        return binary
    os.makedirs(folder, exist_ok=True)
    source_file = os.path.join(folder, "driver.cpp")
    with open(source_file, "w") as f:
        f.write(source)
    with atomic_path(binary) as tmp:
        cmd = [compiler, "-O2", "-std=c++17", f"-I{include}", "-I/usr/include/eigen3", source_file, "-o", str(tmp),
               "-lompl"]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            print(f"OMPL C++ anchor skipped: the driver did not build ({done.stderr.strip().splitlines()[-1:]})")
            raise _BuildFailed
    return binary


class _BuildFailed(Exception):
    pass


def run_driver(binary: str, world, planner: str, seed: int, iterations: int = 0,
               seconds: float = 0.0) -> Tuple[float, float, int]:
    """(seconds in solve, path length or inf, iterations) of one OMPL run."""
    b = world.bounds
    args = [binary, planner, str(seed + 1), str(iterations), repr(seconds), repr(0.2 * b.diagonal),
            *map(repr, (b.xmin, b.xmax, b.ymin, b.ymax, *world.start, *world.goal))]
    for o in world.obstacles:
        args += [repr(o.center[0]), repr(o.center[1]), repr((o.radius + world.robot_radius) ** 2)]
    out = subprocess.run(args, capture_output=True, text=True, check=True).stdout.split()
    return float(out[0]), float(out[1]), int(out[2])


def exact_penetration(world, path: np.ndarray) -> float:
    """Deepest violation of the robot radius along a polyline (0 if none),
    by exact point–segment distance from every circle centre."""
    worst = 0.0
    for a, b in zip(path[:-1], path[1:]):
        for o in world.obstacles:
            gap = math.sqrt(point_segment_dist2(o.center[0], o.center[1], a[0], a[1], b[0], b[1]))
            worst = max(worst, o.radius + world.robot_radius - gap)
    return worst


def _ints(text: str) -> List[int]:
    return [int(float(v)) for v in text.split(",") if v]


def speed(world, driver: Optional[str], sizes: List[int], runs: List[int]) -> None:
    rows: Dict[int, Dict[str, list]] = {}
    for size, n_runs in zip(sizes, runs):
        rows[size] = {"navlab": [], "ompl": [], "clip": []}
        for seed in range(n_runs):
            r = navlab.plan(world, planner="rrt_star", sampler="uniform", seed=seed, max_iter=size)
            rows[size]["navlab"].append((r.stats["time_s"], r.cost))
            rows[size]["clip"].append(exact_penetration(world, r.path))
            if driver:
                t, c, its = run_driver(driver, world, "RRTstar", seed, iterations=size)
                assert its == size, (its, size)
                rows[size]["ompl"].append((t, c))
            print(f"  {size} iterations, run {seed + 1}/{n_runs} done", file=sys.stderr, flush=True)

    print(f"\nRRT*, uniform sampling, scene pythonrobotics (optimum {OPTIMUM} m); medians of runs alternating "
          "navlab / OMPL C++ (exact checkers)")
    print(f"{'iterations':>10} {'runs':>4} {'navlab ms':>10} {'OMPL C++ ms':>12} {'OMPL/navlab':>11} "
          f"{'range':>12} {'navlab us/it':>12} {'OMPL us/it':>10} {'navlab cost':>11} {'OMPL cost':>10}")
    per_it = {}
    for size, data in rows.items():
        t_nav = statistics.median(t for t, _ in data["navlab"])
        c_nav = statistics.median(c for _, c in data["navlab"])
        per_it[size] = t_nav / size
        line = f"{size:>10} {len(data['navlab']):>4} {t_nav * 1e3:>10.1f} "
        if data["ompl"]:
            t_ompl = statistics.median(t for t, _ in data["ompl"])
            c_ompl = statistics.median(c for _, c in data["ompl"])
            # the range of the per-run ratios (each OMPL run over the navlab run beside it)
            ratios = [o / n for (o, _), (n, _) in zip(data["ompl"], data["navlab"])]
            line += f"{t_ompl * 1e3:>12.1f} {t_ompl / t_nav:>10.2f}x {spread(ratios, 1, 'x'):>12} " \
                    f"{t_nav / size * 1e6:>12.2f} " \
                    f"{t_ompl / size * 1e6:>10.2f} {c_nav:>11.4f} {c_ompl:>10.4f}"
        else:
            line += f"{'-':>12} {'-':>11} {'-':>12} {t_nav / size * 1e6:>12.2f} {'-':>10} {c_nav:>11.4f} {'-':>10}"
        print(line)
        if max(data["clip"]) > 1e-9:
            print(f"  navlab paths clipping an obstacle at {size}: {max(data['clip']):.3g} m deep")
    if 10000 in per_it and max(sizes) > 10000:
        top = max(sizes)
        print(f"navlab time per iteration at {top} / at 10000 iterations: {per_it[top] / per_it[10000]:.2f}x")


def anytime(world, driver: Optional[str], budgets: List[float], n_runs: int) -> None:
    planners = ["rrt_star", "informed_rrt_star"] + ([f"ompl:{p}" for p in ("RRTstar", "InformedRRTstar", "BITstar")]
                                                    if driver else [])
    costs: Dict[Tuple[float, str], List[float]] = {(b, p): [] for b in budgets for p in planners}
    for budget in budgets:
        for seed in range(n_runs):
            for p in planners:
                if p.startswith("ompl:"):
                    c = run_driver(driver, world, p[5:], seed, seconds=budget)[1]
                else:
                    c = navlab.plan(world, planner=p, seed=seed, max_iter=10**12, max_time=budget).cost
                costs[budget, p].append(c)
            print(f"  anytime {budget} s, run {seed + 1}/{n_runs} done", file=sys.stderr, flush=True)
    print(f"\nAnytime quality on pythonrobotics: median gap to the optimum over {n_runs} runs (solved/runs)")
    print(f"{'planner':<22}" + "".join(f"{f'{b:g} s':>18}" for b in budgets))
    for p in planners:
        cells = []
        for b in budgets:
            found = [c for c in costs[b, p] if math.isfinite(c)]
            gap = 100 * (statistics.median(costs[b, p]) / OPTIMUM - 1) if len(found) * 2 > n_runs else math.inf
            cells.append(f"{gap:>+9.2f}% ({len(found)}/{n_runs})")
        print(f"{p:<22}" + "".join(f"{c:>18}" for c in cells))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="5000,10000,100000,1000000", help="iteration counts (comma-separated)")
    ap.add_argument("--runs", default="7,7,5,3", help="runs per size (one number for all, or one per size)")
    ap.add_argument("--budgets", default="0.2,1", help="anytime budgets in seconds ('' skips the part)")
    ap.add_argument("--anytime-runs", type=int, default=9)
    ap.add_argument("--no-ompl", action="store_true", help="navlab only")
    args = ap.parse_args()
    sizes, runs = _ints(args.sizes), _ints(args.runs)
    runs = runs * len(sizes) if len(runs) == 1 else runs
    if len(runs) != len(sizes):
        ap.error("--runs: give one number, or one per size")
    print(load_line("at start"))
    world = navlab.load_world("pythonrobotics")
    for planner in ("rrt_star", "informed_rrt_star"):
        navlab.plan(world, planner=planner, max_iter=200)  # compile / load the kernels first
    driver = None
    if not args.no_ompl:
        try:
            driver = build_driver()
        except _BuildFailed:
            driver = None
    if sizes:
        speed(world, driver, sizes, runs)
    budgets = [float(b) for b in args.budgets.split(",") if b]
    if budgets:
        anytime(world, driver, budgets, args.anytime_runs)
    print(load_line("at end"))


if __name__ == "__main__":
    main()
