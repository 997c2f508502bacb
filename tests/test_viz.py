"""Figures a reader can read, drawn where a notebook asks.

Checked against the figure's own geometry: artists counted in the given
axes, the legend's box against every drawn point, axis labels present, a
GIF's frames, size and moving obstacles.
"""

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

import navlab  # noqa: E402
from navlab.grid import make_maze, plan_world  # noqa: E402
from navlab.result import Tree  # noqa: E402
from navlab.viz import (animate_run, draw_path, draw_tree, draw_world, place_legend, plot_grid_plan,  # noqa: E402
                        plot_plan, plot_run)
from navlab.viz.legend import _data_points  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _trap_result(**kw):
    return navlab.plan("trap", seed=0, max_iter=400, keep_tree=True, **kw)


def _legend_clear(ax) -> bool:
    """The legend lies outside the axes, or its box holds none of the data."""
    legend = ax.get_legend()
    assert legend is not None
    fig = ax.figure
    fig.canvas.draw()
    box = legend.get_window_extent()
    axes_box = ax.get_window_extent()
    if box.x0 >= axes_box.x1 - 1 or box.x1 <= axes_box.x0 + 1 or box.y0 >= axes_box.y1 - 1:
        return True
    pts = _data_points(ax)
    inside = (pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)
    return not inside.any()


def test_plot_plan_draws_into_the_given_axes_and_returns_them():
    r = _trap_result()
    fig, (left, right) = plt.subplots(1, 2)
    out = plot_plan(navlab.load_world("trap"), r, ax=right)
    assert out is right
    assert not left.lines and not left.patches and not left.collections  # nothing strayed into the other axes
    assert len(right.collections) == 1  # the tree, one line collection
    assert len(right.collections[0].get_segments()) == len(r.tree) - 1
    assert right.get_xlabel() == "x [m]" and right.get_ylabel() == "y [m]"


def test_plot_plan_of_a_result_alone_draws_it_in_the_world_navlab_plan_recorded():
    """plot_plan(result, ax=...) as issue 19 writes it: the same drawing as plot_plan(world, result, ax=...)."""
    r = _trap_result()
    fig, (alone, both) = plt.subplots(1, 2)
    assert plot_plan(r, ax=alone) is alone
    plot_plan(navlab.load_world("trap"), r, ax=both)
    assert alone.get_title() == both.get_title() and len(alone.patches) == len(both.patches) > 0
    assert [line.get_xydata().tolist() for line in alone.lines] == [line.get_xydata().tolist() for line in both.lines]
    with pytest.raises(TypeError, match="plot_plan\\(world, result\\) or plot_plan\\(result\\)"):
        plot_plan(navlab.load_world("trap"))
    import dataclasses

    with pytest.raises(ValueError, match="does not record its world"):
        plot_plan(dataclasses.replace(r, world=None))
    plt.close(fig)


def test_plot_plan_without_ax_makes_and_saves_a_figure(tmp_path):
    fig = plot_plan(navlab.load_world("trap"), _trap_result(), str(tmp_path / "p.png"))
    assert (tmp_path / "p.png").stat().st_size > 0
    assert fig.axes[0].get_xlabel() == "x [m]"


@pytest.mark.parametrize("scene", ["trap", "clutter", "one_obstacle", "squarefield", "growth_ratio", "pythonrobotics"])
def test_legend_never_covers_the_data(scene):
    world = navlab.load_world(scene)
    r = navlab.plan(world, seed=1, max_iter=300, keep_tree=True)
    ax = plot_plan(world, r, ax=plt.subplots()[1])
    assert _legend_clear(ax)


def test_legend_goes_to_an_empty_corner_when_there_is_one():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 0.2], label="low line")  # the upper corners are empty
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    legend = place_legend(ax)
    fig.canvas.draw()
    box, axes_box = legend.get_window_extent(), ax.get_window_extent()
    assert box.x0 >= axes_box.x0 and box.x1 <= axes_box.x1 and box.y1 <= axes_box.y1  # inside the axes
    assert box.y0 > axes_box.y0 + 0.5 * axes_box.height  # in an upper corner
    assert _legend_clear(ax)


def test_legend_goes_outside_when_every_corner_is_taken():
    fig, ax = plt.subplots()
    xy = np.random.default_rng(0).random((4000, 2))
    ax.plot(xy[:, 0], xy[:, 1], ".", label="everywhere")
    legend = place_legend(ax)
    fig.canvas.draw()
    assert legend.get_window_extent().x0 >= ax.get_window_extent().x1  # right of the axes
    assert place_legend(plt.subplots()[1]) is None  # nothing labelled: no legend


def test_tree_object():
    r = _trap_result()
    tree = r.tree
    assert isinstance(tree, Tree)
    assert tree.nodes.shape == (len(tree), 2) and tree.parent.shape == (len(tree),)
    edges = tree.edges()
    assert edges.shape == (len(tree) - 1, 2, 2)
    # every edge joins a node to its parent
    child = np.flatnonzero(tree.parent >= 0)
    assert np.array_equal(edges[:, 1], tree.nodes[child]) and np.array_equal(edges[:, 0],
                                                                              tree.nodes[tree.parent[child]])
    # mapping access for code written when it was a dict
    assert tree["nodes"] is tree.nodes and "parent" in tree and "raw_cells" not in tree
    assert tree.get("raw_cells") is None
    with pytest.raises(KeyError, match="raw_cells"):
        tree["raw_cells"]
    grid_tree = navlab.plan("trap", planner="astar", smooth=True).tree
    assert grid_tree and len(grid_tree) == 0 and grid_tree.raw_cells.shape[1] == 2 and grid_tree.raster is not None
    assert not Tree() and Tree().edges().shape == (0, 2, 2)


def test_draw_functions_compose():
    world = navlab.load_world("trap")
    r = _trap_result()
    fig, ax = plt.subplots()
    draw_world(ax, world)
    draw_tree(ax, r.tree)
    draw_tree(ax, r.tree.nodes, r.tree.parent, label=None)  # arrays work too
    draw_path(ax, r.path, label="mine", color="k")
    assert len(ax.collections) == 2 and any(line.get_label() == "mine" for line in ax.lines)


def test_grid_plot_into_axes_has_labels_and_the_raw_path():
    grid = make_maze(5, 5, seed=1)
    r = plan_world(grid, (0.3, 0.3), (2.3, 2.3), smooth=True)
    ax = plot_grid_plan(grid, r, ax=plt.subplots()[1])
    labels = [line.get_label() for line in ax.lines]
    assert "raw path" in labels and ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    assert _legend_clear(ax)


def test_a_grid_larger_than_its_axes_keeps_every_thin_wall():
    """Drawn cell by cell, a big grid was sampled down to the axes' pixels, which skipped whole columns of
    cells: a maze's one-cell walls showed as stripes (newcomer run, session 19). Now blocks of cells are
    drawn by their mean darkness (square-rooted), so a one-cell wall darkens its block's column, a maze
    whose corridors are narrower than a block is not drawn black (each block as dark as its darkest cell
    did that: review, session 19), and the axes still span exactly the map."""
    from navlab.grid import OccupancyGrid
    from navlab.viz import draw_grid

    blocked = np.zeros((600, 4000), bool)
    blocked[:, 7::40] = True  # 100 one-cell walls, each in a different 40-cell block
    blocked[300:, 2020] = True  # and a half wall, in a block of its own
    grid = OccupancyGrid(blocked, resolution=0.05, origin=(1.0, -2.0, 0.0))
    fig, ax = plt.subplots(figsize=(7, 7))
    draw_grid(ax, grid)
    image = ax.get_images()[0].get_array()
    box = ax.get_window_extent()
    assert image.shape[1] <= box.width and image.shape[0] <= box.height  # no column of the image is skipped
    k = -(-4000 // image.shape[1])  # cells per block
    wall = 255 * (1 - math.sqrt(1 / k))  # a block one wall cell wide, all its rows
    dark_columns = (image < 255).any(axis=0)
    assert np.count_nonzero(dark_columns) == 101 and np.count_nonzero((image <= wall + 1).all(axis=0)) == 100
    assert ax.get_xlim() == (1.0, 1.0 + 4000 * 0.05) and ax.get_ylim() == (-2.0, -2.0 + 600 * 0.05)
    world = navlab.World.from_grid(grid, (1.1, -1.9), (2.0, -1.9))  # a map under a world's shapes too
    ax3 = plt.subplots(figsize=(7, 7))[1]
    draw_world(ax3, world)
    shade = ax3.get_images()[0].get_array()
    assert shade.shape[1] <= box.width and np.count_nonzero((shade < 255).any(axis=0)) == 101
    dense = np.zeros((3000, 3000), bool)  # walls and one-cell corridors alternating: blocks half wall
    dense[:, ::2] = True
    ax4 = plt.subplots(figsize=(7, 7))[1]
    draw_grid(ax4, OccupancyGrid(dense))
    half = ax4.get_images()[0].get_array()
    assert 0 < half.min() and half.max() < 255  # grey all over: neither black nor white
    small = OccupancyGrid(blocked[:20, :30])  # a grid smaller than its axes: cell by cell, as before
    ax2 = plt.subplots()[1]
    draw_grid(ax2, small)
    assert np.array_equal(ax2.get_images()[0].get_array() == 0, small.blocked)


def test_sim_plot_draws_the_true_trajectory_on_top():
    from navlab.sim.runner import simulate
    world = navlab.load_world("clutter")
    result, _, _ = simulate(world, robot="diff", planner="astar", seed=0)
    ax = plot_run(world, result, ax=plt.subplots()[1])
    by_label = {line.get_label(): line for line in ax.lines}
    true, planned = by_label["true trajectory"], by_label["planned path"]
    assert true.get_zorder() > planned.get_zorder()
    assert ax.get_xlabel() == "x [m]"
    assert _legend_clear(ax)


def test_gif_frames_aspect_legend_and_no_ghost(tmp_path, monkeypatch):
    import matplotlib.text

    from navlab.sim.runner import simulate
    from navlab.world.io import world_from_dict

    titles = []  # what each frame's title says (an outside check saw "REACHED" on the first frame)
    set_text = matplotlib.text.Text.set_text
    monkeypatch.setattr(matplotlib.text.Text, "set_text",
                        lambda self, text: (titles.append(str(text)) if str(text).startswith("t = ") else None,
                                            set_text(self, text))[1])

    world = world_from_dict({
        "name": "wide", "bounds": {"x": [0, 12], "y": [0, 4]}, "start": [1, 2], "goal": [11, 2],
        "obstacles": [{"type": "circle", "center": [6, 3.4], "radius": 0.3,
                       "motion": {"velocity": [0, -0.3], "at_bounds": "reflect"}}]})
    result, _, _ = simulate(world, robot="omni3", controller="potential_field", seed=0)
    out = tmp_path / "run.gif"
    animate_run(world, result, str(out), 0.15, max_frames=20, progress=False)
    im = Image.open(out)
    assert im.n_frames == min(20, len(result.true_poses))
    outcome = result.status.name
    assert titles and titles[-1].endswith(f": {outcome}") and outcome != "running"
    assert [t for t in titles if t.endswith(f": {outcome}")] == [titles[-1]] * titles.count(titles[-1])  # the end only
    assert any(t.endswith(": running") for t in titles)
    w, h = im.size
    assert w > 1.4 * h  # a 3:1 world makes a wide GIF (legend on the right adds width)
    # the obstacle's start position (6, 3.4) is empty in a late frame: no ghost left there
    frames = []
    for k in (0, im.n_frames - 1):
        im.seek(k)
        frames.append(np.asarray(im.convert("RGB"), dtype=int))
    first, last = frames
    moved = np.abs(first - last).sum(axis=2) > 60
    assert moved.any()
    def blue(frame):  # the moving obstacle's fill (tab:blue): the only blue thing in the axes
        frame = frame[:, : int(0.65 * frame.shape[1])]  # the legend (with a blue swatch) is on the right
        return (frame[..., 2] - frame[..., 0] > 60) & (frame[..., 2] - frame[..., 1] > 20)

    early, late = blue(first), blue(last)
    assert early.sum() > 20 and abs(int(late.sum()) - int(early.sum())) < 0.3 * early.sum()  # drawn once in each
    assert (early & late).sum() < 0.2 * early.sum()  # and gone from where it started: no ghost


def test_the_footprint_is_drawn_along_a_run_and_in_the_gif(tmp_path):
    import matplotlib.patches as mpatches

    from navlab.robots import make_robot
    from navlab.sim.runner import simulate
    from navlab.viz import plot_run
    from navlab.viz.sim_plot import animate_run

    result, world, sim = simulate("one_obstacle", robot="jackal", controller="rpp", max_time=20)
    fig = plot_run(world, result, footprint=make_robot("jackal").shape)
    polygons = [p for p in fig.axes[0].patches if isinstance(p, mpatches.Polygon) and not p.get_fill()]
    assert len(polygons) >= 5
    # each outline is the rectangle at a pose of the run: 4 corners 0.42 × 0.33 apart
    corners = polygons[0].get_xy()[:4]
    sides = sorted(np.hypot(*np.diff(np.vstack((corners, corners[:1])), axis=0).T))
    assert sides == pytest.approx([0.33, 0.33, 0.42, 0.42])
    animate_run(world, result, str(tmp_path / "run.gif"), sim.robot.radius, max_frames=5,
                footprint=sim.robot.shape)
    assert (tmp_path / "run.gif").stat().st_size > 0
