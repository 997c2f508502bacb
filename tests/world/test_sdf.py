"""Gazebo SDF worlds: a hand-written world, a BARN world counted independently, and bad files."""

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from navlab.world import Circle, Polygon, Rectangle, WorldFormatError, load_world
from navlab.world.sdf import parse_sdf

BARN = Path(__file__).resolve().parents[3] / "shared" / "data" / "barn"


def _model(name, geometry, pose="0 0 0 0 0 0", static=True, extra=""):
    return (f"<model name='{name}'><static>{int(static)}</static><pose>{pose}</pose><link name='link'>"
            f"<collision name='c'><geometry>{geometry}</geometry></collision>"
            f"<visual name='v'><geometry><mesh><uri>x.dae</uri></mesh></geometry></visual>{extra}</link></model>")


HAND = ("<sdf version='1.6'><world name='default'><light name='sun' type='directional'/>"
        "<plugin name='p' filename='libfoo.so'/>"
        + _model("ground_plane", "<plane><normal>0 0 1</normal><size>100 100</size></plane>")
        + _model("post", "<cylinder><radius>0.2</radius><length>1</length></cylinder>", "9 9 0 0 0 0")
        + _model("crate", "<box><size>1 0.5 1</size></box>", "3 4 0.5 0 0 1.5707963267948966")
        + _model("slab", "<box><size>2 0.2 1</size></box>", "-3 1 0 0 0 0.5")
        + "<state world_name='default'><model name='post'><pose>1 2 0 0 0 0</pose></model></state>"
        "</world></sdf>")


def test_hand_written_world():
    world = parse_sdf(HAND.encode(), "hand.world")
    assert world.meta["obstacle_names"] == ["post", "crate", "slab"]
    post, crate, slab = world.obstacles
    # the <state> pose wins over the model's own
    assert isinstance(post, Circle) and post.center == (1.0, 2.0) and post.radius == 0.2
    # a quarter turn swaps the box's sides
    assert isinstance(crate, Rectangle)
    np.testing.assert_allclose((*crate.min, *crate.max), (2.75, 3.5, 3.25, 4.5), atol=1e-12)
    assert isinstance(slab, Polygon)
    c, s = math.cos(0.5), math.sin(0.5)
    expected = [(-3 + c * x - s * y, 1 + s * x + c * y) for x, y in ((-1, -0.1), (1, -0.1), (1, 0.1), (-1, 0.1))]
    np.testing.assert_allclose(slab.points, expected, atol=1e-12)
    # no start or goal in SDF: BARN's, inside bounds grown around everything
    assert world.start == (-2.0, 3.0) and world.goal == (-2.0, 13.0)
    corners = np.array(expected + [(2.75, 3.5), (3.25, 4.5), (0.8, 1.8), (1.2, 2.2), (-2, 3), (-2, 13)])
    lo, hi = corners.min(axis=0) - 1.0, corners.max(axis=0) + 1.0
    np.testing.assert_allclose((world.bounds.xmin, world.bounds.xmax, world.bounds.ymin, world.bounds.ymax),
                               (lo[0], hi[0], lo[1], hi[1]), atol=1e-12)


def test_link_and_collision_poses_compose():
    text = ("<sdf version='1.6'><world name='w'><model name='m'><pose>1 0 0 0 0 1.5707963267948966</pose>"
            "<link name='l'><pose>1 0 0 0 0 0</pose><collision name='c'><pose>0 0.5 0 0 0 0</pose>"
            "<geometry><cylinder><radius>0.1</radius><length>1</length></cylinder></geometry></collision>"
            "</link></model></world></sdf>")
    (post,) = parse_sdf(text.encode()).obstacles
    # model at (1, 0) turned 90°: the link 1 m ahead is at (1, 1), the collision 0.5 m to its left at (0.5, 1)
    np.testing.assert_allclose(post.center, (0.5, 1.0), atol=1e-12)


@pytest.mark.skipif(not BARN.is_dir(), reason="../shared/data/barn is not beside the checkout")
@pytest.mark.parametrize("number", [0, 108])
def test_a_barn_world_loads_unchanged(number):
    path = BARN / f"world_{number}.world"
    world = load_world(str(path))
    # independent count: models with a cylinder collision, placed at their <state> pose
    root = ET.parse(path).getroot().find("world")
    state = {m.get("name"): m.find("pose").text.split() for m in root.find("state").findall("model")}
    cylinders = [m for m in root.findall("model") if m.find("link/collision/geometry/cylinder") is not None]
    assert len(world.obstacles) == len(cylinders) > 100
    for model, obstacle in zip(cylinders, world.obstacles):
        x, y = (float(v) for v in state[model.get("name")][:2])
        assert obstacle.center == (x, y) and obstacle.radius == 0.075


@pytest.mark.parametrize("geometry, words", [
    ("<mesh><uri>model://rock/mesh.dae</uri></mesh>", "model 'thing': mesh collision geometry cannot be read"),
    ("<sphere><radius>1</radius></sphere>", "model 'thing': sphere"),
    ("<cylinder><radius>-1</radius></cylinder>", "model 'thing': cylinder radius must be 1 positive"),
    ("<box><size>1 1</size></box>", "model 'thing': box size must be 3 positive"),
])
def test_unreadable_geometry_names_the_model(geometry, words):
    text = f"<sdf version='1.6'><world name='w'>{_model('thing', geometry)}</world></sdf>"
    with pytest.raises(WorldFormatError, match=words):
        parse_sdf(text.encode(), "bad.world")


@pytest.mark.parametrize("pose, words", [
    ("1 2 3", "model 'thing': malformed pose '1 2 3'"),
    ("1 2 0 0 0 nan", "malformed pose"),
    ("a b c d e f", "malformed pose"),
    ("0 0 0 0.5 0 0", "tilted"),
])
def test_malformed_pose_names_the_model(pose, words):
    text = f"<sdf version='1.6'><world name='w'>{_model('thing', '<cylinder><radius>1</radius></cylinder>', pose)}" \
           "</world></sdf>"
    with pytest.raises(WorldFormatError, match=words):
        parse_sdf(text.encode(), "bad.world")


@pytest.mark.parametrize("text, words", [
    (b"<sdf><world name='w'>", "not well-formed XML"),
    (b"<!DOCTYPE x [<!ENTITY a 'aaaa'>]><sdf/>", "DOCTYPE"),
    (b"<world/>", "not an SDF file"),
    (b"<sdf version='1.6'/>", "no <world>"),
    (b"<sdf><world name='w'><include><uri>model://jackal</uri></include></world></sdf>", "include"),
    # an internal LookupError and RecursionError until session 17 (an attack on the command)
    (b"<?xml version='1.0' encoding='bogus-enc'?><sdf><world/></sdf>", "not readable XML \\(unknown encoding"),
    (b"<sdf><world name='w'>" + b"<model name='n'>" * 2000 + b"</model>" * 2000 + b"</world></sdf>",
     "model 'n': models nested more than 100 deep"),
    # the World's own checks and the <state> poses named no file (an attack on the command, session 17)
    (b"<sdf><world name='w'><model name='a'><pose>1e300 0 0 0 0 0</pose><link name='l'><collision name='c'>"
     b"<geometry><cylinder><radius>0.1</radius><length>1</length></cylinder></geometry></collision></link>"
     b"</model></world></sdf>", "^bad.world: bounds.xmax = 1e\\+300 is out of range"),
    (b"<sdf><world name='w'><state><model name='a'><pose>bad</pose></model></state></world></sdf>",
     "^bad.world: model 'a': malformed pose 'bad'"),
])
def test_bad_files(text, words):
    with pytest.raises(WorldFormatError, match=words):
        parse_sdf(text, "bad.world")


def test_missing_and_fifo_files(tmp_path):
    import os

    with pytest.raises(WorldFormatError, match="no such file"):
        load_world(str(tmp_path / "nothing.world"))
    fifo = tmp_path / "pipe.world"
    os.mkfifo(fifo)
    with pytest.raises(WorldFormatError, match="not a regular file"):
        load_world(str(fifo))
