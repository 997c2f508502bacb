"""Every kind of planning source read into one :class:`~navlab.world.World`.

A *source* is what a user points navlab at: a built-in scene name, a YAML
world file, a ROS map_server map (YAML + PGM/PNG), a Moving AI ``.map``, a
:class:`World` or an :class:`~navlab.grid.OccupancyGrid`. :func:`load_source`
turns any of them into a World, so planners, plots and the CLI deal with one
thing. A world YAML and a map YAML share the ``.yaml`` suffix; they are told
apart by content (a map has ``image``, a world has ``bounds``).

Maps carry no start or goal: a query on a map must supply both.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import replace
from pathlib import Path
from typing import Any, Optional, Tuple

import numpy as np

from ..angles import HeadingWarning
from ..errors import NavlabError, ParameterError
from ..limits import check_coordinate, check_flag, check_length
from .io import WorldFormatError, load_world, read_yaml_document
from .world import World


class MissingQueryError(NavlabError):
    """A map source was given without a start or a goal.

    Attributes
    ----------
    field : str
        ``"start"`` or ``"goal"`` (the CLI names its flag from it).
    """

    def __init__(self, field: str, source: str) -> None:
        super().__init__(f"{source} is a map and has no {field}: give {field}=(x, y) in metres")
        self.field = field


def source_kind(source: Any) -> str:
    """What ``source`` is: ``"world"``, ``"occupancy"``, ``"scene"``,
    ``"world_file"``, ``"ros_map"`` or ``"movingai_map"``.

    Raises
    ------
    WorldFormatError
        A file that is neither a world nor a map (the message says why).
    navlab.registry.UnknownNameError
        Not a file and not a scene name (the message lists the scenes).
    """
    from ..grid.occupancy import OccupancyGrid
    from .scenes import SCENES

    if isinstance(source, World):
        return "world"
    if isinstance(source, OccupancyGrid):
        return "occupancy"
    if not isinstance(source, (str, os.PathLike)):
        raise ParameterError(f"source must be a scene name, a file path, a World or an OccupancyGrid, "
                        f"got {type(source).__name__}")
    path = Path(source)
    if not path.exists():
        text = os.fspath(source)
        if text in SCENES:
            return "scene"
        if path.suffix.lower() in (".yaml", ".yml", ".map", ".pgm", ".png", ".world", ".sdf") or os.sep in text:
            raise WorldFormatError(f"{text}: no such file")
        SCENES.get(text)  # raises with the list of scenes and a hint
    if path.is_dir():
        raise WorldFormatError(f"{path}: is a folder, not a world or map file")
    suffix = path.suffix.lower()
    if suffix == ".map":
        return "movingai_map"
    if suffix in (".pgm", ".png"):
        raise WorldFormatError(f"{path}: an image alone is not a map; give the map_server YAML that names it")
    if suffix in (".world", ".sdf"):
        return "world_file"
    if suffix not in (".yaml", ".yml"):
        raise WorldFormatError(f"{path}: unknown source format '{suffix}' (expected a world or map_server "
                               ".yaml, a Gazebo SDF .world, or a Moving AI .map)")
    data = read_yaml_document(path)
    if isinstance(data, dict) and "image" in data:
        return "ros_map"
    if isinstance(data, dict) and ("bounds" in data or "obstacles" in data):
        return "world_file"
    raise WorldFormatError(f"{path}: neither a world file (it would have 'bounds', 'start', 'goal') nor a "
                           "map_server map (it would have 'image', 'resolution', 'origin')")


def _point_or_none(value: Any, field: str):
    if value is None:
        return None
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") or len(value) not in (2, 3):
        raise ParameterError(f"{field} must be two numbers (x, y) in metres or a pose (x, y, theta), got {value!r}")
    point = (check_coordinate(f"{field} x", value[0]), check_coordinate(f"{field} y", value[1]))
    return point + tuple(value[2:])  # a heading is checked by the World


def load_source(source: Any, start=None, goal=None, robot_radius: Optional[float] = None,
                goal_tolerance: Optional[float] = None, allow_unknown: Optional[bool] = None) -> World:
    """Read any planning source into a :class:`World`.

    Parameters
    ----------
    source : str, os.PathLike, World or OccupancyGrid
        A built-in scene name, a world YAML, a map_server YAML, a Moving AI
        ``.map``, a World or an OccupancyGrid.
    start, goal : (x, y), optional
        Metres. They override the source's own; a map has none, so for a map
        both are required.
    robot_radius, goal_tolerance : float, optional
        Metres; override the source's (maps default to 0).
    allow_unknown : bool, optional
        For maps: whether unknown cells are free (default: occupied).

    Raises
    ------
    MissingQueryError
        A map without ``start`` or ``goal``.
    WorldFormatError, navlab.grid.MapFormatError, navlab.ParameterError
        Malformed files or values; the message names the file and the field.
    """
    start, goal = _point_or_none(start, "start"), _point_or_none(goal, "goal")
    changes: dict = {}
    if robot_radius is not None:
        changes["robot_radius"] = check_length("robot_radius", robot_radius)
    if goal_tolerance is not None:
        changes["goal_tolerance"] = check_length("goal_tolerance", goal_tolerance)
    if allow_unknown is not None:
        changes["allow_unknown"] = check_flag("allow_unknown", allow_unknown)

    kind = source_kind(source)
    superseded = []  # the source's own heading warnings, said only for the headings the query keeps
    if kind in ("world", "scene", "world_file"):
        if kind == "world" or (start is None and goal is None):
            world = source if kind == "world" else load_world(source)
        else:
            with warnings.catch_warnings(record=True) as superseded:
                warnings.simplefilter("always")
                world = load_world(source)
        loaded = world
    else:
        if kind == "occupancy":
            grid, label = source, f"grid '{source.name}'"
        else:
            from ..grid.mapio import load_movingai_map, load_ros_map

            grid = load_movingai_map(source) if kind == "movingai_map" else load_ros_map(source)
            label = os.fspath(source)
        for field, value in (("start", start), ("goal", goal)):
            if value is None:
                raise MissingQueryError(field, label)
        world = World.from_grid(grid, start, goal, where=label)
    if start is not None or goal is not None:
        world = world.with_query(start, goal)
    for caught in superseded:  # (a query that failed above says only why: one line, not a note about the file)
        end = str(caught.message).split(" ")[0].split("_")[0]  # "start theta 90 ..." or "goal_heading 400 ..."
        if issubclass(caught.category, HeadingWarning) and end in ("start", "goal") and \
                getattr(world, f"{end}_heading") != getattr(loaded, f"{end}_heading"):
            continue  # the file's heading, replaced by the query's: warning of it would name a heading not planned
        warnings.warn_explicit(caught.message, caught.category, caught.filename, caught.lineno)
    return replace(world, **changes) if changes else world

