"""Matplotlib drawing of worlds, trees, paths and runs (never called by algorithms).

Every ``plot_*`` function makes a whole figure, or draws into the ``ax=``
it is given (a notebook's subplot) and returns that axes; it is built from
the ``draw_*`` functions, which draw one thing into an axes and can be
combined freely. See docs/viz.md.
"""

from .grid_plot import draw_grid, plot_grid_plan
from .legend import place_legend
from .plot import draw_map, draw_path, draw_tree, draw_world, plot_plan
from .save import save_figure
from .sim_plot import animate_run, draw_footprint, draw_run, draw_scene, plot_run

__all__ = ["animate_run", "draw_footprint", "draw_grid", "draw_map", "draw_path", "draw_run", "draw_scene", "draw_tree",
           "draw_world", "place_legend", "plot_grid_plan", "plot_plan", "plot_run", "save_figure"]
