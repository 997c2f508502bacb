"""Pictures of simulated runs: the world or map, the planned path, the true
and the odometry trajectories (like the seeds' RViz screenshots), and GIFs."""

from __future__ import annotations

from typing import Optional

import numpy as np

from .plot import _pyplot, draw_path, draw_world, save_figure


def _draw_scene(ax, scene_world) -> None:
    from ..grid.occupancy import OccupancyGrid
    from .grid_plot import draw_grid

    if isinstance(scene_world, OccupancyGrid):
        draw_grid(ax, scene_world)
        ax.set_aspect("equal")
    else:
        draw_world(ax, scene_world, show_inflation=False)


def plot_run(scene_world, result, out: Optional[str] = None, raw_path=None, title: Optional[str] = None):
    """World, planned path, true trajectory, odometry, start and goal."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    _draw_scene(ax, scene_world)
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
    return save_figure(fig, out)


def animate_run(scene_world, result, out: str, robot_radius: float, fps: int = 10, max_frames: int = 150) -> None:
    """A GIF of the run (Pillow writer), at most ``max_frames`` frames."""
    plt = _pyplot()
    from matplotlib import patches
    from matplotlib.animation import FuncAnimation, PillowWriter

    fig, ax = plt.subplots(figsize=(5, 5))
    _draw_scene(ax, scene_world)
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
        ax.set_title(f"t = {result.t[i]:.1f} s")
        return trail, body, heading

    FuncAnimation(fig, draw, frames=frames, blit=False).save(out, writer=PillowWriter(fps=fps))
    plt.close(fig)
