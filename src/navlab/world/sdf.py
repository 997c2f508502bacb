"""Gazebo SDF ``.world`` files as navlab worlds (the BARN benchmark's format).

What is read: every ``<model>`` of the ``<world>`` whose links have
``<collision>`` geometry of type ``cylinder`` (a circle of its radius) or
``box`` (a rectangle of its x and y sizes, rotated by the yaw), placed by the
model, link and collision poses composed in the plane. When the file has a
``<state>`` section (Gazebo saves one), the models' poses there win over the
ones in their definitions, as Gazebo itself loads them. ``plane`` geometry
(the ground), lights, plugins, visuals and physics are ignored. Anything else
— a ``mesh``, a ``sphere``, a tilted model, an ``<include>`` of a model from
Gazebo's database — is refused with one line naming the model, because
leaving it out would put a robot through a wall.

The SDF specification: http://sdformat.org/spec (``pose`` is
``x y z roll pitch yaw`` in metres and radians).

An SDF world has no start or goal; unless given, they are BARN's
(:data:`DEFAULT_START` → :data:`DEFAULT_GOAL`, the protocol of
``the-barn-challenge``'s ``run.py``). The bounds are the box around the
obstacles, start and goal grown by :data:`BOUNDS_MARGIN`.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .errors import WorldFormatError
from .shapes import Circle, Polygon, Rectangle
from .world import Bounds, World

#: the largest SDF file read (a BARN world is 0.45 MB)
MAX_SDF_BYTES = 64 * 1024 * 1024
#: the most obstacles one SDF world may have
MAX_SDF_OBSTACLES = 200_000
#: [m, m] BARN's start position (its heading, 1.57 rad, is the run's, not the world's)
DEFAULT_START = (-2.0, 3.0)
#: [m, m] BARN's goal, 10 m ahead of the start
DEFAULT_GOAL = (-2.0, 13.0)
#: [m] free room around the obstacles, start and goal
BOUNDS_MARGIN = 1.0
#: [rad] a roll or pitch above this is a tilted model, which a plan view cannot hold
TILT_TOLERANCE = 1e-6
#: the deepest nesting of models read (Gazebo's own worlds nest two or three; 2 000 was a RecursionError)
MAX_MODEL_DEPTH = 100
#: geometry without extent in the plane, or none to collide with
IGNORED_GEOMETRY = ("plane", "empty")

Pose2 = Tuple[float, float, float]


def _pose(element: Optional[ET.Element], model: str) -> Pose2:
    """(x, y, yaw) of a ``<pose>`` child (identity when absent)."""
    if element is None:
        return (0.0, 0.0, 0.0)
    node = element.find("pose")
    if node is None:
        return (0.0, 0.0, 0.0)
    frame = node.get("relative_to") or ""
    if frame not in ("", "world") and node.get("relative_to") is not None:
        raise WorldFormatError(f"model '{model}': pose relative_to '{frame}' is not supported")
    text = (node.text or "").split()
    try:
        values = [float(v) for v in text]
    except ValueError:
        raise WorldFormatError(f"model '{model}': malformed pose {node.text!r} (expected 6 numbers "
                               "x y z roll pitch yaw)") from None
    if len(values) != 6 or not all(math.isfinite(v) for v in values):
        raise WorldFormatError(f"model '{model}': malformed pose {node.text!r} (expected 6 finite numbers "
                               "x y z roll pitch yaw)")
    if abs(math.remainder(values[3], math.pi)) > TILT_TOLERANCE or abs(math.remainder(values[4], math.pi)) \
            > TILT_TOLERANCE:
        raise WorldFormatError(f"model '{model}': tilted (roll {values[3]:g}, pitch {values[4]:g} rad); a plan "
                               "view holds only upright models")
    return values[0], values[1], values[5]


def _compose(a: Pose2, b: Pose2) -> Pose2:
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def _number(node: Optional[ET.Element], field: str, model: str, count: int = 1) -> List[float]:
    text = (node.text or "").split() if node is not None else []
    try:
        values = [float(v) for v in text]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) and v > 0 for v in values):
        raise WorldFormatError(f"model '{model}': {field} must be {count} positive number(s), "
                               f"got {None if node is None else node.text!r}")
    return values


def _shape(geometry: ET.Element, at: Pose2, model: str):
    """The obstacle one ``<geometry>`` makes at pose ``at``, or None when it is ignored."""
    kinds = [child.tag for child in geometry]
    if not kinds or kinds[0] in IGNORED_GEOMETRY:
        return None
    kind = kinds[0]
    if kind == "cylinder":
        (radius,) = _number(geometry.find("cylinder/radius"), "cylinder radius", model)
        return Circle((at[0], at[1]), radius)
    if kind == "box":
        sx, sy, _ = _number(geometry.find("box/size"), "box size", model, 3)
        yaw = math.remainder(at[2], math.pi / 2)
        if abs(yaw) < 1e-12:
            # axis-aligned (a quarter turn swaps the sides)
            quarter = round(math.remainder(at[2], 2 * math.pi) / (math.pi / 2)) % 2
            hx, hy = (sy / 2, sx / 2) if quarter else (sx / 2, sy / 2)
            return Rectangle((at[0] - hx, at[1] - hy), (at[0] + hx, at[1] + hy))
        c, s = math.cos(at[2]), math.sin(at[2])
        corners = [(at[0] + c * x - s * y, at[1] + s * x + c * y)
                   for x, y in ((-sx / 2, -sy / 2), (sx / 2, -sy / 2), (sx / 2, sy / 2), (-sx / 2, sy / 2))]
        return Polygon(corners)
    raise WorldFormatError(f"model '{model}': {kind} collision geometry cannot be read (navlab reads cylinder and "
                           "box; a mesh or other shape would have to be replaced by them)")


def _state_poses(world: ET.Element) -> Dict[str, Pose2]:
    """Model poses from the world's ``<state>`` section, by model name."""
    out: Dict[str, Pose2] = {}
    state = world.find("state")
    if state is None:
        return out
    for model in state.findall("model"):
        name = model.get("name") or ""
        out[name] = _pose(model, name)
    return out


def _model_shapes(model: ET.Element, pose: Pose2, name: str, depth: int = 1) -> List[Any]:
    if depth > MAX_MODEL_DEPTH:
        raise WorldFormatError(f"model '{name.split('::')[0]}': models nested more than {MAX_MODEL_DEPTH} deep")
    shapes = []
    for link in model.findall("link"):
        link_pose = _compose(pose, _pose(link, name))
        for collision in link.findall("collision"):
            geometry = collision.find("geometry")
            if geometry is None:
                raise WorldFormatError(f"model '{name}': a collision without geometry")
            shape = _shape(geometry, _compose(link_pose, _pose(collision, name)), name)
            if shape is not None:
                shapes.append(shape)
    for nested in model.findall("model"):
        nested_name = f"{name}::{nested.get('name') or ''}"
        shapes.extend(_model_shapes(nested, _compose(pose, _pose(nested, nested_name)), nested_name, depth + 1))
    return shapes


def parse_sdf(text: bytes, where: str = "<sdf>", start: Optional[Sequence[float]] = None,
              goal: Optional[Sequence[float]] = None) -> World:
    """A :class:`World` from SDF text (see the module's notes); ``where`` names it in errors."""
    if b"<!DOCTYPE" in text or b"<!ENTITY" in text:
        # entity expansion is how an XML file of kilobytes becomes gigabytes; SDF has no use for it
        raise WorldFormatError(f"{where}: an SDF world must not declare a DOCTYPE or entities")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise WorldFormatError(f"{where}: not well-formed XML ({exc})") from None
    except LookupError as exc:  # <?xml encoding='bogus'?>: Python has no such codec
        raise WorldFormatError(f"{where}: not readable XML ({exc})") from None
    if root.tag != "sdf":
        raise WorldFormatError(f"{where}: not an SDF file (the root element is <{root.tag}>, expected <sdf>)")
    world = root.find("world")
    if world is None:
        raise WorldFormatError(f"{where}: no <world> element")
    if world.find("include") is not None:
        uri = world.find("include/uri")
        raise WorldFormatError(f"{where}: <include> of {None if uri is None else uri.text!r} cannot be read "
                               "(navlab does not resolve Gazebo's model database); inline the model")
    obstacles: List[Any] = []
    names: List[str] = []
    name = ""
    try:
        state = _state_poses(world)
        for model in world.findall("model"):
            name = model.get("name") or f"model {len(names)}"
            pose = state.get(name) or _pose(model, name)
            for shape in _model_shapes(model, pose, name):
                obstacles.append(shape)
                names.append(name)
                if len(obstacles) > MAX_SDF_OBSTACLES:
                    raise WorldFormatError(f"more than {MAX_SDF_OBSTACLES} obstacles")
    except WorldFormatError as exc:
        raise WorldFormatError(f"{where}: {exc}") from None
    except ValueError as exc:  # a shape's own check (a degenerate box)
        raise WorldFormatError(f"{where}: model '{name}': {exc}") from None
    start = tuple(float(v) for v in (start if start is not None else DEFAULT_START))[:2]
    goal = tuple(float(v) for v in (goal if goal is not None else DEFAULT_GOAL))[:2]
    points = [start, goal] + [p for o in obstacles for p in (o.bbox()[:2], o.bbox()[2:])]
    xy = np.array(points, float)
    lo, hi = xy.min(axis=0) - BOUNDS_MARGIN, xy.max(axis=0) + BOUNDS_MARGIN
    stem = os.path.splitext(os.path.basename(where))[0]
    try:
        return World(name=stem, bounds=Bounds(float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])), start=start,
                     goal=goal, obstacles=tuple(obstacles), meta={"obstacle_names": names, "source": where})
    except ValueError as exc:  # the World's own checks (a model past navlab's range, a 1e-300 m cylinder)
        raise WorldFormatError(f"{where}: {exc}") from None


def read_sdf(path, start=None, goal=None) -> World:
    """Read a Gazebo SDF ``.world`` file (bounded: a regular file of at most 64 MiB)."""
    from ..yamlio import read_bounded

    where = os.fspath(path)
    raw = read_bounded(path, where, WorldFormatError, MAX_SDF_BYTES, what="SDF world")
    return parse_sdf(raw, where, start, goal)


SDF_SUFFIXES = (".world", ".sdf")
