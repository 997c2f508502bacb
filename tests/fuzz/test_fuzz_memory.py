"""Requests too large for memory are refused with a ValueError naming the field, before allocating.

Each case runs in one child process under an address-space limit (so a failing
case gets a MemoryError instead of taking the machine's memory) with tracemalloc
measuring the peak Python/numpy allocation against ``MEMORY_BUDGET``.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

from fuzz.strategies import MEMORY_BUDGET

SRC = str(Path(__file__).resolve().parents[2] / "src")
ADDRESS_SPACE_LIMIT = 3 * 2**29  # [bytes] the child's virtual memory, 1.5 GiB (navlab itself maps ~0.5 GiB)


# name: (code run in the child with D = a folder of prepared files, the field the error must name, marks)
CASES = {
    "world file over the size limit": ("navlab.load_world(D / 'big.yaml')", "MiB", ()),
    "world file of 0.25 MiB": ("navlab.load_world(D / 'part.yaml')", None, ()),
    "max_iter 10**12": ("navlab.plan('clutter', 'rrt_star', max_iter=10**12)", "max_iter", ()),
    # With a time budget the arrays follow the tree grown, not max_iter: planned, within the budget.
    "max_iter 10**9 with max_time": ("navlab.plan('clutter', 'rrt_star', max_iter=10**9, max_time=0.5)", None, ()),
    "boundary directions 10**9": ("navlab.plan('clutter', 'rrt', sampler='boundary', max_iter=50, directions=10**9)",
                                  "directions", ()),
    "Moving AI width 10**11": ("load_map(D / 'wide.map')", "width", ()),
    # 10⁸ pixels is within MAX_CELLS; loading them needs more than the child's address space allows.
    "PNG of 100 megapixels": ("load_map(D / 'bomb.yaml')", "image", ()),
    # The logs grow with the run (which ends when the robot arrives), not with max_time.
    "simulated time 10**6 s": ("simulate('one_obstacle', max_time=1e6)", None, ()),
    # A sweep at the cell limit: 10 000 cells in one world (all pairs were 5·10⁷ comparisons, 7.8 GB).
    "bench summary of 10 000 cells": (
        "__import__('navlab.bench.analysis', fromlist=['summarize']).summarize(["
        "{'trial_id': f's{k}', 'cell_id': f's{k}', 'trial': 0, 'world': 'trap', 'planner': 'rrt_star', "
        "'sampler': f's{k}', 'status': 'EXACT', 'success': True, 'cost': 10.0 + k * 1e-6, 'cpu_s': 0.1} "
        "for k in range(10000)])", None, ()),
}

CHILD = r"""
import json, resource, sys, time, tracemalloc
from pathlib import Path
resource.setrlimit(resource.RLIMIT_AS, (int(sys.argv[2]), int(sys.argv[2])))
import navlab
from navlab.grid.mapio import load_map
from navlab.sim.runner import simulate
navlab.plan('clutter', 'rrt_star', max_iter=20)  # load the compiled kernels outside the measurement
D = Path(sys.argv[1])
for name, code in json.loads(sys.stdin.read()).items():
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        eval(code)
        row = {"outcome": "ok"}
    except BaseException as exc:
        row = {"outcome": "error", "type": type(exc).__name__, "value_error": isinstance(exc, ValueError),
               "message": str(exc)[:300]}
    row["peak"] = tracemalloc.get_traced_memory()[1]  # numpy reports a refused allocation too
    row["seconds"] = time.perf_counter() - t0
    tracemalloc.stop()
    print(json.dumps({name: row}), flush=True)
"""


def world_text(size):
    """A world file of about ``size`` bytes of circles."""
    head = "bounds: {x: [0, 100], y: [0, 100]}\nstart: [0, 0]\ngoal: [1, 1]\nobstacles:\n"
    line = "  - {type: circle, center: [%d.5, %d.5], radius: 0.1}\n"
    n = int(size / len(line % (50, 50)))
    return head + "".join(line % (i % 97, i % 89) for i in range(n))


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory):
    d = tmp_path_factory.mktemp("memory")
    (d / "part.yaml").write_text(world_text(0.25 * 2**20))
    (d / "big.yaml").write_text(world_text(1000) + "#" * (2 * 2**20))
    (d / "wide.map").write_text("type octile\nheight 1\nwidth 100000000000\nmap\n....\n")
    Image.new("1", (10000, 10000), 1).save(d / "bomb.png")
    (d / "bomb.yaml").write_text("image: bomb.png\nresolution: 0.05\norigin: [0, 0, 0]\n")
    env = {**os.environ, "PYTHONPATH": SRC, "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, "-c", CHILD, str(d), str(ADDRESS_SPACE_LIMIT)],
                          input=json.dumps({k: v[0] for k, v in CASES.items()}), capture_output=True, text=True,
                          env=env, timeout=600)
    rows = {}
    for line in proc.stdout.splitlines():
        rows.update(json.loads(line))
    assert rows, proc.stderr[-2000:]
    return rows


@pytest.mark.parametrize("name", [pytest.param(k, marks=v[2]) for k, v in CASES.items()])
def test_within_the_memory_budget(outcomes, name):
    row = outcomes[name]
    field = CASES[name][1]
    assert row["peak"] <= MEMORY_BUDGET, f"{name}: peak {row['peak'] / 2**20:.0f} MiB ({row})"
    if name == "world file of 0.25 MiB":  # an eighth of the 2 MiB limit: under an eighth of the budget
        assert row["outcome"] == "ok" and row["peak"] <= MEMORY_BUDGET / 8, row
    if name == "bench summary of 10 000 cells":  # summarised, not refused
        assert row["outcome"] == "ok", row
    if field is not None:
        assert row["outcome"] == "error" and row["value_error"] and field in row["message"], row
