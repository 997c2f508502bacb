"""`navlab plan clutter` loads few compiled entry points from numba's cache (each is read, unpickled and
linked apart in a fresh process): which ones is asserted on numba's own cache log (NUMBA_DEBUG_CACHE),
not on time. The bucket grid's one build kernel (it was two entry points) is checked against the
layout written out with numpy."""

import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from navlab.sampling import bucket_grid as G
from navlab.world import Bounds

#: the entry points a tree query on a built-in scene loads: the endpoints' check, the goal bookkeeping,
#: the bucket grid's build and the tree loop (everything else is inlined or called from compiled code)
PLAN_CLUTTER_ENTRY_POINTS = {"geometry.points_free_batch", "tree_kernel.add_goal_candidate", "bucket_grid._build",
                             "tree_kernel.grow"}


def test_plan_clutter_loads_only_its_entry_points():
    env = dict(os.environ, NUMBA_DEBUG_CACHE="1")
    args = [sys.executable, "-m", "navlab", "plan", "clutter", "--max-iter", "50"]
    subprocess.run(args, capture_output=True, timeout=300, env={k: v for k, v in env.items()
                                                                if k != "NUMBA_DEBUG_CACHE"})  # fills the cache
    out = subprocess.run(args, capture_output=True, text=True, timeout=300, env=env)
    assert out.returncode == 0, out.stderr
    loaded = set(re.findall(r"data loaded from '.*[/\\]([\w.]+)-\d+\.py\d+\.\d+\.nbc'", out.stdout + out.stderr))
    assert loaded == PLAN_CLUTTER_ENTRY_POINTS


def reference_layout(xy, cost, n, expected, bounds):
    """The grid's arrays as the bucket grid's documentation defines them, with numpy: each node in the
    cell its coordinates fall in (clamped to the border cells), blocks in cell order sized
    ceil(count * expected / n) + BLOCK_SLACK, nodes in index order within a block."""
    h, nx, ny = G.grid_shape(bounds, expected)
    gparams = G.grid_params(bounds, h)

    def index(v, v0, count):
        c = (v - v0) * gparams[G.G_INV_H]
        return np.where(c >= count - 1, count - 1, np.where(c >= 0.0, np.floor(np.where(c >= 0.0, c, 0.0)), 0))

    cells = (index(xy[:n, 1], bounds.ymin, ny) * nx + index(xy[:n, 0], bounds.xmin, nx)).astype(np.int64)
    counts = np.bincount(cells, minlength=nx * ny)
    room = np.array([math.ceil(c * (expected / max(n, 1))) for c in counts], dtype=np.int64) + G.BLOCK_SLACK
    start = np.concatenate([[0], np.cumsum(room)])
    slots = np.empty(n, dtype=np.int64)
    for cell in range(nx * ny):
        members = np.flatnonzero(cells == cell)  # index order
        slots[members] = start[cell] + np.arange(len(members))
    coarse = np.zeros(-(-nx // G.COARSE) * -(-ny // G.COARSE), dtype=np.int64)
    np.add.at(coarse, (cells // nx) // G.COARSE * -(-nx // G.COARSE) + (cells % nx) // G.COARSE, 1)
    return start, counts, slots, coarse


@pytest.mark.parametrize("seed, n, expected", [(0, 1, 1), (1, 50, 100), (2, 700, 1400), (3, 333, 333)])
def test_the_build_kernel_lays_out_the_grid_as_documented(seed, n, expected):
    rng = np.random.default_rng(seed)
    bounds = Bounds(-2.0, 13.0, 1.0, 9.0)
    xy = rng.uniform([-4.0, -1.0], [15.0, 11.0], size=(expected, 2))  # some outside the bounds: border cells
    cost = rng.uniform(0.0, 20.0, size=expected)
    next_node = np.full(expected, -1, dtype=np.int64)
    slot = np.full(expected, -1, dtype=np.int64)
    grid = G.BucketGrid(bounds)
    grid.rebuild(xy, cost, next_node, slot, n, expected)
    meta, block, block_id, _, got_slot, _, _, coarse = grid.arrays
    start, counts, slots, want_coarse = reference_layout(xy, cost, n, expected, bounds)
    np.testing.assert_array_equal(meta[:, G.M_START], start)
    np.testing.assert_array_equal(meta[:-1, G.M_FILL], start[:-1] + counts)  # every node in its block
    assert (meta[:, G.M_HEAD] == -1).all() and (next_node == -1).all()  # no overflow
    np.testing.assert_array_equal(got_slot[:n], slots)
    np.testing.assert_array_equal(block_id[slots], np.arange(n))
    np.testing.assert_array_equal(block[slots], np.column_stack([xy[:n], cost[:n]]))
    np.testing.assert_array_equal(coarse, want_coarse)
