"""Fuzzing world documents and world files: a World, or one WorldFormatError naming the field.

Planning in every world that loads returns a Result that shapely agrees with.
"""

import copy
import math

import numpy as np
import pytest
import yaml
from hypothesis import assume, example, given
from hypothesis import strategies as st

import navlab
from navlab.limits import MAX_COORDINATE, MIN_LENGTH
from navlab.world import World, WorldFormatError, world_from_dict
from navlab.world.io import read_world_file

from fuzz.checks import check_world_result
from fuzz.strategies import (examples, field_in, leaf_paths, obstacle_docs, same_field, set_path, wild_values,
                             world_documents)

SOURCE = "fuzzed.yaml"


def load(doc):
    """The World, or the WorldFormatError (checked to be one line naming the file)."""
    try:
        return world_from_dict(doc, SOURCE)
    except WorldFormatError as exc:
        message = str(exc)
        assert message.startswith(f"{SOURCE}: ") and "\n" not in message and len(message) < 600, message
        return exc


def check_world_in_range(w: World) -> None:
    values = [w.bounds.xmin, w.bounds.xmax, w.bounds.ymin, w.bounds.ymax, *w.start, *w.goal,
              w.robot_radius, w.goal_tolerance]
    for o in w.obstacles:
        values += [v for point in getattr(o, "points", ()) for v in point]
        values += list(getattr(o, "center", ())) + list(getattr(o, "min", ())) + list(getattr(o, "max", ()))
        if hasattr(o, "radius"):
            assert o.radius >= MIN_LENGTH
    assert all(isinstance(v, float) and math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in values), values
    for length in (w.robot_radius, w.goal_tolerance):
        assert length == 0 or length >= MIN_LENGTH


def valid_obstacles(doc):
    """The document with only the obstacles that load on their own."""
    keep = []
    for o in doc["obstacles"]:
        if isinstance(load({**doc, "obstacles": [o]}), World):
            keep.append(o)
    return {**doc, "obstacles": keep}


@examples(80)
@given(world_documents())
def test_generated_documents_load_or_name_a_field(doc):
    out = load(doc)
    if isinstance(out, World):
        check_world_in_range(out)
    else:
        field = field_in(str(out))
        assert field, str(out)
        assert field.split(".")[0].split("[")[0] in doc, str(out)


@examples(120)
@given(world_documents(), st.data())
@example(doc={"bounds": {"x": [0, 10], "y": [0, 10]}, "start": [1, 1], "goal": [9, 9], "obstacles": []},
         data=None).via("issue 13: start: abc blamed field 'world'")
def test_one_bad_value_is_blamed_on_its_field(doc, data):
    doc = valid_obstacles(doc)
    assume(isinstance(load(doc), World))
    if data is None:  # the explicit example
        name, keys, value = "start", ("start",), "abc"
    else:
        name, keys = data.draw(st.sampled_from(leaf_paths(doc)), label="field")
        value = data.draw(wild_values(), label="value")
    bad = copy.deepcopy(doc)
    set_path(bad, keys, value)
    out = load(bad)
    if isinstance(out, World):
        check_world_in_range(out)
    else:
        assert same_field(field_in(str(out)), name), (name, str(out))


@examples(40)
@given(st.one_of(
    st.binary(max_size=200),
    st.text(max_size=200).map(lambda t: t.encode("utf-8", "surrogatepass")),
    world_documents().map(lambda d: yaml.safe_dump(d).encode()),
    st.sampled_from([b"", b"\x00", b"\xff\xfe", b"---\n...\n", b"[" * 3000, b"&a [*a]", b"!!python/object:os.system 1",
                     b"a: &x [1]\nb: *x\n", b"bounds: !!binary aGVsbG8=\n", b"2020-01-01", b"- - - -"])))
def test_any_bytes_give_a_world_or_one_error(tmp_path_factory, content):
    path = tmp_path_factory.mktemp("w") / "world.yaml"
    path.write_bytes(content)
    try:
        w = read_world_file(path)
    except WorldFormatError as exc:
        assert str(exc).startswith(f"{path}: ") and "\n" not in str(exc)
    else:
        check_world_in_range(w)


@examples(25)
@given(world_documents(), st.sampled_from(["rrt", "rrt_star", "informed_rrt_star"]), st.integers(0, 2**32 - 1))
def test_planning_in_any_loaded_world_gives_a_checked_result(doc, planner, seed):
    w = load(valid_obstacles(doc))
    assume(isinstance(w, World))
    result = navlab.plan(w, planner=planner, seed=seed, max_iter=120)
    check_world_result(w, result)


@examples(15)
@given(st.lists(obstacle_docs(10.0), min_size=1, max_size=4), st.floats(0, 0.5), st.integers(0, 1000))
def test_touching_and_tight_worlds(obstacles, radius, seed):
    """Start and goal on obstacle surfaces and corners: collision or a checked path, never a path through."""
    doc = valid_obstacles({"bounds": {"x": [0, 10], "y": [0, 10]}, "start": [0.5, 0.5], "goal": [9.5, 9.5],
                           "robot_radius": radius, "obstacles": obstacles})
    w = load(doc)
    assume(isinstance(w, World) and w.obstacles)
    o = w.obstacles[0]
    corner = (getattr(o, "min", None) or (getattr(o, "points", None) or [None])[0]
              or (o.center[0] + o.radius, o.center[1]))
    for query in ({"start": corner}, {"goal": corner}):
        moved = w.with_query(**query)
        if moved.bounds.contains(np.array(moved.start))[0] and moved.bounds.contains(np.array(moved.goal))[0]:
            check_world_result(moved, navlab.plan(moved, planner="rrt_star", seed=seed, max_iter=80))


@pytest.mark.parametrize("value", [10 ** 400, -(10 ** 30), 1e300, math.inf, math.nan, 5e-324, "abc", {"a": 1}])
def test_each_numeric_field_rejects_out_of_range(value):
    base = {"bounds": {"x": [0, 10], "y": [0, 10]}, "start": [1, 1], "goal": [9, 9],
            "obstacles": [{"type": "circle", "center": [5, 5], "radius": 1}]}
    for name, keys in leaf_paths(base):
        if keys[-1] == "type" or (value == 5e-324 and keys[-1] != "radius"):
            continue  # a tiny coordinate is fine; only a length has a smallest value
        bad = copy.deepcopy(base)
        set_path(bad, keys, value)
        out = load(bad)
        if isinstance(out, World):
            pytest.fail(f"{name} = {value!r} was accepted")
        assert same_field(field_in(str(out)), name), (name, str(out))


@st.composite
def surface_points(draw, kind):
    """An obstacle with integer coordinates and a point exactly on its surface (exact in float64)."""
    c = st.integers(2, 8)
    if kind == "circle":
        cx, cy, r = draw(c), draw(c), draw(st.integers(1, 2))
        dx, dy = draw(st.sampled_from([(r, 0), (-r, 0), (0, r), (0, -r)]))
        return {"type": "circle", "center": [cx, cy], "radius": r}, [cx + dx, cy + dy]
    if kind == "rectangle":
        x0, y0, wdt, hgt = draw(c), draw(c), draw(st.integers(1, 2)), draw(st.integers(1, 2))
        point = [draw(st.integers(x0, x0 + wdt)), draw(st.sampled_from([y0, y0 + hgt]))]
        return {"type": "rectangle", "min": [x0, y0], "max": [x0 + wdt, y0 + hgt]}, point
    x0, y0 = draw(c), draw(c)
    points = [[x0, y0], [x0 + 2, y0], [x0 + 1, y0 + 2]]
    return {"type": "polygon", "points": points}, draw(st.sampled_from(points + [[x0 + 1, y0]]))


@pytest.mark.parametrize("kind", ["circle", "rectangle", "polygon"])
@examples(10)
@given(data=st.data())
def test_touching_an_obstacle_is_a_collision_for_every_shape(kind, data):
    obstacle, point = data.draw(surface_points(kind))
    w = world_from_dict({"bounds": {"x": [0, 12], "y": [0, 12]}, "start": point, "goal": [11.5, 11.5],
                         "obstacles": [obstacle]})
    assert navlab.plan(w, planner="rrt", seed=0, max_iter=20).status is navlab.Status.INVALID_START
