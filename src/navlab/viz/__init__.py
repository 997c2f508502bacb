"""Matplotlib drawing of worlds, trees and paths (never called by algorithms)."""

from .plot import draw_path, draw_tree, draw_world, plot_plan
from .save import save_figure

__all__ = ["draw_path", "draw_tree", "draw_world", "plot_plan", "save_figure"]
