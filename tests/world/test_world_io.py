import math

import pytest
import yaml

import navlab
from navlab.registry import UnknownNameError
from navlab.world import SCENES, WorldFormatError, save_world

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
    (lambda d: d.update(bounds={"x": [5, 1], "y": [0, 1]}), "bounds"),
    (lambda d: d["obstacles"].append({"type": "circel", "center": [1, 1], "radius": 1}), "obstacles[3].type"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": [1, 1]}), "obstacles[3].radius"),
    (lambda d: d["obstacles"].append({"type": "circle", "center": [1, 1], "radius": 0}), "obstacles[3]"),
    (lambda d: d["obstacles"].append({"type": "polygon", "points": [[0, 0], [1, 1], [1, 0], [0, 1]]}), "obstacles[3]"),
    (lambda d: d.update(gaol=[1, 2]), "gaol"),
])
def test_malformed_world_names_file_and_field(tmp_path, edit, field):
    data = yaml.safe_load(ZIGZAG)
    edit(data)
    path = write(tmp_path, yaml.safe_dump(data))
    with pytest.raises(WorldFormatError) as err:
        navlab.load_world(path)
    assert str(path) in str(err.value) and f"'{field}'" in str(err.value)


def test_unknown_field_suggests(tmp_path):
    data = yaml.safe_load(ZIGZAG)
    data["gaol"] = data.pop("goal")
    with pytest.raises(WorldFormatError, match="Did you mean 'goal'"):
        navlab.load_world(write(tmp_path, yaml.safe_dump(data)))


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
