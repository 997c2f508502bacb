"""Hybrid A*'s compiled set-up and finishing steps against plain Python doing the same (session 24 moved
them into compiled code to cut what a small query pays right after another program has run)."""

import math

import numpy as np
import pytest

from navlab.grid.hybrid_astar import _merged, _path_segments
from navlab.grid.hybrid_field import SETTLED, field_from_clearance
from navlab.sampling.curves import LEFT, NOP, RIGHT, STRAIGHT

from grid.test_hybrid_heuristic import heap_field  # tests/ is on the path (pyproject: pythonpath)


def merged_reference(kinds, lengths):
    """Consecutive segments of one kind and direction as one, in Python."""
    out = []
    for kind, length in zip(kinds.tolist(), lengths.tolist()):
        if out and out[-1][0] == kind and (out[-1][1] < 0) == (length < 0):
            out[-1] = (kind, out[-1][1] + length)
        else:
            out.append((kind, length))
    return out


def test_merging_segments_is_the_python_merge_bit_for_bit():
    rng = np.random.default_rng(24)
    for _ in range(500):
        n = int(rng.integers(0, 12))
        kinds = rng.choice([LEFT, STRAIGHT, RIGHT], n).astype(np.int64)
        lengths = rng.uniform(-2.0, 2.0, n) * rng.choice([1.0, 1.0, 0.0], n)  # zero lengths too
        got_kinds, got_lengths = _merged(kinds, lengths)
        assert list(zip(got_kinds.tolist(), got_lengths.tolist())) == merged_reference(kinds, lengths)


def test_the_path_segments_walk_the_parent_chain_then_the_tail():
    """A chain 0 <- 3 <- 5 <- 6 from start node 0 (joined by an arc) and an analytic tail with a NOP and a
    negligible segment, against the same walk in Python."""
    parent = np.array([-1, -1, 0, 0, 1, 3, 5])
    prim = np.array([-1, -1, 2, 1, 0, 2, 4])
    prim_kind = np.array([LEFT, STRAIGHT, RIGHT, LEFT, STRAIGHT, RIGHT], dtype=np.int64)
    prim_len = np.array([0.5, 0.4, 0.5, -0.5, -0.4, -0.5])
    akinds = np.array([RIGHT, STRAIGHT, NOP, LEFT, NOP], dtype=np.int64)
    alens = np.array([0.7, 1e-15, 0.0, -0.3, 0.0])
    for join_kind, last in (([LEFT, NOP], 6), ([NOP, NOP], 6), ([LEFT, NOP], 0), ([NOP, STRAIGHT], 1)):
        join_kind = np.array(join_kind, dtype=np.int64)
        join_len = np.array([0.01, 0.02])
        chain, v = [], last
        while parent[v] >= 0:
            chain.append(prim[v])
            v = parent[v]
        expected = [(join_kind[v], join_len[v])] if join_kind[v] != NOP else []
        expected += [(prim_kind[j], prim_len[j]) for j in reversed(chain)]
        expected += [(k, s) for k, s in zip(akinds, alens) if k != NOP and abs(s) > 1e-12]
        kinds, lengths = _path_segments(parent, prim, last, join_kind, join_len, prim_kind, prim_len, akinds, alens,
                                        1e-12)
        assert list(zip(kinds.tolist(), lengths.tolist())) == [(int(k), float(s)) for k, s in expected]


@pytest.mark.parametrize("seed", range(4))
def test_the_field_from_clearance_is_heap_dijkstra_over_the_clear_cells(seed):
    """The cells clear of ``limit`` and the goal's, and the value at the start cell and at every cell the wave
    settled on the way, against a heap Dijkstra in Python over those cells."""
    rng = np.random.default_rng(seed)
    clear = rng.uniform(0.0, 5.0, (30, 40))
    res, limit = 0.1, 0.1  # (four cells in five clear: the start is reached)
    gx, gy, sx, sy = 3, 4, 35, 25
    passable = clear * res > limit
    passable[gy, gx] = True
    truth = heap_field(passable, gx, gy, res)
    got_passable, state, dist, *_, at = field_from_clearance(clear, res, limit, gx, gy, sx, sy)
    assert np.array_equal(got_passable, passable)
    assert math.isfinite(at) and at == truth[sy, sx]
    inner = dist.reshape(32, 42)[1:-1, 1:-1]
    settled = (state.reshape(32, 42)[1:-1, 1:-1] & SETTLED) != 0
    assert settled.sum() > 10 and np.array_equal(inner[settled], truth[settled])
