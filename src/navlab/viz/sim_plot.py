"""Pictures of simulated runs: the world or map, the planned path, the true
and the odometry trajectories (like the seeds' RViz screenshots), and GIFs."""

from __future__ import annotations

from typing import Optional

import numpy as np

from .plot import _pyplot, draw_path, draw_world, finish_figure


def _draw_scene(ax, scene_world) -> None:
    from ..grid.occupancy import OccupancyGrid
    from .grid_plot import draw_grid

    if isinstance(scene_world, OccupancyGrid):
        draw_grid(ax, scene_world)
        ax.set_aspect("equal")
    else:
        draw_world(ax, scene_world, show_inflation=False)


def _moving(scene_world):
    """(index, shape, track) of each moving obstacle of a world (none for maps)."""
    from ..world.motion import track

    if not hasattr(scene_world, "obstacles"):
        return []
    return [(i, o, track(o, scene_world.bounds, i)) for i, o in enumerate(scene_world.obstacles)
            if o.motion is not None]


def _shape_patch(shape, **style):
    from matplotlib import patches

    from ..world.shapes import Circle, Rectangle

    if isinstance(shape, Circle):
        return patches.Circle(shape.center, shape.radius, **style)
    if isinstance(shape, Rectangle):
        return patches.Rectangle(shape.min, shape.max[0] - shape.min[0], shape.max[1] - shape.min[1], **style)
    return patches.Polygon(shape.points, closed=True, **style)


def _draw_moving(ax, moving, times) -> None:
    """Each moving obstacle's outline at ``times``, coloured by time, and the
    trail of its centre (the filled shape drawn by the world is at t = 0)."""
    from matplotlib import cm

    from ..world.motion import translated

    if not moving or len(times) == 0:
        return
    colours = cm.viridis(np.linspace(0.0, 1.0, len(times)))
    for _, shape, tr in moving:
        x0, y0, x1, y1 = shape.bbox()
        centre = np.array(((x0 + x1) / 2, (y0 + y1) / 2))
        trail = centre + np.array([tr.offset(t) for t in np.linspace(times[0], times[-1], 200)])
        ax.plot(trail[:, 0], trail[:, 1], ":", color="0.4", lw=0.8, zorder=3)
        for t, colour in zip(times, colours):
            ax.add_patch(_shape_patch(translated(shape, *tr.offset(t)), fill=False, ec=colour, lw=1.0, zorder=3))
    ax.plot([], [], ":", color="0.4", label=f"moving obstacles (outlines at t = {times[0]:g}…{times[-1]:.0f} s)")


def plot_run(scene_world, result, out: Optional[str] = None, raw_path=None, title: Optional[str] = None):
    """World, planned path, true trajectory, odometry, start and goal; moving
    obstacles as time-coloured outlines (dark: early, yellow: late) along
    their trails."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    _draw_scene(ax, scene_world)
    _draw_moving(ax, _moving(scene_world), np.linspace(0.0, result.time_s, 8))
    if raw_path is not None and len(raw_path) and hasattr(scene_world, "cell_to_world"):
        raw = scene_world.cell_to_world(raw_path)
        ax.plot(raw[:, 0], raw[:, 1], "-", color="tab:blue", lw=1.0, alpha=0.6, label="A* path")
    if result.path is not None:
        draw_path(ax, result.path, label="planned path", color="tab:green", lw=1.8)
    ax.plot(result.true_poses[:, 0], result.true_poses[:, 1], "-", color="tab:red", lw=1.6, label="true trajectory")
    ax.plot(result.odom_poses[:, 0], result.odom_poses[:, 1], "--", color="tab:purple", lw=1.0, label="odometry")
    ax.plot(*result.true_poses[0, :2], "o", color="tab:green", ms=8)
    ax.plot(*result.goal, "*", color="tab:red", ms=14)
    ax.set_title(title or f"{result.status.name} in {result.time_s:.1f} s, final error "
                 f"{1000 * result.error_true:.0f} mm")
    ax.legend(loc="best", fontsize=8)
    return finish_figure(fig, out)


def animate_run(scene_world, result, out: str, robot_radius: float, fps: int = 10, max_frames: int = 150,
                progress: Optional[bool] = None) -> None:
    """A GIF of the run (Pillow writer), at most ``max_frames`` frames, with
    the moving obstacles where they were at each frame. The file appears
    whole or not at all; a failed write is one ``ValueError`` naming it.
    ``progress``: a bar on stderr (default: when stderr is a terminal)."""
    plt = _pyplot()
    from matplotlib import patches
    from matplotlib.animation import FuncAnimation, PillowWriter

    from ..atomic import atomic_path
    from ..world.motion import translated

    fig, ax = plt.subplots(figsize=(5, 5))
    _draw_scene(ax, scene_world)
    moving = _moving(scene_world)
    # the world draws moving obstacles at t = 0: hide those and draw them where they are each frame
    for _, shape, _ in moving:
        ax.add_patch(_shape_patch(shape, fc="white", ec="white", lw=1.5, zorder=2.5))
    movers = []
    for _, shape, _ in moving:
        movers.append(_shape_patch(shape, fc="tab:blue", ec="k", alpha=0.8, zorder=4))
        ax.add_patch(movers[-1])
    if result.path is not None:
        draw_path(ax, result.path, label="planned path", color="tab:green", lw=1.5)
    ax.plot(*result.goal, "*", color="tab:red", ms=12)
    trail, = ax.plot([], [], "-", color="tab:red", lw=1.4)
    body = patches.Circle(result.true_poses[0, :2], robot_radius, fc="tab:orange", ec="k", zorder=6)
    ax.add_patch(body)
    heading, = ax.plot([], [], "-", color="k", lw=1.5, zorder=7)
    frames = np.unique(np.linspace(0, len(result.true_poses) - 1, min(max_frames, len(result.true_poses))).astype(int))

    def draw(i):
        x, y, th = result.true_poses[i]
        trail.set_data(result.true_poses[: i + 1, 0], result.true_poses[: i + 1, 1])
        body.center = (x, y)
        heading.set_data([x, x + robot_radius * np.cos(th)], [y, y + robot_radius * np.sin(th)])
        for patch, (_, shape, tr) in zip(movers, moving):
            moved = translated(shape, *tr.offset(float(result.t[i])))
            if hasattr(patch, "set_center"):
                patch.set_center(moved.center)
            elif hasattr(patch, "set_xy") and not hasattr(moved, "points"):
                patch.set_xy(moved.min)
            else:
                patch.set_xy(moved.points)
        ax.set_title(f"t = {result.t[i]:.1f} s")
        return trail, body, heading, *movers

    import sys

    from tqdm import tqdm

    show = sys.stderr.isatty() if progress is None else progress
    with tqdm(total=len(frames), desc=f"writing {out}", unit="frame", disable=not show, file=sys.stderr,
              leave=False) as bar:
        try:
            with atomic_path(out) as tmp:
                FuncAnimation(fig, draw, frames=frames, blit=False).save(
                    tmp, writer=PillowWriter(fps=fps), progress_callback=lambda k, n: bar.update(1))
        except OSError as exc:
            raise ValueError(f"{out}: cannot write the animation: {exc.strerror or exc}") from None
        finally:
            plt.close(fig)
