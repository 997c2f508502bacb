"""Pictures of simulated runs: the world or map, the planned path, the true
and the odometry trajectories (like the seeds' RViz screenshots), and GIFs."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..errors import ParameterError
from .plot import _pyplot, draw_footprint, draw_path, draw_world, finish_plot, new_axes


def draw_scene(ax, scene_world, moving: bool = True) -> None:
    """A simulated world (shapes) or map (occupancy grid), axes in metres;
    ``moving=False`` leaves the moving obstacles out (drawn per frame instead)."""
    from ..grid.occupancy import OccupancyGrid
    from .grid_plot import draw_grid

    if isinstance(scene_world, OccupancyGrid):
        draw_grid(ax, scene_world)
    else:
        draw_world(ax, scene_world, show_inflation=False, moving=moving)


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


def draw_run(ax, result, raw_path=None, scene_world=None, footprint=None) -> None:
    """A run's planned path, replans, true trajectory (on top), odometry, start and goal, and
    the robot's ``footprint`` (a :class:`~navlab.world.footprint.Footprint`) along the way."""
    if raw_path is not None and len(raw_path) and hasattr(scene_world, "cell_to_world"):
        raw = scene_world.cell_to_world(raw_path)
        ax.plot(raw[:, 0], raw[:, 1], "-", color="tab:blue", lw=1.0, alpha=0.6, label="A* path", zorder=3)
    if result.path is not None:
        draw_path(ax, result.path, label="planned path", color="tab:green", lw=1.8, zorder=4)
    for k, replanned in enumerate(getattr(result, "replans", ())):
        draw_path(ax, replanned, label=f"replans ({len(result.replans)})" if k == 0 else None,
                  color="tab:olive", lw=1.2, ls="--", zorder=4.2)
        ax.plot(*replanned[0, :2], "x", color="tab:olive", ms=7, zorder=4.2)
    # the true trajectory above every planned path: it is what happened
    ax.plot(result.odom_poses[:, 0], result.odom_poses[:, 1], "--", color="tab:purple", lw=1.0, label="odometry",
            zorder=5)
    ax.plot(result.true_poses[:, 0], result.true_poses[:, 1], "-", color="tab:red", lw=1.6, label="true trajectory",
            zorder=5.5)
    ax.plot(*result.true_poses[0, :2], "o", color="tab:green", ms=8, zorder=6)
    ax.plot(*result.goal, "*", color="tab:red", ms=14, zorder=6)
    if footprint is not None:
        draw_footprint(ax, footprint, result.true_poses)


def plot_run(scene_world, result, out: Optional[str] = None, raw_path=None, title: Optional[str] = None, ax=None,
             footprint=None):
    """World, planned path and replans, true trajectory, odometry, start and
    goal; moving obstacles as time-coloured outlines (dark: early, yellow:
    late) along their trails.

    With ``ax``, draws into those axes and returns them; otherwise returns a
    new figure (closed once written to ``out``), as :func:`navlab.viz.plot_plan`.
    """
    fig, ax, owned = new_axes(ax)
    draw_scene(ax, scene_world)
    _draw_moving(ax, _moving(scene_world), np.linspace(0.0, result.time_s, 8))
    draw_run(ax, result, raw_path, scene_world, footprint)
    ax.set_title(title or f"{result.status.name} in {result.time_s:.1f} s, final error "
                 f"{1000 * result.error_true:.0f} mm")
    return finish_plot(fig, ax, owned, out)


#: Longest GIF written by default (s of animation) and its frame rate: a
#: one-minute run becomes a 15 s GIF at 10 fps (150 frames).
GIF_FPS, GIF_MAX_FRAMES = 10, 150


def animate_run(scene_world, result, out: str, robot_radius: float, fps: int = GIF_FPS,
                max_frames: int = GIF_MAX_FRAMES, progress: Optional[bool] = None, footprint=None) -> None:
    """A GIF of the run (Pillow writer): the robot, its trail, the moving
    obstacles where they were at each frame, the planned path and replans,
    with a legend; sized to the world's aspect ratio.

    At most ``max_frames`` frames, evenly spaced in time; only the artists
    that move are redrawn each frame (the static scene is rendered once), so
    a one-minute run takes a few seconds. The file appears whole or not at
    all; a failed write is one ``ParameterError`` naming it. ``progress``: a bar
    on stderr (default: when stderr is a terminal).
    """
    import sys

    from matplotlib import patches
    from PIL import Image
    from tqdm import tqdm

    from ..atomic import atomic_path
    from ..world.motion import translated

    plt = _pyplot()
    x0, x1, y0, y1 = _extent(scene_world)
    aspect = (x1 - x0) / max(y1 - y0, 1e-9)
    # the axes keep the world's aspect ratio; margins for labels, title and legend are fixed in inches
    ax_w = 3.8
    ax_h = ax_w / max(aspect, 1e-3)
    if ax_h > 4.5:
        ax_w, ax_h = ax_w * 4.5 / ax_h, 4.5
    left, right, bottom, top = 0.75, 2.1, 0.55, 0.4
    fig_w, fig_h = left + ax_w + right, bottom + ax_h + top
    fig = plt.figure(figsize=(fig_w, fig_h), dpi=80)
    ax = fig.add_axes((left / fig_w, bottom / fig_h, ax_w / fig_w, ax_h / fig_h))
    draw_scene(ax, scene_world, moving=False)  # moving obstacles are drawn where they are, per frame
    moving = _moving(scene_world)
    if result.path is not None:
        draw_path(ax, result.path, label="planned path", color="tab:green", lw=1.5)
    for k, replanned in enumerate(getattr(result, "replans", ())):
        draw_path(ax, replanned, label=f"replans ({len(result.replans)})" if k == 0 else None,
                  color="tab:olive", lw=1.0, ls="--")
    if not hasattr(scene_world, "bounds"):  # a world draws its own goal; a map does not
        ax.plot(*result.goal, "*", color="tab:red", ms=12, label="goal", zorder=6)
    movers = [_shape_patch(shape, fc="tab:blue", ec="k", alpha=0.8, zorder=4,
                           label="moving obstacle" if k == 0 else None) for k, (_, shape, _) in enumerate(moving)]
    for patch in movers:
        ax.add_patch(patch)
    trail, = ax.plot([], [], "-", color="tab:red", lw=1.4, label="true trajectory", zorder=5)
    shaped = footprint is not None and not footprint.is_disc
    body = patches.Polygon(footprint.at(result.true_poses[0]), closed=True, fc="tab:orange", ec="k", zorder=6,
                           label="robot") if shaped else \
        patches.Circle(result.true_poses[0, :2], robot_radius, fc="tab:orange", ec="k", zorder=6, label="robot")
    ax.add_patch(body)
    heading, = ax.plot([], [], "-", color="k", lw=1.5, zorder=7)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, fontsize=8)
    clock = ax.set_title(" ")  # the title counts the time, frame by frame
    dynamic = [trail, body, heading, clock, *movers]
    for artist in dynamic:
        artist.set_animated(True)
    fig.canvas.draw()
    background = fig.canvas.copy_from_bbox(fig.bbox)  # the static scene, rendered once
    frames = np.unique(np.linspace(0, len(result.true_poses) - 1,
                                   min(max_frames, len(result.true_poses))).astype(int))

    def render(i: int) -> np.ndarray:
        x, y, th = result.true_poses[i]
        trail.set_data(result.true_poses[: i + 1, 0], result.true_poses[: i + 1, 1])
        if shaped:
            body.set_xy(footprint.at(result.true_poses[i]))
        else:
            body.center = (x, y)
        heading.set_data([x, x + robot_radius * np.cos(th)], [y, y + robot_radius * np.sin(th)])
        for patch, (_, shape, tr) in zip(movers, moving):
            moved = translated(shape, *tr.offset(float(result.t[i])))
            if hasattr(patch, "set_center"):
                patch.set_center(moved.center)
            elif hasattr(moved, "points"):
                patch.set_xy(moved.points)
            else:
                patch.set_xy(moved.min)
        # the outcome only once it has happened: mid-run the robot has not REACHED anything yet
        outcome = result.status.name if i == len(result.true_poses) - 1 else "running"
        clock.set_text(f"t = {result.t[i]:.1f} s of {result.time_s:.1f} s: {outcome}")
        fig.canvas.restore_region(background)
        for artist in dynamic:
            ax.draw_artist(artist)
        return Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3].copy())

    # One palette for every frame, from the last (its trail is complete):
    # choosing a palette per frame was two thirds of the time
    palette = render(int(frames[-1])).quantize(colors=64, method=Image.Quantize.MEDIANCUT)

    show = sys.stderr.isatty() if progress is None else progress
    try:
        with tqdm(total=len(frames), desc=f"writing {out}", unit="frame", disable=not show, file=sys.stderr,
                  leave=False) as bar:
            images = []
            for i in frames:
                images.append(render(int(i)).quantize(palette=palette, dither=Image.Dither.NONE))
                bar.update(1)
        with atomic_path(out) as tmp:
            images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                           duration=int(round(1000 / fps)), loop=0)
    except OSError as exc:
        raise ParameterError(f"{out}: cannot write the animation: {exc.strerror or exc}") from None
    finally:
        plt.close(fig)


def _extent(scene_world):
    """(xmin, xmax, ymin, ymax) of a world or map, metres."""
    if hasattr(scene_world, "bounds"):
        b = scene_world.bounds
        return b.xmin, b.xmax, b.ymin, b.ymax
    x0, y0 = scene_world.origin[0], scene_world.origin[1]
    return x0, x0 + scene_world.width * scene_world.resolution, y0, y0 + scene_world.height * scene_world.resolution
