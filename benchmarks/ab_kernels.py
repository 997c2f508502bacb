"""Paired in-process A/B of two versions of navlab's grid kernels (``grid/kernels.py``).

    git show abd3c7c:src/navlab/grid/kernels.py > /tmp/old_kernels.py
    python benchmarks/ab_kernels.py /tmp/old_kernels.py src/navlab/grid/kernels.py --queries 21
    python benchmarks/ab_kernels.py OLD NEW --algorithm jps --loose   # a change that alters expansions

Both files are loaded into one process (numba's disk cache off, so neither
reuses the other's compiled code) and run the same corner-to-corner query on
issue 22's maps (4096 x 4096, 20 % random obstacles; a 1001 x 1001 maze),
alternating query by query, old first in every other pair. Each version keeps
its own search state, so every timed query after the first is a repeat query
(the state cleared of what the previous one wrote). Printed: each version's
median CPU time and the median and quartiles of the per-pair ratios new/old.
On this 2-core shared VM two copies of one file measure 1.00 with quartiles
0.998-1.005, where medians from separate processes moved by 20 % in a day.

Before timing, the two versions' answers are compared: the same status and
expansions and the same search state bit for bit (or, when one packs A*'s
state and the other keeps float64, the same cells closed and reached with the
same g to 1e-10 relative), or with ``--loose`` only the same goal cost (for changes that
expand other nodes).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import re
import statistics
import sys
import tempfile
import time

import numpy as np


def load_kernels(path: str, name: str):
    """The kernels module at ``path``, imported as ``name`` with numba's caching off."""
    # A copy outside the package cannot use its relative imports (``from ..jit import njit``, since the
    # kernels take numba's njit from navlab.jit): name them absolutely, at the start of a line only.
    source = open(path).read().replace("cache=True", "cache=False")
    source = re.sub(r"^(\s*)from \.\.(?=\w)", r"\1from navlab.", source, flags=re.M)
    source = re.sub(r"^(\s*)from \.(?=\w)", r"\1from navlab.grid.", source, flags=re.M)
    source = re.sub(r"^(\s*)from \. import", r"\1from navlab.grid import", source, flags=re.M)
    copy = os.path.join(tempfile.mkdtemp(), name + ".py")
    with open(copy, "w") as f:
        f.write(source)
    spec = importlib.util.spec_from_file_location(name, copy)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def issue22_maps():
    """(name, blocked cells) of bench_grid.py's --large maps (4096² random 20 %, the 1001² maze)."""
    from bench_grid import _large_maps

    for name, make in _large_maps():
        yield name.split("-")[0], make().blocked


def in_strips(module, algorithm: str) -> bool:
    """Whether ``module``'s ``algorithm`` searches the strip layout (A* and Dijkstra since session 28)."""
    return algorithm != "jps" and hasattr(module, "strip_shape")


def strip_layout(module, grid):
    """``(bits, SH, size, moves)``: ``module``'s strip layout of ``grid`` and its legal moves in it, built
    by the module's own ``legal_moves`` (once per grid and module)."""
    cache = vars(grid).setdefault("_ab_layouts", {})
    if module.__name__ not in cache:
        bits, SH, size = module.strip_shape(grid.rows, grid.stride)
        moves = module.legal_moves(grid.blocked, np.zeros((0, 0), bool), np.empty(size, np.uint8), bits)
        cache[module.__name__] = bits, SH, size, moves
    return cache[module.__name__]


def state_array(module, algorithm: str, grid) -> np.ndarray:
    """The per-cell state ``module``'s ``algorithm`` searches in: packed (``state_layout``: A* and
    Dijkstra since session 19, JPS with ``make_jps``) or one float64 per cell (older kernels), in the
    strip layout or in padded rows (:func:`in_strips`)."""
    cells = strip_layout(module, grid)[2] if in_strips(module, algorithm) else grid.rows * grid.stride
    if hasattr(module, "make_jps" if algorithm == "jps" else "state_layout"):
        return np.zeros(cells, dtype=module.state_layout(False)[0])
    return np.zeros(cells)


def state_rows(module, algorithm: str, grid, state: np.ndarray) -> np.ndarray:
    """``state`` in padded rows, flat, whichever layout ``module`` searched it in."""
    if in_strips(module, algorithm):
        return module.to_rows(state, grid.rows, grid.stride).ravel()
    return state


def state_costs(module, state: np.ndarray):
    """(closed mask, g) of a search's state, as ``module`` packs it."""
    if hasattr(module, "state_costs"):
        return module.state_costs(state)
    return state < 0, np.where(state == 0, np.inf, np.abs(state) - 1.0)


def searcher_call(module, algorithm: str):
    """``call(searcher, state, start, goal)``: one search with ``module``'s kernel on a searcher's arrays
    and ``state`` (:func:`state_array`), returning (status, expanded). A* is compiled once here (each
    make_astar call makes a new kernel)."""
    if algorithm == "jps":
        jps = module.make_jps(False) if hasattr(module, "make_jps") else module.jps
        return lambda g, state, start, goal: jps(g.grid.moves, g.stride, g.grid.index(*start), g.grid.index(*goal),
                                                 state, g.lo, g.hi, g.extent, g.key, g.cell, g.next, g.head, g.stack)
    kernel = module.make_astar(8, 4 if algorithm == "astar" else 0, False)
    if in_strips(module, algorithm):
        flags = {}  # the blocks each searcher's state holds, in the module's layout

        def call(g, state, start, goal):
            bits, SH, size, moves = strip_layout(module, g.grid)
            marks = flags.setdefault(id(g), np.zeros(-(-size >> module.BLOCK_BITS), np.uint8))
            a, b = (module.strip_index(x + 1, y + 1, SH, bits) for x, y in (start, goal))
            return kernel(g.grid.no_free, g.stride, moves, SH, bits, a, b, 1.0, state, g.parent, marks, g.key,
                          g.cell, g.next, g.head, g.stack)
        return call
    return lambda g, state, start, goal: kernel(  # (older kernels: padded rows)
        g.grid.no_free, g.grid.moves, g.stride, g.grid.index(*start),
        g.grid.index(*goal), 1.0, state, g.parent, g.lo, g.hi, g.extent, g.key, g.cell, g.next, g.head, g.stack)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old", help="the kernels.py to compare against")
    ap.add_argument("new", help="the kernels.py being measured")
    ap.add_argument("--queries", type=int, default=21, help="timed pairs per map (default 21)")
    ap.add_argument("--algorithm", choices=("astar", "dijkstra", "jps"), default="astar")
    ap.add_argument("--loose", action="store_true", help="compare only the goal cost, not expansions and state")
    args = ap.parse_args()
    if args.queries < 1:
        ap.error("--queries must be at least 1")
    for path in (args.old, args.new):
        if not os.path.isfile(path):
            ap.error(f"{path}: not a file")

    import bench_grid

    from navlab.grid.planner import GridSearcher, PaddedGrid

    versions = {}
    for tag, path in (("old", args.old), ("new", args.new)):
        try:
            versions[tag] = load_kernels(path, f"kernels_{tag}")
        except Exception as exc:  # noqa: BLE001 - any file that does not import is the same answer
            ap.error(f"{path}: not a grid kernels file ({type(exc).__name__}: {exc})")
        if not hasattr(versions[tag], "make_astar") or not any(hasattr(versions[tag], f) for f in ("make_jps", "jps")):
            ap.error(f"{path}: not a grid kernels file (no make_astar and make_jps or jps)")
    calls = {tag: searcher_call(module, args.algorithm) for tag, module in versions.items()}
    for name, blocked in issue22_maps():
        free = np.argwhere(~blocked)
        grid = PaddedGrid(blocked)
        start, goal = bench_grid.corners(free)  # cells (x, y): each call indexes its layout
        searchers, states, answers = {}, {}, {}
        for tag, module in versions.items():
            searchers[tag] = GridSearcher(grid)
            states[tag] = state_array(module, args.algorithm, grid)
            answer = calls[tag](searchers[tag], states[tag], start, goal)
            while answer[0] == module.OVERFLOW:
                searchers[tag].grow()
                answer = calls[tag](searchers[tag], states[tag], start, goal)
            answers[tag] = answer
        rows = {tag: state_rows(versions[tag], args.algorithm, grid, states[tag]) for tag in versions}
        decoded = {tag: state_costs(versions[tag], rows[tag]) for tag in versions}
        costs = {tag: float(g[grid.index(*goal)]) for tag, (_, g) in decoded.items()}
        if args.loose:
            if answers["old"][0] != answers["new"][0] or abs(costs["old"] - costs["new"]) > 1e-9 * max(1.0, costs["old"]):
                sys.exit(f"{name}: the versions disagree: {answers} costs {costs}")
        elif answers["old"] != answers["new"] or not _same_state(rows, decoded):
            sys.exit(f"{name}: the versions disagree (status, expanded: {answers}); rerun with --loose if meant")
        times = {"old": [], "new": []}
        ratios = []
        for k in range(args.queries):
            took = {}
            for tag in (("old", "new") if k % 2 == 0 else ("new", "old")):
                t0 = time.thread_time()
                calls[tag](searchers[tag], states[tag], start, goal)
                took[tag] = time.thread_time() - t0
                times[tag].append(took[tag])
            ratios.append(took["new"] / took["old"])
        q1, q3 = np.percentile(ratios, [25, 75])
        print(f"{args.algorithm} {name}: old {1e3 * statistics.median(times['old']):.1f} ms, "
              f"new {1e3 * statistics.median(times['new']):.1f} ms CPU; new/old {statistics.median(ratios):.3f} "
              f"(quartiles {q1:.3f}-{q3:.3f}, {args.queries} pairs); expanded {answers['old'][1]} -> "
              f"{answers['new'][1]}, goal cost {costs['new']:.9f}")


def _same_state(states, decoded) -> bool:
    """The two versions' states equal: bit for bit if they pack it alike, else the same cells closed
    and reached with the same g (to 1e-10 relative: a float64 state sums its floats, and over the
    21 000 moves of maze1001's path that drifts by about 1e-8)."""
    if states["old"].dtype == states["new"].dtype:
        return np.array_equal(states["old"], states["new"])
    (closed_old, g_old), (closed_new, g_new) = decoded["old"], decoded["new"]
    reached = np.isfinite(g_old)
    return (np.array_equal(closed_old, closed_new) and np.array_equal(reached, np.isfinite(g_new))
            and np.allclose(g_old[reached], g_new[reached], rtol=1e-10, atol=1e-9))


if __name__ == "__main__":
    main()
