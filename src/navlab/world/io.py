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

Every number is checked against :mod:`navlab.limits` here, at the file
boundary, so the geometry kernels only ever see finite coordinates within
±``MAX_COORDINATE`` and lengths of at least ``MIN_LENGTH``. Whatever is wrong
with a file (not UTF-8, not YAML, empty, a directory, a wrong type or an
out-of-range number anywhere) raises one :class:`WorldFormatError` whose
message names the file and the field.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable, Dict, Tuple, Union

from ..angles import finite_heading
from ..atomic import write_text_atomic
from ..limits import check_coordinate, check_length, shown
from ..yamlcore import number_text
from ..registry import suggest
from .footprint import Footprint, FootprintError
from .errors import WorldFormatError  # noqa: F401  (defined apart so the SDF reader can raise it too)
from .motion import MotionFormatError, with_motion
from .shapes import Circle, Obstacle, Point, Polygon, Rectangle
from .world import Bounds, World

#: [bytes] largest world file read: about 40 000 obstacles, parsed in seconds and well under 256 MiB of
#: memory (PyYAML needs ~80 bytes per byte of text); larger environments belong in an occupancy map
MAX_FILE_BYTES = 2 * 2**20



class _FieldError(ValueError):
    """A bad value, raised while parsing and turned into a WorldFormatError naming the file and ``field``."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field


def _number(field: str, value: Any) -> float:
    """A finite coordinate within ±MAX_COORDINATE (see :mod:`navlab.limits`); a quoted number
    (``'1e-3'``) is taken as one (:func:`navlab.yamlcore.number_text`)."""
    value = number_text(value)  # may be inf: check_coordinate says "must be finite"
    try:
        return check_coordinate(field, value)
    except ValueError as exc:
        raise _FieldError(field, _short(exc)) from None


def _heading(field: str, value: Any) -> float:
    """A finite heading [rad] of any size (the World wraps it, and warns beyond ±2π), not a coordinate:
    a file's 1e8 was refused as 'out of range (≤ 1e+07 m)' where the API and the flags take it."""
    value = number_text(value)
    try:
        return finite_heading(field, value)
    except ValueError as exc:
        raise _FieldError(field, _short(exc)) from None


def _length(field: str, value: Any, allow_zero: bool = True) -> float:
    """A non-negative (or positive) length within [MIN_LENGTH, MAX_COORDINATE]."""
    v = _number(field, value)  # the same messages for a wrong type or a huge number
    try:
        return check_length(field, v, allow_zero=allow_zero)
    except ValueError as exc:
        raise _FieldError(field, _short(exc)) from None


def _pair(field: str, value: Any) -> Point:
    """Two coordinates ``[x, y]``."""
    if isinstance(value, (str, bytes, dict)) or not isinstance(value, (list, tuple)) or len(value) != 2:
        raise _FieldError(field, f"expected a pair [x, y] of numbers, got {_show(value)}")
    return (_number(f"{field}[0]", value[0]), _number(f"{field}[1]", value[1]))


def _interval(field: str, value: Any) -> Tuple[float, float]:
    """``[min, max]`` with max > min."""
    if isinstance(value, (str, bytes, dict)) or not isinstance(value, (list, tuple)) or len(value) != 2:
        raise _FieldError(field, f"expected [min, max], got {_show(value)}")
    lo, hi = _number(f"{field}[0]", value[0]), _number(f"{field}[1]", value[1])
    if not hi > lo:
        raise _FieldError(field, f"needs max > min, got [{lo:g}, {hi:g}]")
    return lo, hi


def _show(value: Any) -> str:
    """A bad value for a message, shortened: the message must stay one readable line."""
    return shown(value, 60)


def _short(exc: Exception, limit: int = 200) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _mapping(field: str, value: Any, keys: Dict[str, bool]) -> Dict[str, Any]:
    """``value`` as a mapping whose keys are among ``keys`` (True = required)."""
    if not isinstance(value, dict):
        raise _FieldError(field, f"expected a mapping, got {_show(value)}")
    valid = sorted(keys)
    for key in value:
        if not isinstance(key, str) or key not in keys:
            # a key that is no name (null, true, 1) as the file writes it, and nothing guessed for it: null was
            # "field 'None': ... Did you mean 'name'?" (attack, session 21)
            if key is None or isinstance(key, bool):
                name = {None: "null", True: "true", False: "false"}[key]
            else:
                name = str(key)
            raise _FieldError(f"{field}.{name}" if field else name, f"unknown field; valid: {', '.join(valid)}."
                              + (suggest(name, valid) if isinstance(key, str) else ""))
    for key, required in keys.items():
        if required and key not in value:
            raise _FieldError(f"{field}.{key}" if field else key, "missing (required)")
    return value


# --- obstacles: one parser per shape -------------------------------------------------------------

def _circle(where: str, item: Dict[str, Any]) -> Circle:
    return Circle(center=_pair(f"{where}.center", item["center"]),
                  radius=_length(f"{where}.radius", item["radius"], allow_zero=False))


def _rectangle(where: str, item: Dict[str, Any]) -> Rectangle:
    lo, hi = _pair(f"{where}.min", item["min"]), _pair(f"{where}.max", item["max"])
    if not (hi[0] > lo[0] and hi[1] > lo[1]):
        raise _FieldError(f"{where}.max", f"must exceed min {lo} in x and y, got {hi}")
    return Rectangle(min=lo, max=hi)


def _polygon(where: str, item: Dict[str, Any]) -> Polygon:
    raw = item["points"]
    if isinstance(raw, (str, bytes, dict)) or not isinstance(raw, (list, tuple)):
        raise _FieldError(f"{where}.points", f"expected a list of [x, y] pairs, got {_show(raw)}")
    if len(raw) < 3:
        raise _FieldError(f"{where}.points", f"a polygon needs at least 3 points, got {len(raw)}")
    points = tuple(_pair(f"{where}.points[{j}]", p) for j, p in enumerate(raw))
    try:
        return Polygon(points=points)
    except ValueError as exc:  # not simple, or no area
        raise _FieldError(f"{where}.points", _short(exc)) from None


#: shape name → (parser, its fields: True = required)
OBSTACLE_PARSERS: Dict[str, Tuple[Callable[[str, Dict[str, Any]], Obstacle], Dict[str, bool]]] = {
    "circle": (_circle, {"center": True, "radius": True}),
    "rectangle": (_rectangle, {"min": True, "max": True}),
    "polygon": (_polygon, {"points": True}),
}


def _obstacle(where: str, item: Any) -> Obstacle:
    """One entry of ``obstacles``: ``{type: <shape>, <the shape's fields>}``."""
    shapes = sorted(OBSTACLE_PARSERS)
    if not isinstance(item, dict) or "type" not in item:
        raise _FieldError(where, f"expected a mapping with a 'type' ({', '.join(shapes)}), got {_show(item)}")
    kind = item["type"]
    if not isinstance(kind, str) or kind not in OBSTACLE_PARSERS:
        raise _FieldError(f"{where}.type", f"unknown shape {_show(kind)}; valid: {', '.join(shapes)}."
                          + suggest(str(kind), shapes))
    parse, fields = OBSTACLE_PARSERS[kind]
    _mapping(where, item, {"type": True, "motion": False, **fields})
    try:
        return with_motion(parse(where, item), item.get("motion"))  # moving obstacles: world/motion.py
    except MotionFormatError as exc:
        raise _FieldError(f"{where}.{exc.field}", _short(exc)) from None


# --- the whole document ---------------------------------------------------------------------------

_TOP_FIELDS = {"name": False, "bounds": True, "start": True, "goal": True, "robot_radius": False,
               "goal_tolerance": False, "obstacles": False, "footprint": False, "turning_radius": False}


def _point_or_pose(field: str, value: Any) -> Tuple[float, ...]:
    """``[x, y]`` or a pose ``[x, y, theta]`` (theta in radians)."""
    if isinstance(value, (list, tuple)) and len(value) == 3:
        return _pair(field, value[:2]) + (_heading(f"{field}[2]", value[2]),)
    if isinstance(value, (str, bytes, dict)) or not isinstance(value, (list, tuple)) or len(value) != 2:
        raise _FieldError(field, f"expected [x, y] or a pose [x, y, theta] of numbers, got {_show(value)}")
    return _pair(field, value)


def _world(data: Any, default_name: str) -> World:
    if not isinstance(data, dict):
        raise _FieldError("", f"expected a mapping of world fields, got {type(data).__name__}")
    _mapping("", data, _TOP_FIELDS)
    bounds_raw = data["bounds"]
    if not isinstance(bounds_raw, dict) or set(bounds_raw) != {"x", "y"}:
        raise _FieldError("bounds", f"expected {{x: [min, max], y: [min, max]}}, got {_show(bounds_raw)}")
    (x0, x1), (y0, y1) = _interval("bounds.x", bounds_raw["x"]), _interval("bounds.y", bounds_raw["y"])

    raw_obstacles = data.get("obstacles")
    if raw_obstacles is None:
        raw_obstacles = []
    if not isinstance(raw_obstacles, list):
        raise _FieldError("obstacles", f"expected a list, got {_show(raw_obstacles)}")
    obstacles = tuple(_obstacle(f"obstacles[{i}]", item) for i, item in enumerate(raw_obstacles))

    name = data.get("name")
    if name is None or name == "":
        name = default_name
    elif isinstance(name, bool) or not isinstance(name, (str, int, float)):
        raise _FieldError("name", f"expected text, got {_show(name)}")
    kwargs: Dict[str, Any] = {"start": _point_or_pose("start", data["start"]),
                              "goal": _point_or_pose("goal", data["goal"])}
    if data.get("footprint") is not None:
        try:
            kwargs["footprint"] = Footprint.from_value(data["footprint"])
        except FootprintError as exc:
            raise _FieldError("footprint", _short(exc)) from None
    for key in ("robot_radius", "goal_tolerance"):
        if data.get(key) is not None:
            kwargs[key] = _length(key, data[key])
    if data.get("turning_radius") is not None:
        # the world's robot's smallest turning radius: the heading-aware planners' default for it
        kwargs["meta"] = {"turning_radius": _length("turning_radius", data["turning_radius"], allow_zero=False)}
    try:
        return World(name=str(name), bounds=Bounds(x0, x1, y0, y1), obstacles=obstacles, **kwargs)
    except ValueError as exc:  # a rule the World adds beyond the per-field checks above
        field = next((k for k in ("start", "goal", "robot_radius", "goal_tolerance", "bounds", "obstacles", "footprint")
                      if k in str(exc)), "world")
        raise _FieldError(field, _short(exc)) from None


def world_from_dict(data: Any, source: str = "<dict>") -> World:
    """Build a :class:`World` from the YAML structure, validating every field.

    Raises
    ------
    WorldFormatError
        Anything malformed; the message is ``"<source>: field '<field>': <what>"``.
    """
    try:
        return _world(data, Path(source).stem)
    except _FieldError as exc:
        what = str(exc)
        if not exc.field:
            raise WorldFormatError(f"{source}: {what}") from None
        if what.startswith(exc.field + " "):
            # a check that names its value reads on from the field, not after it a second time: "field
            # 'obstacles[0].radius' must be positive", "field 'start[0]' = 1e+08 is out of range"
            raise WorldFormatError(f"{source}: field '{exc.field}'{what[len(exc.field):]}") from None
        raise WorldFormatError(f"{source}: field '{exc.field}': {what}") from None
    except RecursionError:  # a YAML document nested thousands deep
        raise WorldFormatError(f"{source}: nested too deeply to be a world file") from None


def read_yaml_document(path: Union[str, os.PathLike]) -> Any:
    """The YAML document in ``path`` (UTF-8, at most :data:`MAX_FILE_BYTES` = 2 MiB), or None when empty.

    Read through :func:`navlab.yamlio.read_yaml`: a regular file only, aliases
    counted at every use, no key given twice.

    Raises
    ------
    WorldFormatError
        The file cannot be read (missing, a directory, a FIFO, no permission),
        is too large (in bytes or once its aliases are expanded), is not UTF-8,
        is not YAML or repeats a key; the message names the file.
    """
    from ..yamlio import read_yaml  # PyYAML only when a file is read: a built-in scene needs none

    return read_yaml(path, WorldFormatError, MAX_FILE_BYTES, what="world file")


def read_world_file(path: Union[str, os.PathLike]) -> World:
    """Read a YAML world file (see :func:`read_yaml_document`).

    Raises
    ------
    WorldFormatError
        The file cannot be read, is not UTF-8 YAML, is empty, or is malformed;
        the message names the file.
    """
    data = read_yaml_document(path)
    if data is None:
        raise WorldFormatError(f"{path}: empty; expected the world fields (bounds, start, goal, ...)")
    return world_from_dict(data, str(path))


def save_world(world: World, path: Union[str, os.PathLike]) -> None:
    """Write a world as a YAML world file that :func:`load_world` reads back (atomically)."""
    import yaml

    write_text_atomic(path, yaml.safe_dump(world.to_dict(), sort_keys=False))


def load_world(source: Union[str, os.PathLike, World]) -> World:
    """A world from a YAML path, a Gazebo SDF ``.world`` (see :mod:`navlab.world.sdf`),
    a built-in scene name, or a World (returned as is).

    Raises
    ------
    WorldFormatError
        The file is malformed or unreadable (the message names the file and the field).
    navlab.registry.UnknownNameError
        Neither a file nor a scene name; the message lists the scenes.
    """
    from .scenes import SCENES

    if isinstance(source, World):
        return source
    if not isinstance(source, (str, bytes, os.PathLike)):
        raise WorldFormatError(f"a world must be a file path, a scene name or a World, got {source!r}")
    text = os.fspath(source)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    if os.path.exists(text):
        if text.lower().endswith((".world", ".sdf")):
            from .sdf import read_sdf

            return read_sdf(text)
        return read_world_file(text)
    if text in SCENES:
        return SCENES.get(text)()
    if text.endswith((".yaml", ".yml", ".world", ".sdf")) or os.sep in text:
        raise WorldFormatError(f"{text}: no such file")
    SCENES.get(text)  # raises with the list of scenes and a hint
    raise AssertionError("unreachable")
