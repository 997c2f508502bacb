"""How long the navlab command takes to start, in fresh processes.

    python benchmarks/bench_startup.py            # 9 runs of each command
    python benchmarks/bench_startup.py --runs 21

Each command runs in a new process (numba's cache warm: a first run compiles
and is dropped), alternating between commands; the table gives the median, the
range and the goal. Two floors run beside them: importing numpy, and a process
that loads one cached numba function (numba's own start-up, which every
planning command pays); the last line is navlab's share above that floor. `python -X importtime -c "import navlab.cli"` shows where
an import's time goes; tests/test_lazy_imports.py keeps the heavy modules out
of `navlab --help` (a test on the import graph, not on time).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

from conditions import load_line, spread

# The floors: what any program pays before navlab's own code runs. A process that
# loads one cached numba function pays numba's import and its target set-up (the
# code generator's registries, numba's BLAS check importing scipy.linalg), which
# every navlab command that plans pays too.
NUMBA_FLOOR = """
import numba
@numba.njit(cache=True)
def one(x):
    return x + 1
one(1)
"""
COMMANDS = [("navlab --help", ["-m", "navlab", "--help"], 0.3),
            ("navlab plan clutter", ["-m", "navlab", "plan", "clutter"], 0.8),
            ("navlab list planners", ["-m", "navlab", "list", "planners"], None),
            ("floor: import numpy", ["-c", "import numpy"], None),
            ("floor: one numba kernel", ["numba_floor.py"], None)]


def run(args, folder) -> float:
    t0 = time.perf_counter()
    subprocess.run([sys.executable, *args], cwd=folder, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=9)
    args = ap.parse_args()
    print(load_line("at start"))
    times = {name: [] for name, _, _ in COMMANDS}
    with tempfile.TemporaryDirectory() as folder:
        with open(os.path.join(folder, "numba_floor.py"), "w", encoding="utf-8") as f:
            f.write(NUMBA_FLOOR)
        for _, argv, _ in COMMANDS:
            run(argv, folder)  # compile / fill the numba cache
        for _ in range(args.runs):
            for name, argv, _ in COMMANDS:
                times[name].append(run(argv, folder))
    print(f"\n{'command':<24} {'median':>8} {'range':>14} {'goal':>6}  ({args.runs} fresh processes each, "
          f"{os.cpu_count()} cores)")
    for name, _, goal in COMMANDS:
        median = statistics.median(times[name])
        verdict = "" if goal is None else ("  met" if median < goal else "  NOT met")
        print(f"{name:<24} {median:>7.3f}s {spread(times[name], 2, ' s'):>14} "
              f"{'' if goal is None else f'{goal:.1f}s':>6}{verdict}")
    floor = statistics.median(times["floor: one numba kernel"])
    print(f"navlab plan clutter above the numba floor: {statistics.median(times['navlab plan clutter']) - floor:.3f} s")
    print(load_line("at end"))


if __name__ == "__main__":
    main()
