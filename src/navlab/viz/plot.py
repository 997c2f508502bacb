"""Drawing planning results with matplotlib (Agg backend, files only)."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np

from ..errors import ParameterError
from ..result import Result, Tree
from .legend import FRAME, place_legend
from .save import save_figure


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def finish_figure(fig, out: Optional[str], dpi: int = 110):
    """Write ``fig`` to ``out`` (when given) and release it; return it.

    The file appears whole or not at all (:func:`.save.save_figure`); a
    write that fails (disk full, no permission) is one ``ParameterError`` naming
    the file.
    """
    if out:
        try:
            save_figure(fig, out, dpi=dpi, bbox_inches="tight")
        except OSError as exc:
            raise ParameterError(f"{out}: cannot write the figure: {exc.strerror or exc}") from None
        except ValueError as exc:  # matplotlib: "Format 'txt' is not supported (supported formats: ...)"
            raise ParameterError(f"{out}: cannot write the figure: {exc}") from None
        finally:
            _pyplot().close(fig)
    return fig


def new_axes(ax=None, figsize=(7, 7)):
    """``(figure, axes, owned)``: ``ax`` and its figure when given (drawing into
    a caller's axes, e.g. a notebook's subplot), else a new figure whose
    ``owned`` flag says the caller of the ``plot_*`` function saves and closes it."""
    if ax is not None:
        return ax.figure, ax, False
    fig, ax = _pyplot().subplots(figsize=figsize)
    return fig, ax, True


def finish_plot(fig, ax, owned: bool, out: Optional[str]):
    """The ``plot_*`` functions' common ending: the legend where it covers no
    data, then the figure saved to ``out`` (new figures only) and returned;
    drawing into a given ``ax`` returns that axes (``out`` saves its figure)."""
    place_legend(ax)
    if not owned:
        if out:
            finish_figure_keep(fig, out)
        return ax
    return finish_figure(fig, out)


def finish_figure_keep(fig, out: str, dpi: int = 110) -> None:
    """Write ``fig`` to ``out`` without closing it (a caller's figure stays theirs)."""
    try:
        save_figure(fig, out, dpi=dpi, bbox_inches="tight")
    except OSError as exc:
        raise ParameterError(f"{out}: cannot write the figure: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise ParameterError(f"{out}: cannot write the figure: {exc}") from None


def draw_map(ax, grid, allow_unknown: bool = False, occupied: float = 0.35) -> None:
    """An occupancy grid under a world's shapes, in world coordinates (its
    origin's yaw applied): occupied cells dark (grey level ``occupied``),
    unknown cells mid grey (light when ``allow_unknown``), free cells white;
    a grid larger than the axes in blocks of cells (:func:`cell_image`)."""
    import matplotlib.transforms as mtransforms

    levels = (1.0, 0.85 if allow_unknown else 0.6, occupied)
    shade, k = cell_image(ax, grid, *(round(255 * level) for level in levels))
    h, w = shade.shape
    ox, oy, yaw = grid.origin
    size = k * grid.resolution  # (the last blocks may reach past the map's far edges, in white)
    image = ax.imshow(shade, cmap="gray", vmin=0, vmax=255, origin="lower", extent=(0, w * size, 0, h * size),
                      interpolation="nearest", zorder=1)
    image.set_transform(mtransforms.Affine2D().rotate(yaw).translate(ox, oy) + ax.transData)


def cell_image(ax, grid, free: int, unknown: int, blocked: int):
    """``(image, k)``: a grid's cells as grey levels (uint8, row 0 first), in blocks of k × k cells when
    it has more cells across than ``ax`` has pixels.

    A block's darkness (below ``free``) is its cells' mean darkness, raised to the power ½ against the
    darkest level (``blocked``): a block all blocked is as dark as one blocked cell, a one-cell wall
    across a block of 8 shows at 35 % of that, not at the 12 % a plain mean gives, and corridors
    narrower than a block stay lighter than walls. (Drawn cell by cell, the image was sampled down to
    the axes' pixels, which skips whole rows and columns: a maze's one-cell walls showed as stripes;
    each block's darkest cell instead turned a maze with corridors narrower than a block black.) The
    last blocks past the grid's far edges are filled with ``free``."""
    image = np.full(grid.blocked.shape, free, dtype=np.uint8)
    image[grid.unknown] = unknown
    image[grid.blocked] = blocked
    box = ax.get_window_extent()
    k = max(1, math.ceil(grid.height / max(box.height, 1.0)), math.ceil(grid.width / max(box.width, 1.0)))
    if k == 1:
        return image, 1
    h, w = image.shape
    dark = np.zeros((-(-h // k) * k, -(-w // k) * k), dtype=np.float32)
    dark[:h, :w] = free - image
    mean = dark.reshape(dark.shape[0] // k, k, dark.shape[1] // k, k).mean(axis=(1, 3))
    darkest = float(free - blocked)
    return np.rint(free - darkest * np.sqrt(mean / darkest)).astype(np.uint8), k


def draw_world(ax, world, show_inflation: bool = True, moving: bool = True) -> None:
    """Obstacles (filled), their inflation by the robot radius (dashed),
    bounds, start and goal; axes labelled in metres, equal aspect.

    ``moving=False`` leaves out the obstacles that move (an animation draws
    them where they are in each frame, so no copy stays at t = 0).
    """
    from matplotlib import patches

    from ..world.shapes import Circle, Polygon, Rectangle

    r = world.robot_radius
    if getattr(world, "occupancy", None) is not None:
        draw_map(ax, world.occupancy, world.allow_unknown)
    solid = {"color": "0.35", "zorder": 2, "label": "obstacle"}
    grown = {"fill": False, "ls": "--", "lw": 0.7, "ec": "0.5", "zorder": 2,
             "label": f"inflated by the robot radius {r:g} m"}
    for o in world.obstacles:
        if not moving and getattr(o, "motion", None) is not None:
            continue
        if isinstance(o, Circle):
            ax.add_patch(patches.Circle(o.center, o.radius, **solid))
            if show_inflation and r > 0:
                ax.add_patch(patches.Circle(o.center, o.radius + r, **grown))
        elif isinstance(o, Rectangle):
            w, h = o.max[0] - o.min[0], o.max[1] - o.min[1]
            ax.add_patch(patches.Rectangle(o.min, w, h, **solid))
            if show_inflation and r > 0:
                ax.add_patch(patches.FancyBboxPatch(o.min, w, h, boxstyle=f"round,pad={r}", **grown))
        elif isinstance(o, Polygon):
            ax.add_patch(patches.Polygon(o.points, closed=True, **solid))
            if show_inflation and r > 0:
                import shapely

                outline = shapely.Polygon(o.points).buffer(r)
                ax.add_patch(patches.Polygon(np.column_stack(outline.exterior.xy), closed=True, **grown))
        else:
            continue
        # one legend entry per kind, however many obstacles
        solid["label"] = grown["label"] = None
    b = world.bounds
    ax.plot([b.xmin, b.xmax, b.xmax, b.xmin, b.xmin], [b.ymin, b.ymin, b.ymax, b.ymax, b.ymin], color="k", lw=1,
            gid=FRAME)
    ax.plot(*world.start, "o", color="tab:green", ms=9, zorder=5, label="start")
    ax.plot(*world.goal, "*", color="tab:red", ms=14, zorder=5, label="goal")
    if world.goal_tolerance > 0:
        ax.add_patch(patches.Circle(world.goal, world.goal_tolerance, fill=False, ec="tab:red", lw=0.8, zorder=5))
    ax.set_xlim(b.xmin - 0.02 * b.diagonal, b.xmax + 0.02 * b.diagonal)
    ax.set_ylim(b.ymin - 0.02 * b.diagonal, b.ymax + 0.02 * b.diagonal)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def draw_tree(ax, tree, parent: Optional[np.ndarray] = None, label: Optional[str] = "tree") -> None:
    """A search tree's edges as one line collection (thin blue).

    ``tree`` is a :class:`navlab.Tree` (``result.tree``), or the node array
    (N, 2) with ``parent`` (N,) given apart (−1 for the root). A tree of poses
    (N, 3) is drawn by its chords (its edges are Dubins / Reeds–Shepp curves).
    """
    from matplotlib.collections import LineCollection

    from ..result import Tree

    if not isinstance(tree, Tree):
        tree = Tree(nodes=np.asarray(tree, float), parent=np.asarray(parent))
    segs = tree.edges()[:, :, :2]
    ax.add_collection(LineCollection(segs, colors="tab:blue", linewidths=0.4, alpha=0.5, zorder=3,
                                     label=f"{label} ({len(tree)} nodes)" if label and len(segs) else None))


def draw_path(ax, path: np.ndarray, label: str = "path", color: str = "tab:orange", **kw) -> None:
    """A path (N, 2+) as a polyline (x, y columns; headings, if any, ignored)."""
    path = np.asarray(path, dtype=float)
    if len(path):
        kw.setdefault("ls", "-")
        kw.setdefault("zorder", 4)
        ax.plot(path[:, 0], path[:, 1], color=color, lw=kw.pop("lw", 2.2), label=label, **kw)


def draw_footprint(ax, footprint, poses, count: int = 12, **style) -> None:
    """The robot's footprint outline at ``count`` poses evenly spread over ``poses`` (N, 3),
    the last one included (a disc footprint is drawn as its circle)."""
    from matplotlib import patches

    poses = np.asarray(poses, float).reshape(-1, 3)
    picks = np.unique(np.linspace(0, len(poses) - 1, min(count, len(poses))).astype(int))
    style = {"fill": False, "ec": "tab:orange", "lw": 0.9, "zorder": 5.2, **style}
    label = style.pop("label", "footprint")
    for k, i in enumerate(picks):
        ax.add_patch(patches.Polygon(footprint.at(poses[i]), closed=True, label=label if k == 0 else None, **style))


def draw_pose_path(ax, result) -> None:
    """For a path of poses (N, 3): its reverse stretches dashed over it, the
    footprint along it, and arrows for the start and goal headings."""
    path = np.asarray(result.path, dtype=float)
    if path.ndim != 2 or path.shape[1] != 3 or not len(path):
        return
    direction = getattr(result, "direction", None)
    if direction is not None and len(direction) == len(path) and np.any(direction < 0):
        back = np.where(direction < 0, path[:, 1], np.nan)
        ax.plot(path[:, 0], back, color="tab:red", lw=2.2, ls="--", zorder=4.1, label="in reverse")
    value = result.params.get("footprint")
    if value is not None:
        from ..world.footprint import Footprint

        draw_footprint(ax, Footprint.from_value(value), path, count=16)
    size = 0.04 * max(np.ptp(path[:, 0]), np.ptp(path[:, 1]), 1e-9)
    for pose in (path[0], path[-1]):
        ax.arrow(pose[0], pose[1], size * np.cos(pose[2]), size * np.sin(pose[2]), width=size * 0.12,
                 color="black", zorder=6, length_includes_head=True)


def _world_and_result(world, result):
    """``plot_plan``'s two spellings, (world, result) and (result,), as (world, result)."""
    if result is not None:
        return world, result
    if not isinstance(world, Result):
        raise TypeError(f"plot_plan(world, result) or plot_plan(result): got one {type(world).__name__} and no result")
    if world.world is None:
        raise ParameterError("this result does not record its world (navlab.plan records it; a planner called "
                             "directly does not): plot_plan(world, result)")
    return world.world, world


def plot_plan(world, result=None, out: Optional[str] = None, title: Optional[str] = None, ax=None):
    """World, tree (if kept), path, start and goal.

    ``plot_plan(result, ax=ax)`` draws a result of :func:`navlab.plan` in the
    world it records (``result.world``); ``plot_plan(world, result)`` draws
    any planner's result in ``world``.

    Parameters
    ----------
    world : World or Result
        What was planned in (``navlab.load_world`` or the source's world), or
        the result itself when ``result`` is not given.
    result : Result, optional
        A planner's result; its ``tree`` is drawn when it was kept.
    out : str, optional
        Write the figure here (format from the suffix); written whole or not at all.
    title : str, optional
        Default: world, planner (+ sampler) and status.
    ax : matplotlib Axes, optional
        Draw into these axes (a notebook's subplot) instead of a new figure.

    Returns
    -------
    Figure or Axes
        The new figure (closed once saved to ``out``), or ``ax`` when given.

    Examples
    --------
    >>> import matplotlib.pyplot as plt, navlab
    >>> from navlab.viz import plot_plan
    >>> fig, axes = plt.subplots(1, 2)
    >>> for ax, sampler in zip(axes, ("uniform", "gaussian")):
    ...     r = navlab.plan("trap", sampler=sampler, seed=0, max_iter=300, keep_tree=True)
    ...     _ = plot_plan(r, ax=ax)
    """
    world, result = _world_and_result(world, result)
    fig, ax, owned = new_axes(ax)
    tree = result.tree if result.tree is not None else Tree()
    if "raster" in tree and getattr(world, "occupancy", None) is None:
        draw_map(ax, tree["raster"], occupied=0.8)  # the cells a grid planner saw, under the exact shapes
    draw_world(ax, world)
    if "nodes" in tree:
        draw_tree(ax, tree)
    if "raw_cells" in tree and "raster" in tree:  # a smoothed grid path: the path before smoothing
        raw = tree["raster"].cell_to_world(tree["raw_cells"])
        draw_path(ax, raw, label="grid path before smoothing", color="tab:blue", lw=1.0, ls="--")
    draw_path(ax, result.path, label=f"path {result.cost:.3f} m" if np.isfinite(result.cost) else "path")
    draw_pose_path(ax, result)
    what = result.params.get("planner", "")
    if result.params.get("sampler"):
        what += f" + {result.params['sampler']}"
    ax.set_title(title or f"{world.name}: {what} — {result.status.name}")
    return finish_plot(fig, ax, owned, out)
