"""Hybrid A*'s compiled re-check of a path against shapely: the same overlaps, the same cell named."""

import math

import numpy as np
import pytest
import shapely

from navlab.grid.hybrid_certify import first_overlap_exact
from navlab.sampling.footprint_lattice import first_overlap

OUTLINES = {
    "car": [[-1.0, -1.0], [3.3, -1.0], [3.3, 1.0], [-1.0, 1.0]],
    "skew triangle": [[-0.3, -0.2], [0.5, 0.05], [-0.1, 0.3]],
    "L (not convex)": [[-0.5, -0.5], [0.6, -0.5], [0.6, -0.1], [-0.1, -0.1], [-0.1, 0.7], [-0.5, 0.7]],
}


def _case(rng, outline):
    h, w = rng.integers(8, 30, 2)
    res = rng.uniform(0.02, 1.0)
    blocked = rng.random((h, w)) < rng.choice([0.0, 0.005, 0.02, 0.1])
    # from footprints within a cell to footprints covering many cells (a blocked cell wholly inside)
    verts = np.array(outline) * rng.uniform(0.1, 3.0) * res
    k = rng.integers(1, 6)
    poses = np.column_stack([rng.uniform(0.1, 0.9, k) * w * res, rng.uniform(0.1, 0.9, k) * h * res,
                             rng.uniform(-4, 4, k)])
    if rng.random() < 0.1:  # and some off the map
        poses[0, :2] = -0.2 * res
    grow = rng.choice([0.0, 0.25 * res, 0.7 * res])
    return blocked, res, verts, poses, grow


def _ringed_cells(blocked, res, grow):
    """Every blocked cell and the ring just outside the map, as shapely boxes grown by ``grow``, row by row."""
    h, w = blocked.shape
    ringed = np.ones((h + 2, w + 2), bool)
    ringed[1:-1, 1:-1] = blocked
    ys, xs = np.nonzero(ringed)
    return xs - 1, ys - 1, shapely.box((xs - 1) * res - grow, (ys - 1) * res - grow, xs * res + grow,
                                       ys * res + grow)


@pytest.mark.parametrize("name", sorted(OUTLINES))
def test_the_compiled_recheck_finds_the_cell_shapely_finds(name):
    """None exactly when shapely finds no pose's polygon meeting a blocked or ring cell's grown square;
    else the first such pose's lowest cell (row by row), which is also first_overlap's answer."""
    rng = np.random.default_rng(31)
    hits = misses = 0
    for _ in range(300):
        blocked, res, verts, poses, grow = _case(rng, OUTLINES[name])
        xs, ys, cells = _ringed_cells(blocked, res, grow)
        c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
        shapes = shapely.polygons(np.stack([poses[:, :1] + c * verts[:, 0] - s * verts[:, 1],
                                            poses[:, 1:2] + s * verts[:, 0] + c * verts[:, 1]], axis=-1))
        expected = None
        for shape in shapes:
            meets = np.nonzero(shapely.intersects(shape, cells))[0]
            if len(meets):
                expected = (int(xs[meets[0]]), int(ys[meets[0]]))  # row by row: nonzero's order
                break
        got = first_overlap_exact(blocked, res, verts, 0.0, poses, grow)
        assert got == expected
        assert got == first_overlap(blocked, res, verts, 0.0, poses, grow)
        hits += got is not None
        misses += got is None
    assert hits > 50 and misses > 50  # both answers exercised


def test_a_footprint_around_a_blocked_cell_overlaps_it():
    """No edge crosses the cell: only the inside test finds it."""
    blocked = np.zeros((9, 9), bool)
    blocked[4, 4] = True
    square = np.array([[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0]])
    assert first_overlap_exact(blocked, 1.0, square, 0.0, np.array([[4.5, 4.5, 0.3]]), 0.0) == (4, 4)
    assert first_overlap_exact(blocked, 1.0, square * 0.1, 0.0, np.array([[2.5, 2.5, 0.3]]), 0.0) is None


def test_touching_counts():
    blocked = np.zeros((4, 4), bool)
    blocked[1, 2] = True  # the square [2, 3] x [1, 2]
    unit = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    assert first_overlap_exact(blocked, 1.0, unit, 0.0, np.array([[1.5, 1.5, 0.0]]), 0.0) == (2, 1)
    assert first_overlap_exact(blocked, 1.0, unit, 0.0, np.array([[1.5 - 1e-6, 1.5, 0.0]]), 0.0) is None
    assert first_overlap_exact(blocked, 1.0, unit, 0.0, np.array([[1.5 - 1e-6, 1.5, 0.0]]), 1e-6) == (2, 1)


@pytest.mark.parametrize("disc", [0.0, 0.3, 1.7])
def test_discs_and_points_by_their_distance_from_the_squares(disc):
    """A disc (or a point) overlaps exactly the grown squares within its radius (shapely's distance)."""
    rng = np.random.default_rng(5)
    hits = 0
    for _ in range(200):
        blocked, res, _, poses, grow = _case(rng, OUTLINES["car"])
        radius = disc * res
        xs, ys, cells = _ringed_cells(blocked, res, grow)
        expected = None
        for x, y, _ in poses:
            near = np.nonzero(shapely.distance(shapely.Point(x, y), cells) <= radius)[0]
            if len(near):
                expected = (int(xs[near[0]]), int(ys[near[0]]))
                break
        assert first_overlap_exact(blocked, res, np.empty((0, 2)), radius, poses, grow) == expected
        hits += expected is not None
    assert 20 < hits < 180


def test_poses_off_the_map_meet_the_ring():
    blocked = np.zeros((3, 3), bool)
    unit = np.array([[-0.2, -0.2], [0.2, -0.2], [0.2, 0.2], [-0.2, 0.2]])
    assert first_overlap_exact(blocked, 1.0, unit, 0.0, np.array([[1.5, 1.5, 0.0]]), 0.0) is None
    assert first_overlap_exact(blocked, 1.0, unit, 0.0, np.array([[1.5, 1.5, 0.0], [0.1, 2.5, math.pi / 4]]),
                               0.0) == (-1, 2)


@pytest.mark.parametrize("disc", [0.0, 0.3])
def test_a_footprint_wholly_beyond_the_ring_leaves_the_map(disc):
    """Poses several cells outside the map meet none of the ring's squares, yet the
    footprint is off the map: each names the ring cell nearest its pose (shapely's
    first_overlap, which tests the ring only, misses these)."""
    blocked = np.zeros((10, 10), bool)
    outline = np.empty((0, 2)) if disc else np.array([[-0.3, -0.2], [0.4, -0.2], [0.4, 0.2], [-0.3, 0.2]])
    for pose, ring_cell in (((-5.0, 5.5), (-1, 5)), ((15.0, 5.5), (10, 5)), ((5.5, 40.0), (5, 10)),
                            ((-7.0, -7.0), (-1, -1)), ((12.5, -3.0), (10, -1))):
        assert first_overlap_exact(blocked, 1.0, outline, disc, np.array([[*pose, 0.7]]), 0.0) == ring_cell
    inside = np.array([[5.5, 5.5, 0.7], [1.0, 9.0, 0.0]])
    assert first_overlap_exact(blocked, 1.0, outline, disc, inside, 0.0) is None


def test_a_start_pose_off_the_map_is_an_invalid_start():
    from navlab.grid import OccupancyGrid
    from navlab.grid.hybrid_astar import plan_hybrid
    from navlab.result import Status

    grid = OccupancyGrid(np.zeros((20, 20), bool), resolution=1.0)
    result = plan_hybrid(grid, (-5.0, 10.0, 0.0), (15.0, 10.0, 0.0), turning_radius=2.0)
    assert result.status == Status.INVALID_START, result.reason
    assert "leaves the map" in result.reason


@pytest.mark.parametrize("grow", [0.0, 0.0125, 0.025])
def test_the_pose_test_agrees_with_shapely_on_squares_at_its_box_and_circle(grow):
    """world.footprint_collision.pose_grid_overlap, which the search's exact re-check shares with this module,
    passes over squares beyond the outline's bounding box or its circle about the pose before the exact
    test: one blocked cell at a time, placed so that its grown square lies just inside or just outside
    those bounds (and the outline's edges), it answers as shapely does."""
    import shapely

    from navlab.world.footprint_collision import pose_grid_overlap

    res = 0.05
    rng = np.random.default_rng(11)
    outline = np.array([[-0.25, -0.2], [0.25, -0.2], [0.25, 0.2], [-0.25, 0.2]])
    placed, box = np.empty((4, 2)), np.empty((4, 2))
    agree = hits = 0
    for _ in range(400):
        x, y, theta = rng.uniform(0.9, 1.1), rng.uniform(0.9, 1.1), rng.uniform(-math.pi, math.pi)
        c, s = math.cos(theta), math.sin(theta)
        world = np.column_stack([x + c * outline[:, 0] - s * outline[:, 1], y + s * outline[:, 0] + c * outline[:, 1]])
        shape = shapely.Polygon(world)
        # a cell whose grown square's nearest point is about `gap` from the outline's box, circle or edge
        cx = int(math.floor((world[:, 0].max() + grow + rng.uniform(-0.02, 0.02)) / res))
        cy = int(math.floor((y + rng.uniform(-0.35, 0.35)) / res))
        blocked = np.zeros((40, 40), bool)
        blocked[cy, cx] = True
        found, _, _ = pose_grid_overlap(blocked, res, outline, 0.0, x, y, theta, grow, placed, box)
        square = shapely.box(cx * res - grow, cy * res - grow, (cx + 1) * res + grow, (cy + 1) * res + grow)
        expected = shape.intersects(square)
        agree += found == expected
        hits += expected
    assert agree == 400 and 40 < hits < 360  # both answers are tested
