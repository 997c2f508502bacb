"""Hybrid A*'s footprint lattice against its plain construction: every bin and
primitive traced and its cells found directly, no quarter-turn reuse."""

import math

import numpy as np
import pytest

from navlab.sampling.curves import trace_word
from navlab.sampling.footprint_lattice import Lattice, _cells_touched

OUTLINES = {
    "car": ([[-1.0, -1.0], [3.3, -1.0], [3.3, 1.0], [-1.0, 1.0]], 0.0, 4.385, 1.0),
    "small car": ([[-0.25, -0.2], [0.25, -0.2], [0.25, 0.2], [-0.25, 0.2]], 0.0, 0.4, 0.05),
    "skew triangle": ([[-0.3, -0.2], [0.5, 0.05], [-0.1, 0.3]], 0.0, 0.7, 0.04),
    "disc": ([], 0.3, 0.5, 0.05),
}


def cell_set(cells):
    return {tuple(c) for c in cells.tolist()}


@pytest.mark.parametrize("name", sorted(OUTLINES))
@pytest.mark.parametrize("bins", [72, 16, 18])
def test_the_lattice_cells_are_those_traced_at_every_bin(name, bins):
    vertices, disc, radius, res = OUTLINES[name]
    verts = np.array(vertices, float).reshape(-1, 2)
    for theta0 in (0.0, 0.3, -2.1):
        lattice = Lattice(tuple(map(tuple, vertices)), disc, radius, res, bins, True, theta0)
        reach, diag = lattice.circumscribed, math.sqrt(2.0) * res
        nprim = len(lattice.prim_kind)
        pose_margin = diag + 0.5 * lattice.delta + reach * math.sin(lattice.step / 2.0)
        for b in range(bins):
            theta = theta0 + b * lattice.step
            pose = _cells_touched(verts, disc, reach, np.array([[0.0, 0.0, theta]]), pose_margin, res)
            assert cell_set(lattice.pose_cells[lattice.pose_start[b]:lattice.pose_start[b + 1]]) == cell_set(pose)
            for j in range(nprim):
                poses, _ = trace_word(0.0, 0.0, theta, lattice.prim_kind[j:j + 1], lattice.prim_len[j:j + 1],
                                      radius, lattice.ds)
                assert (lattice.dx[b, j], lattice.dy[b, j]) == (poses[-1, 0], poses[-1, 1])
                cells = _cells_touched(verts, disc, reach, poses, diag + 0.5 * lattice.delta, res)
                got = lattice.swept(b, j)
                assert cell_set(got) == cell_set(cells), (b, j)
                distance = got[:, 0] ** 2 + got[:, 1] ** 2
                assert (np.diff(distance) <= 0).all(), "outermost first"


@pytest.mark.parametrize("name", ["car", "skew triangle", "disc"])
def test_the_cells_touched_are_those_shapely_finds_near_the_outline(name):
    """Every cell whose centre lies within the margin of the outline at some traced pose, by shapely over a
    window wider than the motion, and no other."""
    import shapely

    vertices, disc, radius, res = OUTLINES[name]
    verts = np.array(vertices, float).reshape(-1, 2)
    lattice = Lattice(tuple(map(tuple, vertices)), disc, radius, res, 16, True, 0.4)
    margin = math.sqrt(2.0) * res + 0.5 * lattice.delta
    span = int((lattice.circumscribed + margin + lattice.length) / res) + 3
    ix, iy = np.meshgrid(np.arange(-span, span + 1), np.arange(-span, span + 1))
    centres = shapely.points(ix.ravel() * res, iy.ravel() * res)
    for b in range(16):
        for j in range(len(lattice.prim_kind)):
            poses, _ = trace_word(0.0, 0.0, 0.4 + b * lattice.step, lattice.prim_kind[j:j + 1],
                                  lattice.prim_len[j:j + 1], radius, lattice.ds)
            near = np.zeros(centres.shape, bool)
            for x, y, th in poses:
                if len(verts):
                    c, s = math.cos(th), math.sin(th)
                    shape = shapely.Polygon(np.column_stack([x + c * verts[:, 0] - s * verts[:, 1],
                                                             y + s * verts[:, 0] + c * verts[:, 1]]))
                    near |= shapely.dwithin(shape, centres, margin)
                else:
                    near |= shapely.dwithin(shapely.Point(x, y), centres, disc + margin)
            expected = set(zip(ix.ravel()[near].tolist(), iy.ravel()[near].tolist()))
            got = _cells_touched(verts, disc, lattice.circumscribed, poses, margin, res)
            assert cell_set(got) == expected, (b, j)


def test_the_search_swept_check_answers_as_reading_every_cell():
    """The search stops reading a primitive's cells at the first one nearer than the nearest blocked
    cell; its answers must be free_cells' (every cell read) on random maps, at every cell and primitive."""
    from navlab.grid.hybrid_astar import _nearest_blocked2
    from navlab.grid.hybrid_search import _swept_free
    from navlab.sampling.footprint_lattice import free_cells

    rng = np.random.default_rng(8)
    vertices, disc, radius, res = OUTLINES["small car"]
    lattice = Lattice(tuple(map(tuple, vertices)), disc, radius, res, 16, True, 0.2)
    groups = [lattice.swept(b, j) for b in range(16) for j in range(len(lattice.prim_kind))]
    for density in (0.002, 0.01, 0.05):
        blocked = rng.random((40, 50)) < density
        near2 = _nearest_blocked2(blocked)
        for cy in range(0, 40, 3):
            for cx in range(0, 50, 3):
                for cells in groups:
                    assert _swept_free(blocked, near2, cx, cy, cells, 0, len(cells)) == \
                        free_cells(blocked, cx, cy, cells, 0, len(cells))


def test_the_swept_cells_a_search_builds_are_those_asked_for_later():
    """The search builds swept cells as it needs them into the cached lattice's table; the groups it
    built, and the ones asked for afterwards in another order, are those of a lattice built apart."""
    from navlab.grid.hybrid_astar import plan_hybrid
    from navlab.grid.occupancy import OccupancyGrid
    from navlab.sampling.footprint_lattice import lattice_for

    vertices, disc, radius, res = OUTLINES["small car"]
    blocked = np.zeros((60, 80), bool)
    blocked[:40, 40:42] = True
    lattice_for.cache_clear()
    result = plan_hybrid(OccupancyGrid(blocked, resolution=res), (0.5, 0.5, 0.3), (3.5, 0.5, -1.0), radius,
                         footprint=vertices)
    assert result.success
    nprim = 6
    # (every query of a robot searches the lattice of headings k·2π/72, joined from its start heading by an arc)
    lattice = lattice_for(tuple(map(tuple, vertices)), disc, radius, res, 72, True, 0.0)
    built = lattice._swept_table[2] >= 0
    assert 0 < built.sum() < 72 * nprim  # the search asked for some groups, not all
    fresh = Lattice(tuple(map(tuple, vertices)), disc, radius, res, 72, True, 0.0)
    for k in reversed(range(72 * nprim)):
        b, j = divmod(k, nprim)
        assert np.array_equal(lattice.swept(b, j), fresh.swept(b, j)), (b, j)


def test_the_nearest_blocked_distances_count_the_map_edge_as_blocked():
    """One transform and the distance to the edge give what a transform of the map ringed by blocked cells gives."""
    from scipy.ndimage import distance_transform_edt

    from navlab.grid.hybrid_astar import _nearest_blocked2

    rng = np.random.default_rng(4)
    for _ in range(200):
        h, w = rng.integers(1, 40, 2)
        blocked = rng.random((h, w)) < rng.choice([0.0, 0.001, 0.01, 0.1, 0.5])
        ringed = np.zeros((h + 2, w + 2), bool)
        ringed[1:-1, 1:-1] = ~blocked
        expected = np.rint(distance_transform_edt(ringed)[1:-1, 1:-1] ** 2).astype(np.int64)
        assert np.array_equal(_nearest_blocked2(blocked), expected)


@pytest.mark.parametrize("few_cells", [0, 10**9])
def test_the_shapely_recheck_finds_an_overlap_exactly_when_one_exists(few_cells, monkeypatch):
    """first_overlap builds only the cells a footprint can reach (or, below FEW_CELLS candidates, all of
    them: both ways tested); against every blocked cell and the ring of cells around the map, by shapely:
    None exactly when nothing overlaps, else a cell the first overlapping pose does overlap."""
    import shapely

    from navlab.sampling import footprint_lattice
    from navlab.sampling.footprint_lattice import first_overlap

    monkeypatch.setattr(footprint_lattice, "FEW_CELLS", few_cells)

    rng = np.random.default_rng(12)
    for _ in range(150):
        h, w = rng.integers(5, 40, 2)
        res = rng.uniform(0.02, 1.0)
        blocked = rng.random((h, w)) < rng.choice([0.002, 0.02, 0.1])
        if rng.random() < 0.5:
            verts, disc = np.array(OUTLINES["car"][0]) * rng.uniform(0.05, 1.0) * res, 0.0
        else:
            verts, disc = np.empty((0, 2)), rng.uniform(0.0, 3.0) * res
        k = rng.integers(1, 20)
        poses = np.column_stack([rng.uniform(0, w * res, k), rng.uniform(0, h * res, k), rng.uniform(-3, 3, k)])
        grow = rng.choice([0.0, 0.3 * res])
        ringed = np.ones((h + 2, w + 2), bool)
        ringed[1:-1, 1:-1] = blocked
        ys, xs = np.nonzero(ringed)
        cells = shapely.box((xs - 1) * res - grow, (ys - 1) * res - grow, xs * res + grow, ys * res + grow)
        if len(verts):
            c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
            shapes = shapely.polygons(np.stack([poses[:, :1] + c * verts[:, 0] - s * verts[:, 1],
                                                poses[:, 1:2] + s * verts[:, 0] + c * verts[:, 1]], axis=-1))
        else:
            shapes = shapely.buffer(shapely.points(poses[:, :2]), disc, quad_segs=16) if disc > 0 \
                else shapely.points(poses[:, :2])
        overlapping = [i for i in range(k) if shapely.intersects(shapes[i], cells).any()]
        hit = first_overlap(blocked, res, verts, disc, poses, grow)
        assert (hit is None) == (not overlapping)
        if hit is not None:
            x, y = hit
            box = shapely.box(x * res - grow, y * res - grow, (x + 1) * res + grow, (y + 1) * res + grow)
            assert ringed[y + 1, x + 1] and shapely.intersects(shapes[overlapping[0]], box)


def test_the_near_pose_check_answers_as_reading_every_cell():
    """With a clearance map a pose's check stops at the first cell nearer than the nearest blocked or
    off-map cell; its answers must be pose_free's (every cell read) on random maps, at poses all over
    the map and just off it, every heading, every outline; and curve_free's with and without the map."""
    from navlab.sampling import reeds_shepp
    from navlab.sampling.footprint_lattice import (NO_CLEARANCE, NO_EXACT, _pose_free_near, clearance_map, curve_free,
                                                   pose_free)

    rng = np.random.default_rng(9)
    for name in sorted(OUTLINES):
        vertices, disc, radius, res = OUTLINES[name]
        lattice = Lattice(tuple(map(tuple, vertices)), disc, radius, res, 16, True, 0.2)
        common = (lattice.theta0, lattice.step, lattice.bins, lattice.pose_cells, lattice.pose_start)
        for b in range(lattice.bins):  # outermost first in every bin
            cells = lattice.pose_cells[lattice.pose_start[b]:lattice.pose_start[b + 1]]
            assert (np.diff((cells ** 2).sum(axis=1)) <= 0).all()
        free = blocked_poses = 0
        for density in (0.002, 0.02, 0.1):
            blocked = rng.random((60, 70)) < density
            clear = clearance_map(blocked, res)
            agree = 0
            for _ in range(1500):
                x, y = rng.uniform(-2 * res, 72 * res), rng.uniform(-2 * res, 62 * res)
                theta = rng.uniform(-math.pi, math.pi)
                expected = pose_free(blocked, res, x, y, theta, *common)
                agree += _pose_free_near(blocked, res, x, y, theta, *common, clear) == expected
                free += expected
                blocked_poses += not expected
            assert agree == 1500
            for _ in range(150):
                a = (rng.uniform(0, 70 * res), rng.uniform(0, 60 * res), rng.uniform(-3, 3))
                b = (rng.uniform(0, 70 * res), rng.uniform(0, 60 * res), rng.uniform(-3, 3))
                kinds, lengths = reeds_shepp.shortest(a, b, radius)._codes()
                args = (blocked, res, *a, kinds, lengths, radius, lattice.ds, *common)
                fast = curve_free(*args, clear, lattice.clear_disc, *NO_EXACT)
                assert fast == curve_free(*args, *NO_CLEARANCE, *NO_EXACT)
        assert free > 100 and blocked_poses > 100  # both answers are tested


def test_outermost_first_is_a_stable_sort_by_distance():
    """The cells farthest from the origin's cell first, ties in their given order (numpy's stable sort)."""
    from navlab.sampling.footprint_lattice import _outermost_first

    rng = np.random.default_rng(5)
    for n in [0, 1, 2, *rng.integers(3, 400, 60)]:
        cells = rng.integers(-20, 21, (n, 2)).astype(np.int64)
        expected = cells[np.argsort(-(cells[:, 0] ** 2 + cells[:, 1] ** 2), kind="stable")]
        assert np.array_equal(_outermost_first(cells), expected)
