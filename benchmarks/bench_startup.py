"""How long the navlab command takes to start, in fresh processes.

    python benchmarks/bench_startup.py            # 9 runs of each command
    python benchmarks/bench_startup.py --runs 21
    python benchmarks/bench_startup.py --phases   # where plan clutter's time goes, step by step
    python benchmarks/bench_startup.py --python /tmp/qs/bin/python   # another environment's navlab

The first line says which environment ran: its python, where its navlab
comes from (an installed copy, as `pip install .` gives a user, or an
editable source tree) and the .pth files its site-packages runs at every
start (a dev venv's editable finder and the ros2 extra's bootstrapper cost
each process time a user's plain install does not pay).

Each command runs in a new process (numba's cache warm: a first run compiles
and is dropped), alternating between commands; the table gives the median wall
time, its range and the goal, and the median CPU time (user + system) of the
process: on a shared machine the CPU time moves far less with the load than
the wall time does. Three floors run beside them: importing numpy; a process
that loads one cached numba function (numba's own start-up, which every
planning command pays, including numba's BLAS check importing scipy.linalg,
and the garbage collections over numba's objects when the process exits);
and the same done navlab's way: OpenBLAS on one thread (navlab.cli), SciPy's
BLAS module preloaded (navlab.numba_start), numba imported without PyYAML
and with importlib.metadata deferred (numba_start.import_numba_lean), the
cached function loaded without numba's typing and lowering registries
(numba_cached_loads.cached_loads_without_registries), the collector paused
(navlab.cli.plan) and the process ended at once after its work (navlab.cli).
The last lines are navlab's share above that floor. `python -X importtime -m navlab plan clutter` shows where an import's
time goes; tests/test_lazy_imports.py keeps the heavy modules out of
`navlab --help` and the unneeded ones out of `navlab plan clutter` (tests on
the import graph, not on time).
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

from conditions import load_line, spread

# The floors: what any program pays before navlab's own code runs. A process that
# loads one cached numba function pays numba's import and its target set-up (the
# code generator's registries, numba's BLAS check importing scipy.linalg; navlab's
# way: the runtime only), which every navlab command that plans pays too.
NUMBA_FLOOR = """
import sys
NAVLAB_WAY = "navlab" in sys.argv[1:]
if NAVLAB_WAY:  # what navlab plan does: BLAS on one thread, numba's BLAS check without scipy.linalg, no collections
    import atexit, gc, os
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as navlab.cli._one_blas_thread, without click's import
    from navlab.numba_start import preload_cython_blas
    preload_cython_blas()
    gc.disable()
    atexit.register(gc.freeze)
    from navlab.numba_start import import_numba_lean  # numba without PyYAML, importlib.metadata deferred
    import_numba_lean()
import numba
import numpy as np
if NAVLAB_WAY:  # and the cached function loads without numba's typing and lowering registries (navlab.cli.plan)
    from navlab.numba_cached_loads import cached_loads_without_registries
    cached_loads_without_registries()
@numba.njit(cache=True)
def one(x):
    return x[0] + 1.0
one(np.zeros(1))  # an array, like every navlab kernel's arguments (numba's typeof then imports numpy.ma)
if NAVLAB_WAY:  # and it ends at once (navlab.cli._exit_now): atexit handlers, no teardown
    atexit._run_exitfuncs()
    os._exit(0)
"""
# `--phases`: the steps of `navlab plan clutter` one by one, in the command's order and done its way (BLAS on one
# thread, SciPy's BLAS module preloaded, collector paused, ended at once), each timed in wall and CPU milliseconds;
# the exit is timed from the last line written to the process's end.
PHASES = """
import time
marks = [("", time.perf_counter(), time.process_time())]
def mark(name):
    marks.append((name, time.perf_counter(), time.process_time()))
import click, navlab.cli; mark("click, navlab.cli")
import os  # BLAS on one thread as navlab.cli._one_blas_thread does for the command (this -c process is not it)
if not any(name in os.environ for name in navlab.cli.BLAS_THREAD_SETTINGS):
    os.environ.update(OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
import numpy as np; mark("import numpy")
import navlab.cli.plan; mark("the plan verb")
import atexit, gc
gc.disable(); atexit.register(gc.freeze)
from navlab.numba_start import preload_cython_blas
preload_cython_blas(); mark("scipy (numba imports it) + cython_blas")
from navlab.numba_start import import_numba_lean
import_numba_lean(); mark("import numba, navlab's way")
import navlab.planning, navlab.world.sources; mark("navlab's modules (their numba dispatchers)")
from navlab.numba_cached_loads import cached_loads_without_registries
cached_loads_without_registries()
from navlab.world.sources import load_source
world = load_source("clutter"); mark("load_source clutter")
from navlab.endpoints import endpoint_problem
checker = world.checker()
endpoint_problem(world, world.start, "start", checker); mark("first kernel (numba's runtime) + endpoints")
from navlab.warmup import warm_up
warm_up("rrt_star", "uniform"); mark("warm-up (loads the tree kernels)")
from navlab.queries import tree_query
tree_query(world, "rrt_star", "uniform", 0, {}); mark("the query")
for (_, w0, c0), (name, w1, c1) in zip(marks, marks[1:]):
    print(f"{name}\t{(w1 - w0) * 1000:.1f}\t{(c1 - c0) * 1000:.1f}")
print(f"END\t{time.time():.6f}", flush=True)
navlab.cli._exit_now(0)  # as navlab plan ends when run as the command
"""
COMMANDS = [("navlab --help", ["-m", "navlab", "--help"], 0.3),
            ("navlab plan clutter", ["-m", "navlab", "plan", "clutter"], 0.8),
            ("navlab list planners", ["-m", "navlab", "list", "planners"], None),
            ("floor: import numpy", ["-c", "import numpy"], None),
            ("floor: one numba kernel", ["numba_floor.py"], None),
            ("floor: same, navlab's way", ["numba_floor.py", "navlab"], None)]


ENVIRONMENT = """
import glob, json, os, site, sys
import navlab
pth = sorted(os.path.basename(p) for d in site.getsitepackages() for p in glob.glob(os.path.join(d, "*.pth")))
print(json.dumps({"navlab": os.path.dirname(navlab.__file__), "pth": pth}))
"""


def environment_line(python: str) -> str:
    """Which environment is measured: its python, where its navlab comes from, the .pth files run at its start."""
    import json

    out = subprocess.run([python, "-c", ENVIRONMENT], capture_output=True, text=True, check=True, cwd=os.sep)
    found = json.loads(out.stdout)
    installed = any(part in found["navlab"] for part in ("site-packages", "dist-packages"))  # pip's; Debian's
    where = "installed" if installed else "source tree (editable or PYTHONPATH)"
    return (f"environment: {python}; navlab {where}: {found['navlab']}; "
            f".pth run at start: {', '.join(found['pth']) or 'none'}")


def run(python, args, folder) -> tuple[float, float]:
    """Wall seconds and CPU seconds (user + system) of one fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([python, *args], cwd=folder, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)  # one child at a time: the difference is its own
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def phases(python: str, runs: int) -> None:
    """Where `navlab plan clutter`'s time goes: median wall and CPU ms of each step over fresh processes."""
    rows: dict = {}
    totals, exits, starts = [], [], []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        out = subprocess.run([python, "-c", PHASES], capture_output=True, text=True, check=True, cwd=os.sep).stdout
        ended, wall = time.time(), time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        totals.append((wall * 1000, ((after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)) * 1000))
        inside = 0.0
        for line in out.strip().splitlines():
            name, *values = line.split("\t")
            if name == "END":  # the child's last line: what follows is its exit
                exits.append((ended - float(values[0])) * 1000)
            else:
                rows.setdefault(name, ([], []))
                rows[name][0].append(float(values[0]))
                rows[name][1].append(float(values[1]))
                inside += float(values[0])
        starts.append(wall * 1000 - inside - exits[-1])  # the rest: spawning, python's start, site
    print(f"\n{'step of navlab plan clutter':<48} {'wall ms':>8} {'CPU ms':>8}  (medians of {runs} fresh processes)")
    print(f"{'python start (site, .pth files; wall only)':<48} {statistics.median(starts):>8.0f} {'':>8}")
    for name, (wall, cpu) in rows.items():
        print(f"{name:<48} {statistics.median(wall):>8.0f} {statistics.median(cpu):>8.0f}")
    print(f"{'exit (atexit handlers, os._exit; wall only)':<48} {statistics.median(exits):>8.0f}")
    print(f"{'whole process':<48} {statistics.median([w for w, _ in totals]):>8.0f} "
          f"{statistics.median([c for _, c in totals]):>8.0f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=9, help="fresh processes per command (default 9); medians are printed")
    ap.add_argument("--phases", action="store_true",
                    help="time the steps of navlab plan clutter instead of the commands")
    ap.add_argument("--python", default=sys.executable,
                    help="the python of the environment to measure (default: this one), e.g. a venv with "
                         "`pip install .` as a user gets it")
    args = ap.parse_args()
    if os.sep in args.python:  # the processes run in a folder of their own: a relative path must not change meaning
        args.python = os.path.abspath(args.python)
    if not shutil.which(args.python):
        ap.error(f"--python {args.python}: no such program")
    print(load_line("at start"))
    print(environment_line(args.python))
    if args.phases:
        phases(args.python, args.runs)
        print(load_line("at end"))
        return
    times = {name: [] for name, _, _ in COMMANDS}
    cpu = {name: [] for name, _, _ in COMMANDS}
    with tempfile.TemporaryDirectory() as folder:
        with open(os.path.join(folder, "numba_floor.py"), "w", encoding="utf-8") as f:
            f.write(NUMBA_FLOOR)
        for _, argv, _ in COMMANDS:
            run(args.python, argv, folder)  # compile / fill the numba cache
        for _ in range(args.runs):
            for name, argv, _ in COMMANDS:
                wall, seconds = run(args.python, argv, folder)
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
    print("goal: the target for each command's median wall time on this 2-core machine (issue 19). "
          "floor rows: what numpy and numba alone cost; 'one numba kernel' is numba's own start-up done the usual "
          "way, and may take longer than navlab plan itself, which starts numba navlab's way (the row below it; "
          "--help of this script says what that way is)")
    print(load_line("at end"))


if __name__ == "__main__":
    main()
