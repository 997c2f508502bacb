"""Grid planners on rasterised geometric worlds and on maps, against independent truth.

Truth here is shapely's exact distance (circles as a centre point minus the
radius, so nothing is approximated) and a visibility graph solved with scipy's
Dijkstra; navlab's own checker is a second, separate judge.
"""

import math

import numpy as np
import pytest
import shapely
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

import navlab
from navlab.grid import OccupancyGrid
from navlab.grid.rasterize import MAX_CELLS, grid_shape, rasterize
from navlab.world import Bounds, Circle, Polygon, Rectangle, World

from .helpers import shapely_of, true_clearance

GRID = ["astar", "dijkstra", "jps", "theta_star"]


def random_world(seed: int, robot_radius: float) -> World:
    """Circles, rectangles and triangles scattered over a 10 m square, start and goal free."""
    rng = np.random.default_rng(seed)
    obstacles = []
    for _ in range(9):
        x, y = rng.uniform(1.5, 7.5, 2)
        kind = rng.integers(3)
        if kind == 0:
            obstacles.append(Circle((x, y), rng.uniform(0.2, 0.9)))
        elif kind == 1:
            w, h = rng.uniform(0.1, 1.5, 2)
            obstacles.append(Rectangle((x, y), (x + w, y + h)))
        else:
            angles = np.sort(rng.uniform(0, 2 * math.pi, 3))
            r = rng.uniform(0.4, 1.2)
            obstacles.append(Polygon(tuple((x + r * math.cos(a), y + r * math.sin(a)) for a in angles)))
    return World(f"random{seed}", Bounds(0, 10, 0, 10), (0.4, 0.4), (9.6, 9.6), tuple(obstacles),
                 robot_radius=robot_radius)


def shapely_path_clearance(world, path) -> float:
    return min(true_clearance(world, shapely.LineString(path[i:i + 2])) for i in range(len(path) - 1))


def cell_squares(grid, mask):
    jj, ii = np.nonzero(mask)
    x0 = grid.origin[0] + ii * grid.resolution
    y0 = grid.origin[1] + jj * grid.resolution
    return shapely.box(x0, y0, x0 + grid.resolution, y0 + grid.resolution)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("radius", [0.0, 0.2])
def test_raster_is_conservative(seed, radius):
    """Every free cell's whole square keeps more than the robot radius from every obstacle."""
    world = random_world(seed, radius)
    grid = rasterize(world, resolution=0.125)
    free = cell_squares(grid, ~grid.blocked)
    for o in world.obstacles:
        d = shapely.distance(free, shapely_of(o)) - (o.radius if isinstance(o, Circle) else 0.0)
        assert d.min() > radius
    # and it is not blocking everything: a cell well clear of all obstacles stays free
    blocked = cell_squares(grid, grid.blocked)
    clear = np.array([true_clearance(world, b) for b in blocked[::7]])
    assert np.all(clear <= radius + grid.resolution * math.sqrt(2) + 1e-9)


@pytest.mark.parametrize("algorithm", GRID)
@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_grid_paths_on_random_worlds_are_exactly_free(algorithm, seed):
    world = random_world(seed, robot_radius=0.15 * (seed % 2))
    r = navlab.plan(world, planner=algorithm, resolution=0.1, smooth=seed >= 2 and algorithm != "jps")
    assert r.success, r.reason
    assert world.checker().path_free(r.path)
    assert shapely_path_clearance(world, r.path) >= world.robot_radius - 1e-9


@pytest.mark.parametrize("scene", ["trap", "clutter", "squarefield", "pythonrobotics"])
@pytest.mark.parametrize("algorithm", ["astar", "theta_star"])
def test_grid_paths_on_scenes_are_exactly_free(scene, algorithm):
    world = navlab.load_world(scene)
    r = navlab.plan(scene, planner=algorithm, smooth=True)
    assert r.success, r.reason
    np.testing.assert_array_equal(r.path[0], world.start)
    np.testing.assert_array_equal(r.path[-1], world.goal)
    assert world.checker().path_free(r.path)
    assert shapely_path_clearance(world, r.path) >= world.robot_radius - 1e-9


def visibility_shortest_path(world) -> float:
    """Exact-ish shortest path length: a visibility graph over the vertices of the
    obstacles inflated by the robot radius (shapely, 16 segments per quarter
    circle, inscribed, so this is a hair *below* the true optimum), solved
    with scipy's Dijkstra."""
    r = world.robot_radius
    inflated = shapely.union_all([shapely_of(o).buffer((o.radius if isinstance(o, Circle) else 0.0) + r,
                                                       quad_segs=16) for o in world.obstacles])
    interior = inflated.buffer(-1e-7)
    polys = getattr(inflated, "geoms", [inflated])
    verts = np.vstack([np.asarray(p.exterior.coords)[:-1] for p in polys])
    inside = world.bounds.contains(verts)
    nodes = np.vstack((world.start, world.goal, verts[inside]))
    n = len(nodes)
    i, j = np.triu_indices(n, 1)
    lines = shapely.linestrings(np.stack((nodes[i], nodes[j]), axis=1))
    shapely.prepare(interior)
    visible = ~shapely.intersects(lines, interior)
    length = np.hypot(*(nodes[i] - nodes[j]).T)
    graph = csr_matrix((length[visible], (i[visible], j[visible])), shape=(n, n))
    return float(dijkstra(graph, directed=False, indices=0)[1])


def test_astar_on_trap_is_within_ten_percent_of_the_exact_shortest_path():
    truth = visibility_shortest_path(navlab.load_world("trap"))
    r = navlab.plan("trap", planner="astar")
    assert r.success
    assert r.params["resolution"] == pytest.approx(18.0 / 200)
    gap = r.cost / truth - 1
    print(f"trap: visibility-graph optimum {truth:.4f} m, A* {r.cost:.4f} m, gap {100 * gap:+.2f}%")
    assert 0 <= gap < 0.10


def test_map_paths_keep_the_robot_radius_from_occupied_squares():
    rng = np.random.default_rng(5)
    blocked = rng.random((40, 40)) < 0.03
    blocked[:3, :3] = blocked[-3:, -3:] = False
    grid = OccupancyGrid(blocked, 0.1, (-1.0, 2.0, 0.0), name="random")
    squares = cell_squares(grid, blocked)
    for algorithm in GRID:
        r = navlab.plan(grid, planner=algorithm, start=(-0.88, 2.12), goal=(2.88, 5.88), robot_radius=0.04)
        assert r.success, r.reason
        for a, b in zip(r.path[:-1], r.path[1:]):
            assert shapely.distance(squares, shapely.LineString([a, b])).min() >= 0.04


def test_too_many_cells_is_an_error_before_allocating():
    with pytest.raises(ValueError, match="more than 1e\\+08"):
        grid_shape(Bounds(0, 1e4, 0, 1e4), 1e-3)
    with pytest.raises(ValueError, match="resolution"):
        navlab.plan("trap", planner="astar", resolution=1e-4)
    nx, ny = grid_shape(Bounds(0, 10, 0, 10), 0.05)
    assert (nx, ny) == (200, 200) and nx * ny <= MAX_CELLS


def test_resolution_is_refused_for_a_map():
    grid = OccupancyGrid(np.zeros((5, 5), bool), 1.0)
    with pytest.raises(ValueError, match="resolution"):
        navlab.plan(grid, planner="astar", start=(0.5, 0.5), goal=(4.5, 4.5), resolution=0.5)


def test_start_beside_a_wall_joins_the_grid_through_a_free_leg():
    # the start's own cell touches the inflated wall, so the raster blocks it;
    # the path still starts exactly at the start, through a neighbouring cell
    world = World("w", Bounds(0, 4, 0, 4), (1.02, 2.0), (3.5, 2.0), (Rectangle((0.5, 0.0), (0.8, 4.0)),),
                  robot_radius=0.2)
    r = navlab.plan(world, planner="astar", resolution=0.1)
    assert r.success, r.reason
    np.testing.assert_array_equal(r.path[0], world.start)
    assert world.checker().path_free(r.path)


def test_rotated_map_paths_keep_the_robot_radius():
    blocked = np.zeros((30, 30), bool)
    blocked[10:20, 5:25] = True
    yaw = 0.3
    grid = OccupancyGrid(blocked, 0.1, (1.0, 2.0, yaw))
    start, goal = grid.cell_to_world([[2, 2], [27, 27]])
    jj, ii = np.nonzero(blocked)
    corners = np.stack([np.stack([ii + dx, jj + dy], -1) for dx, dy in ((0, 0), (1, 0), (1, 1), (0, 1))], 1) * 0.1
    c, s = math.cos(yaw), math.sin(yaw)
    squares = shapely.polygons(corners @ np.array([[c, s], [-s, c]]) + (1.0, 2.0))  # independent transform
    for algorithm in ("astar", "theta_star"):
        r = navlab.plan(grid, planner=algorithm, start=start, goal=goal, robot_radius=0.05)
        assert r.success, r.reason
        assert min(shapely.distance(squares, shapely.LineString(r.path[i:i + 2])).min()
                   for i in range(len(r.path) - 1)) >= 0.05


def test_a_grid_edited_after_a_plan_gives_the_new_answer():
    grid = OccupancyGrid(np.zeros((20, 20), bool), 0.5)
    query = {"start": (0.25, 5.25), "goal": (9.75, 5.25)}
    straight = navlab.plan(grid, planner="astar", **query)
    assert straight.cost == pytest.approx(9.5)
    wall = np.zeros((20, 20), bool)
    wall[2:, 10] = True
    try:
        grid.blocked[wall] = True  # a mutable grid, edited in place
    except ValueError:
        grid = grid.with_blocked(grid.blocked | wall)  # an immutable grid: a changed copy
    detour = navlab.plan(grid, planner="astar", **query)
    assert detour.success and detour.cost > 12
    assert not np.any(np.all(np.isclose(detour.path, (5.25, 5.25)), axis=1))
