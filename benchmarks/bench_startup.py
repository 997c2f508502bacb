"""How long the navlab command takes to start, in fresh processes.

    python benchmarks/bench_startup.py            # 9 runs of each command
    python benchmarks/bench_startup.py --runs 21

Each command runs in a new process (numba's cache warm: a first run compiles
and is dropped), alternating between commands; the table gives the median wall
time, its range and the goal, and the median CPU time (user + system) of the
process: on a shared machine the CPU time moves far less with the load than
the wall time does. Three floors run beside them: importing numpy; a process
that loads one cached numba function (numba's own start-up, which every
planning command pays, including numba's BLAS check importing scipy.linalg,
and the garbage collections over numba's objects when the process exits);
and the same done navlab's way: SciPy's BLAS module preloaded
(navlab.numba_start) and the objects frozen at exit (navlab.cli). The last
lines are navlab's share above that floor. `python -X importtime -m navlab plan clutter` shows where an import's
time goes; tests/test_lazy_imports.py keeps the heavy modules out of
`navlab --help` and the unneeded ones out of `navlab plan clutter` (tests on
the import graph, not on time).
"""

from __future__ import annotations

import argparse
import os
import resource
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
import sys
if "navlab" in sys.argv[1:]:  # what navlab does: numba's BLAS check without scipy.linalg, no collection at exit
    import atexit, gc
    from navlab.numba_start import preload_cython_blas
    preload_cython_blas()
    atexit.register(gc.freeze)
import numba
import numpy as np
@numba.njit(cache=True)
def one(x):
    return x[0] + 1.0
one(np.zeros(1))  # an array, like every navlab kernel's arguments (numba's typeof then imports numpy.ma)
"""
COMMANDS = [("navlab --help", ["-m", "navlab", "--help"], 0.3),
            ("navlab plan clutter", ["-m", "navlab", "plan", "clutter"], 0.8),
            ("navlab list planners", ["-m", "navlab", "list", "planners"], None),
            ("floor: import numpy", ["-c", "import numpy"], None),
            ("floor: one numba kernel", ["numba_floor.py"], None),
            ("floor: same, navlab's way", ["numba_floor.py", "navlab"], None)]


def run(args, folder) -> tuple[float, float]:
    """Wall seconds and CPU seconds (user + system) of one fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, *args], cwd=folder, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)  # one child at a time: the difference is its own
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=9)
    args = ap.parse_args()
    print(load_line("at start"))
    times = {name: [] for name, _, _ in COMMANDS}
    cpu = {name: [] for name, _, _ in COMMANDS}
    with tempfile.TemporaryDirectory() as folder:
        with open(os.path.join(folder, "numba_floor.py"), "w", encoding="utf-8") as f:
            f.write(NUMBA_FLOOR)
        for _, argv, _ in COMMANDS:
            run(argv, folder)  # compile / fill the numba cache
        for _ in range(args.runs):
            for name, argv, _ in COMMANDS:
                wall, seconds = run(argv, folder)
                times[name].append(wall)
                cpu[name].append(seconds)
    print(f"\n{'command':<28} {'median':>8} {'range':>14} {'goal':>6}  {'CPU':>7} {'range':>14}  "
          f"({args.runs} fresh processes each, {os.cpu_count()} cores)")
    for name, _, goal in COMMANDS:
        median = statistics.median(times[name])
        verdict = "" if goal is None else ("  met" if median < goal else "  NOT met")
        print(f"{name:<28} {median:>7.3f}s {spread(times[name], 2, ' s'):>14} "
              f"{'' if goal is None else f'{goal:.1f}s':>6}  {statistics.median(cpu[name]):>6.3f}s "
              f"{spread(cpu[name], 2, ' s'):>14}{verdict}")
    for what, table in (("wall", times), ("CPU", cpu)):
        share = statistics.median(table["navlab plan clutter"]) - statistics.median(table["floor: same, navlab's way"])
        print(f"navlab plan clutter above the numba floor done navlab's way ({what}): {share:.3f} s")
    print(load_line("at end"))


if __name__ == "__main__":
    main()
