import math

import pytest
import yaml

import navlab
from navlab.registry import UnknownNameError
from navlab.world import SCENES, WorldFormatError, save_world, world_from_dict

ZIGZAG = """
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


def write(tmp_path, text, name="w.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_issue_example_loads_and_round_trips(tmp_path):
    w = navlab.load_world(write(tmp_path, ZIGZAG))
    assert w.name == "zigzag" and w.start == (1.0, 1.0) and len(w.obstacles) == 3
    save_world(w, tmp_path / "again.yaml")
    assert navlab.load_world(tmp_path / "again.yaml") == w


@pytest.mark.parametrize("name", SCENES.names())
def test_scenes_are_valid_problems(name):
    w = navlab.load_world(name)
    assert all(w.checker().points_free([w.start, w.goal]))


def test_pythonrobotics_scene_is_the_classic_demo():
    w = navlab.load_world("pythonrobotics")
    assert (w.start, w.goal, w.robot_radius) == ((0.0, 0.0), (6.0, 10.0), 0.8)
    assert (w.bounds.xmin, w.bounds.xmax) == (-2.0, 15.0)
    assert sorted((o.center + (o.radius,)) for o in w.obstacles) == sorted(
        [(5, 5, 1), (3, 6, 2), (3, 8, 2), (3, 10, 2), (7, 5, 2), (9, 5, 2), (8, 10, 1), (6, 12, 1)])


@pytest.mark.parametrize("edit, field", [
    (lambda d: d.pop("start"), "start"),
    (lambda d: d.update(robot_radius=-1), "robot_radius"),
    (lambda d: d.update(bounds={"x": [0, 10]}), "bounds"),
    (lambda d: d.update(bounds={"x": [5, 1], "y": [0, 1]}), "bounds.x"),
    (lambda d: d["obstacles"].append({"type": "circel", "center": [1, 1], "radius": 1}), "obstacles[3].type"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": [1, 1]}), "obstacles[3].radius"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": [1, 1], "radius": 0}), "obstacles[3].radius"),
    (lambda d: d["obstacles"].append({"type": "polygon", "points": [[0, 0], [1, 1], [1, 0], [0, 1]]}),
     "obstacles[3].points"),
    (lambda d: d.update(gaol=[1, 2]), "gaol"),
])
def test_malformed_world_names_file_and_field(tmp_path, edit, field):
    data = yaml.safe_load(ZIGZAG)
    edit(data)
    path = write(tmp_path, yaml.safe_dump(data))
    with pytest.raises(WorldFormatError) as err:
        navlab.load_world(path)
    assert str(path) in str(err.value) and f"'{field}'" in str(err.value)


# Each value below crashed with a bare TypeError/OverflowError, or blamed "field 'world'", before.
HUGE = 10 ** 400


@pytest.mark.parametrize("edit, field", [
    (lambda d: d.update(bounds={"x": [0, HUGE], "y": [0, 10]}), "bounds.x[1]"),
    (lambda d: d.update(bounds={"x": [0, 1e300], "y": [0, 10]}), "bounds.x[1]"),
    (lambda d: d.update(bounds={"x": [0, float("nan")], "y": [0, 10]}), "bounds.x[1]"),
    (lambda d: d.update(start=[HUGE, 1]), "start[0]"),
    (lambda d: d.update(start={"a": 1}), "start"),
    (lambda d: d.update(start="abc"), "start"),
    (lambda d: d.update(start=[1, [2]]), "start[1]"),
    (lambda d: d.update(start=[1, True]), "start[1]"),
    (lambda d: d.update(goal=[1, 2, 3, 4]), "goal"),
    (lambda d: d.update(goal=[1, 2, "north"]), "goal[2]"),
    (lambda d: d.update(goal=[float("inf"), 2]), "goal[0]"),
    (lambda d: d.update(robot_radius=HUGE), "robot_radius"),
    (lambda d: d.update(robot_radius=1e-300), "robot_radius"),
    (lambda d: d.update(robot_radius={"a": 1}), "robot_radius"),
    (lambda d: d.update(goal_tolerance=float("nan")), "goal_tolerance"),
    (lambda d: d.update(obstacles={"type": "circle"}), "obstacles"),
    (lambda d: d.update(name={"a": 1}), "name"),
    (lambda d: d.update({3: 4}), "3"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": [1, 1], "radius": HUGE}), "obstacles[3].radius"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": [1, 1], "radius": "big"}), "obstacles[3].radius"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": 5, "radius": 1}), "obstacles[3].center"),
    (lambda d: d["obstacles"].append({"type": ["circle"], "center": [1, 1], "radius": 1}), "obstacles[3].type"),
    (lambda d: d["obstacles"].append({"type": "rectangle", "min": [2, 2], "max": [1, 3]}), "obstacles[3].max"),
    (lambda d: d["obstacles"].append({"type": "polygon", "points": [[0, 0], [1, 1]]}), "obstacles[3].points"),
    (lambda d: d["obstacles"].append({"type": "polygon", "points": [[0, 0], [1, 1], [2, 2]]}), "obstacles[3].points"),
    (lambda d: d["obstacles"].append({"type": "polygon", "points": [[0, 0], [1, 0], [HUGE, 1]]}),
     "obstacles[3].points[2][0]"),
    (lambda d: d["obstacles"].append({"type": "polygon", "points": "abc"}), "obstacles[3].points"),
    (lambda d: d["obstacles"].append(7), "obstacles[3]"),
])
def test_bad_value_names_its_field(tmp_path, edit, field):
    data = yaml.safe_load(ZIGZAG)
    edit(data)
    with pytest.raises(WorldFormatError) as err:
        world_from_dict(data, "w.yaml")
    message = str(err.value)
    assert message.startswith("w.yaml: ") and f"field '{field}'" in message, message
    assert "\n" not in message and len(message) < 400


def test_huge_integer_in_the_file_names_the_field(tmp_path):
    path = write(tmp_path, ZIGZAG.replace("robot_radius: 0.0", "robot_radius: " + "9" * 400))
    with pytest.raises(WorldFormatError, match=r"field 'robot_radius' must be a finite number, got an integer of 400 "
                                               r"digits"):
        navlab.load_world(path)


@pytest.mark.parametrize("replace, words", [
    (("robot_radius: 0.0", "robot_radius: -1"), "field 'robot_radius' must be "),
    (("start: [", "start: [100000000, "), r"field 'start\[0\]' = 100000000 is out of range")])
def test_a_field_is_named_once_and_the_check_reads_on_from_it(tmp_path, replace, words):
    """("field 'start[0]': start[0] = ..." until session 18, then for a while "field 'start[0]': = ...")"""
    with pytest.raises(WorldFormatError, match=words) as err:
        navlab.load_world(write(tmp_path, ZIGZAG.replace(*replace, 1)))
    field = words.split("'")[1].replace("\\", "")
    assert str(err.value).count(field) <= 2 and f"{field}': " not in str(err.value)


def test_exponent_without_dot_is_a_number(tmp_path):
    # PyYAML (YAML 1.1) reads `1e-1` as text; YAML 1.2 and the tools writing these files read a number
    w = navlab.load_world(write(tmp_path, ZIGZAG.replace("robot_radius: 0.0", "robot_radius: 1e-1")))
    assert w.robot_radius == 0.1
    with pytest.raises(WorldFormatError, match="field 'robot_radius'"):
        navlab.load_world(write(tmp_path, ZIGZAG.replace("robot_radius: 0.0", "robot_radius: 1e999")))


@pytest.mark.parametrize("content, expected", [
    (b"", "empty"),
    (b"# only a comment\n", "empty"),
    (b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe", "not a UTF-8 text file"),
    ("bounds: {x: [0, 1], y: [0, 1]}\nstart: [0, 0]\ngoal: [1, 1]\nname: caf\u00e9\n".encode("latin-1"),
     "not a UTF-8 text file"),
    (b"a: [1, 2", "not valid YAML"),
    (b"key: value\n  bad indent: 1\n", "not valid YAML"),
    (b"- 1\n- 2\n", "expected a mapping of world fields, got list"),
    (b"just text", "expected a mapping of world fields, got str"),
    (b"[" * 5000 + b"]" * 5000, "nested too deeply|expected a mapping of world fields, got list"),
    # libyaml crashed the process (a segmentation fault) on these:
    (b"start: " + b"[" * 100000 + b"]" * 100000, "nested too deeply"),
    (b"- " * 100000, "nested too deeply"),
    (b"? " * 100000, "nested too deeply"),
    (b"a: {" * 100000, "nested too deeply|not valid YAML"),
])
def test_unreadable_files_give_one_error(tmp_path, content, expected):
    path = tmp_path / "w.yaml"
    path.write_bytes(content)
    with pytest.raises(WorldFormatError, match=expected) as err:
        navlab.load_world(path)
    assert str(path) in str(err.value)


def test_directory_and_oversized_file(tmp_path, monkeypatch):
    folder = tmp_path / "d.yaml"
    folder.mkdir()
    with pytest.raises(WorldFormatError, match="cannot read"):
        navlab.load_world(folder)
    monkeypatch.setattr("navlab.world.io.MAX_FILE_BYTES", 100)
    with pytest.raises(WorldFormatError, match="larger than"):
        navlab.load_world(write(tmp_path, ZIGZAG))


def test_coordinates_at_the_limit_are_accepted():
    from navlab.limits import MAX_COORDINATE

    data = yaml.safe_load(ZIGZAG)
    data["bounds"] = {"x": [-MAX_COORDINATE, MAX_COORDINATE], "y": [-MAX_COORDINATE, MAX_COORDINATE]}
    assert world_from_dict(data).bounds.xmax == MAX_COORDINATE
    data["bounds"]["x"][1] = MAX_COORDINATE * 1.0000001
    with pytest.raises(WorldFormatError, match="bounds.x"):
        world_from_dict(data)


def test_unknown_field_suggests(tmp_path):
    data = yaml.safe_load(ZIGZAG)
    data["gaol"] = data.pop("goal")
    with pytest.raises(WorldFormatError, match="Did you mean 'goal'"):
        navlab.load_world(write(tmp_path, yaml.safe_dump(data)))


@pytest.mark.parametrize("key, shown", [("null", "null"), ("~", "null"), ("true", "true"), ("1", "1")])
def test_a_key_that_is_no_name_is_shown_as_written_without_a_guess(tmp_path, key, shown):
    """(attack, session 21: null: 1 was "field 'None': unknown field ... Did you mean 'name'?")"""
    with pytest.raises(WorldFormatError) as caught:
        navlab.load_world(write(tmp_path, ZIGZAG + f"\n{key}: 1\n"))
    message = str(caught.value)
    assert f"field '{shown}': unknown field; valid: " in message and "Did you mean" not in message


def test_not_yaml_and_missing_file(tmp_path):
    with pytest.raises(WorldFormatError, match="not valid YAML"):
        navlab.load_world(write(tmp_path, "a: [1, 2"))
    with pytest.raises(WorldFormatError, match="no such file"):
        navlab.load_world(tmp_path / "missing.yaml")


def test_unknown_scene_lists_names_with_hint():
    with pytest.raises(UnknownNameError, match="Did you mean 'clutter'") as err:
        navlab.load_world("cluttr")
    assert "squarefield" in str(err.value)


def test_scene_paths_have_seed_lengths():
    # Canonical seed 000 scenes are sized so paths run 10-25 m.
    for name in ("clutter", "squarefield", "trap"):
        w = navlab.load_world(name)
        straight = math.dist(w.start, w.goal)
        assert 10 <= straight <= 25
