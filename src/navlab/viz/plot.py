"""Drawing planning results with matplotlib (Agg backend, files only)."""

from __future__ import annotations

from typing import Optional

import numpy as np

from .save import save_figure


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def finish_figure(fig, out: Optional[str], dpi: int = 110):
    """Write ``fig`` to ``out`` (when given) and release it; return it.

    The file appears whole or not at all (:func:`.save.save_figure`); a
    write that fails (disk full, no permission) is one ``ValueError`` naming
    the file.
    """
    if out:
        try:
            save_figure(fig, out, dpi=dpi, bbox_inches="tight")
        except OSError as exc:
            raise ValueError(f"{out}: cannot write the figure: {exc.strerror or exc}") from None
        except ValueError as exc:  # matplotlib: "Format 'txt' is not supported (supported formats: ...)"
            raise ValueError(f"{out}: cannot write the figure: {exc}") from None
        finally:
            _pyplot().close(fig)
    return fig


def draw_map(ax, grid, allow_unknown: bool = False, occupied: float = 0.35) -> None:
    """An occupancy grid as an image in the map frame: occupied cells dark
    (grey level ``occupied``), unknown cells mid grey (light when
    ``allow_unknown``), free cells white."""
    import matplotlib.transforms as mtransforms

    shade = np.full(grid.blocked.shape, 1.0)
    shade[grid.unknown] = 0.85 if allow_unknown else 0.6
    shade[grid.blocked] = occupied
    w, h = grid.width * grid.resolution, grid.height * grid.resolution
    ox, oy, yaw = grid.origin
    image = ax.imshow(shade, cmap="gray", vmin=0, vmax=1, origin="lower", extent=(0, w, 0, h),
                      interpolation="nearest", zorder=1)
    image.set_transform(mtransforms.Affine2D().rotate(yaw).translate(ox, oy) + ax.transData)


def draw_world(ax, world, show_inflation: bool = True) -> None:
    """Obstacles (filled), their inflation by the robot radius (dashed), bounds, start and goal."""
    from matplotlib import patches

    from ..world.shapes import Circle, Polygon, Rectangle

    r = world.robot_radius
    if getattr(world, "occupancy", None) is not None:
        draw_map(ax, world.occupancy, world.allow_unknown)
    for o in world.obstacles:
        if isinstance(o, Circle):
            ax.add_patch(patches.Circle(o.center, o.radius, color="0.35", zorder=2))
            if show_inflation and r > 0:
                ax.add_patch(patches.Circle(o.center, o.radius + r, fill=False, ls="--", lw=0.7, ec="0.5", zorder=2))
        elif isinstance(o, Rectangle):
            w, h = o.max[0] - o.min[0], o.max[1] - o.min[1]
            ax.add_patch(patches.Rectangle(o.min, w, h, color="0.35", zorder=2))
            if show_inflation and r > 0:
                ax.add_patch(patches.FancyBboxPatch(o.min, w, h, boxstyle=f"round,pad={r}", fill=False,
                                                    ls="--", lw=0.7, ec="0.5", zorder=2))
        elif isinstance(o, Polygon):
            ax.add_patch(patches.Polygon(o.points, closed=True, color="0.35", zorder=2))
            if show_inflation and r > 0:
                import shapely

                grown = shapely.Polygon(o.points).buffer(r)
                ax.plot(*grown.exterior.xy, ls="--", lw=0.7, color="0.5", zorder=2)
    b = world.bounds
    ax.plot([b.xmin, b.xmax, b.xmax, b.xmin, b.xmin], [b.ymin, b.ymin, b.ymax, b.ymax, b.ymin], color="k", lw=1)
    ax.plot(*world.start, "o", color="tab:green", ms=9, zorder=5, label="start")
    ax.plot(*world.goal, "*", color="tab:red", ms=14, zorder=5, label="goal")
    if world.goal_tolerance > 0:
        from matplotlib import patches as p

        ax.add_patch(p.Circle(world.goal, world.goal_tolerance, fill=False, ec="tab:red", lw=0.8, zorder=5))
    ax.set_xlim(b.xmin - 0.02 * b.diagonal, b.xmax + 0.02 * b.diagonal)
    ax.set_ylim(b.ymin - 0.02 * b.diagonal, b.ymax + 0.02 * b.diagonal)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def draw_tree(ax, nodes: np.ndarray, parent: np.ndarray) -> None:
    """Tree edges as one line collection."""
    from matplotlib.collections import LineCollection

    has_parent = parent >= 0
    segs = np.stack((nodes[parent[has_parent]], nodes[has_parent]), axis=1)
    ax.add_collection(LineCollection(segs, colors="tab:blue", linewidths=0.4, alpha=0.5, zorder=3))


def draw_path(ax, path: np.ndarray, label: str = "path", color: str = "tab:orange", **kw) -> None:
    if len(path):
        kw.setdefault("ls", "-")
        ax.plot(path[:, 0], path[:, 1], color=color, lw=kw.pop("lw", 2.2), zorder=4, label=label, **kw)


def plot_plan(world, result, out: Optional[str] = None, title: Optional[str] = None):
    """A figure of world, tree (if kept), path, start and goal; saved to ``out``."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    tree = result.tree if isinstance(result.tree, dict) else {}
    if "raster" in tree and getattr(world, "occupancy", None) is None:
        draw_map(ax, tree["raster"], occupied=0.8)  # the cells a grid planner saw, under the exact shapes
    draw_world(ax, world)
    if "nodes" in tree:
        draw_tree(ax, tree["nodes"], tree["parent"])
    if "raw_cells" in tree and "raster" in tree:  # a smoothed grid path: the path before smoothing
        raw = tree["raster"].cell_to_world(tree["raw_cells"])
        draw_path(ax, raw, label="grid path before smoothing", color="tab:blue", lw=1.0, ls="--")
    draw_path(ax, result.path, label=f"path {result.cost:.3f} m" if np.isfinite(result.cost) else "path")
    what = result.params.get("planner", "")
    if result.params.get("sampler"):
        what += f" + {result.params['sampler']}"
    ax.set_title(title or f"{world.name}: {what} — {result.status.name}")
    ax.legend(loc="upper left", fontsize=8)
    return finish_figure(fig, out)
