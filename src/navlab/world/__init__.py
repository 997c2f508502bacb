"""Geometric worlds, scenes, world files and exact collision checking."""

from .collision import CollisionChecker
from .io import WorldFormatError, load_world, save_world, world_from_dict
from .scenes import SCENES
from .shapes import Circle, Polygon, Rectangle
from .world import Bounds, World

__all__ = [
    "Bounds", "Circle", "CollisionChecker", "Polygon", "Rectangle", "SCENES",
    "World", "WorldFormatError", "load_world", "save_world", "world_from_dict",
]
