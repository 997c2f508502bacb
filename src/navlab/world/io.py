"""YAML world files: reading with errors that name the file and the field.

The format (shared with other tools, so keep it exactly)::

    name: zigzag
    bounds: {x: [0, 10], y: [0, 10]}
    start: [1, 1]
    goal: [9, 9]
    robot_radius: 0.0          # metres; obstacles are inflated by it
    goal_tolerance: 0.0        # optional
    obstacles:
      - {type: circle, center: [6.5, 2.0], radius: 0.6}
      - {type: rectangle, min: [2.5, 0.0], max: [3.0, 7.0]}
      - {type: polygon, points: [[3.6, 7.8], [4.6, 8.2], [4.0, 9.2]]}
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable, Dict, Union

import yaml

from ..registry import suggest
from .motion import MotionFormatError, with_motion
from .shapes import Circle, Polygon, Rectangle
from .world import Bounds, World


class WorldFormatError(ValueError):
    """A world file is malformed; the message names the file and the field."""


_SHAPES: Dict[str, Callable[..., Any]] = {
    "circle": lambda d: Circle(center=d["center"], radius=d["radius"]),
    "rectangle": lambda d: Rectangle(min=d["min"], max=d["max"]),
    "polygon": lambda d: Polygon(points=tuple(d["points"])),
}
_SHAPE_KEYS = {"circle": {"center", "radius"}, "rectangle": {"min", "max"}, "polygon": {"points"}}
_TOP_KEYS = {"name", "bounds", "start", "goal", "robot_radius", "goal_tolerance", "obstacles"}


def world_from_dict(data: Any, source: str = "<dict>") -> World:
    """Build a :class:`World` from the YAML structure, validating every field."""

    def fail(field: str, message: str) -> WorldFormatError:
        return WorldFormatError(f"{source}: field '{field}': {message}")

    if not isinstance(data, dict):
        raise WorldFormatError(f"{source}: expected a mapping of world fields, got {type(data).__name__}")
    unknown = set(data) - _TOP_KEYS
    if unknown:
        key = sorted(unknown)[0]
        raise fail(key, f"unknown field; valid: {', '.join(sorted(_TOP_KEYS))}." + suggest(key, sorted(_TOP_KEYS)))
    for required in ("bounds", "start", "goal"):
        if required not in data:
            raise fail(required, "missing (required)")
    bounds_raw = data["bounds"]
    try:
        if not isinstance(bounds_raw, dict) or set(bounds_raw) != {"x", "y"}:
            raise ValueError("expected {x: [min, max], y: [min, max]}")
        (x0, x1), (y0, y1) = bounds_raw["x"], bounds_raw["y"]
        bounds = Bounds(float(x0), float(x1), float(y0), float(y1))
    except (ValueError, TypeError) as exc:
        raise fail("bounds", str(exc)) from None

    obstacles = []
    raw_obstacles = data.get("obstacles") or []
    if not isinstance(raw_obstacles, list):
        raise fail("obstacles", "expected a list")
    for i, item in enumerate(raw_obstacles):
        where = f"obstacles[{i}]"
        if not isinstance(item, dict) or "type" not in item:
            raise fail(where, "expected a mapping with a 'type' (circle, rectangle, polygon)")
        kind = item["type"]
        if kind not in _SHAPES:
            raise fail(where + ".type", f"unknown shape '{kind}'; valid: circle, polygon, rectangle." + suggest(str(kind), list(_SHAPES)))
        extra = set(item) - _SHAPE_KEYS[kind] - {"type", "motion"}
        missing = _SHAPE_KEYS[kind] - set(item)
        if missing or extra:
            bad = sorted(missing or extra)[0]
            raise fail(f"{where}.{bad}", "missing" if missing else f"not a field of a {kind}")
        try:
            obstacles.append(with_motion(_SHAPES[kind](item), item.get("motion")))
        except MotionFormatError as exc:  # moving obstacles: world/motion.py
            raise fail(f"{where}.{exc.field}", str(exc)) from None
        except (ValueError, TypeError) as exc:
            raise fail(where, str(exc)) from None

    kwargs: Dict[str, Any] = {}
    for key in ("start", "goal", "robot_radius", "goal_tolerance"):
        if key in data:
            kwargs[key] = data[key]
    for key in ("robot_radius", "goal_tolerance"):
        if key in kwargs and (isinstance(kwargs[key], bool) or not isinstance(kwargs[key], (int, float))):
            raise fail(key, f"expected a number of metres, got {kwargs[key]!r}")
    name = str(data.get("name") or Path(source).stem)
    try:
        return World(name=name, bounds=bounds, obstacles=tuple(obstacles), **kwargs)
    except ValueError as exc:
        field = next((k for k in ("start", "goal", "robot_radius", "goal_tolerance") if k in str(exc)), "world")
        raise fail(field, str(exc)) from None


def read_world_file(path: Union[str, os.PathLike]) -> World:
    """Read a YAML world file."""
    p = Path(path)
    try:
        text = p.read_text()
    except OSError as exc:
        raise WorldFormatError(f"{p}: cannot read: {exc.strerror}") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise WorldFormatError(f"{p}: not valid YAML: {exc}") from None
    return world_from_dict(data, str(p))


def save_world(world: World, path: Union[str, os.PathLike]) -> None:
    """Write a world as a YAML world file that :func:`load_world` reads back."""
    Path(path).write_text(yaml.safe_dump(world.to_dict(), sort_keys=False))


def load_world(source: Union[str, os.PathLike, World]) -> World:
    """A world from a YAML path, a built-in scene name, or a World (returned as is).

    Raises
    ------
    WorldFormatError
        The file is malformed (the message names the file and the field).
    navlab.registry.UnknownNameError
        Neither a file nor a scene name; the message lists the scenes.
    """
    from .scenes import SCENES

    if isinstance(source, World):
        return source
    text = os.fspath(source)
    if os.path.exists(text):
        return read_world_file(text)
    if text in SCENES:
        return SCENES.get(text)()
    if text.endswith((".yaml", ".yml")) or os.sep in text:
        raise WorldFormatError(f"{text}: no such file")
    SCENES.get(text)  # raises with the list of scenes and a hint
    raise AssertionError("unreachable")
