"""Occupancy grids, map files and mazes."""

import math

import numpy as np
import pytest
import yaml
from PIL import Image

from navlab.grid import MapFormatError, OccupancyGrid, load_map, make_maze, plan, save_map
from navlab.grid.maze import maze_cell_center, maze_walls


def write_map(tmp_path, pixels, **meta):
    img = tmp_path / meta.pop("image_name", "m.pgm")
    if img.suffix == ".pgm":
        h, w = pixels.shape
        img.write_bytes(f"P5\n{w} {h}\n255\n".encode() + pixels.astype(np.uint8).tobytes())
    else:
        Image.fromarray(pixels.astype(np.uint8)).save(img)
    data = {"image": img.name, "resolution": 0.1, "origin": [1.0, 2.0, 0.0], "negate": 0,
            "occupied_thresh": 0.65, "free_thresh": 0.196, **meta}
    y = tmp_path / "m.yaml"
    y.write_text(yaml.safe_dump(data))
    return y


PIXELS = np.array([[0, 254, 254], [254, 205, 254]])  # top row first, as in the image


def test_ros_map_row_order_and_trinary(tmp_path):
    grid = load_map(write_map(tmp_path, PIXELS))
    # Row y = 0 is the image's bottom row.
    assert grid.blocked.tolist() == [[False, False, False], [True, False, False]]
    assert grid.unknown.tolist() == [[False, True, False], [False, False, False]]
    assert grid.resolution == 0.1 and grid.origin == (1.0, 2.0, 0.0)
    np.testing.assert_allclose(grid.cell_to_world([[0, 1]]), [[1.05, 2.15]])


def test_negate_png_and_scale_modes(tmp_path):
    g = load_map(write_map(tmp_path, 255 - PIXELS, negate=1, image_name="m.png"))
    assert g.blocked.tolist() == [[False, False, False], [True, False, False]]
    g2 = load_map(write_map(tmp_path, np.array([[100, 0]]), mode="raw", image_name="r.png"))
    assert g2.blocked.tolist() == [[True, False]]


def test_plain_pgm_p2(tmp_path):
    (tmp_path / "p.pgm").write_text("P2\n# comment\n2 2\n255\n0 254\n254 254\n")
    (tmp_path / "p.yaml").write_text("image: p.pgm\nresolution: 1\norigin: [0, 0, 0]\n")
    assert load_map(tmp_path / "p.yaml").blocked.tolist() == [[False, False], [True, False]]


def test_save_map_round_trip(tmp_path):
    rng = np.random.default_rng(0)
    blocked = rng.random((40, 55)) < 0.3
    unknown = (rng.random((40, 55)) < 0.1) & ~blocked
    grid = OccupancyGrid(blocked, 0.05, (-3.0, 4.5, 0.0), unknown)
    save_map(grid, tmp_path / "out.yaml")
    back = load_map(tmp_path / "out.yaml")
    np.testing.assert_array_equal(back.blocked, blocked)
    np.testing.assert_array_equal(back.unknown, unknown)
    assert back.resolution == 0.05 and back.origin == (-3.0, 4.5, 0.0)


@pytest.mark.parametrize("meta, text", [
    ({"occupied_thresh": 0.1, "free_thresh": 0.5}, "thresholds"),
    ({"resolution": -1}, "resolution"),
    ({"resolution": "fine"}, "resolution"),
    ({"mode": "ternary"}, "mode"),
    ({"origin": [0, 0]}, "origin"),
    ({"image": "missing.pgm"}, "not found"),
])
def test_malformed_ros_maps(tmp_path, meta, text):
    path = write_map(tmp_path, PIXELS, **meta)
    with pytest.raises(MapFormatError, match=text) as err:
        load_map(path)
    assert str(tmp_path) in str(err.value)


def test_truncated_and_wrong_pgm(tmp_path):
    (tmp_path / "t.pgm").write_bytes(b"P5\n10 10\n255\n" + bytes(20))
    (tmp_path / "t.yaml").write_text("image: t.pgm\nresolution: 1\n")
    with pytest.raises(MapFormatError, match="truncated PGM data"):
        load_map(tmp_path / "t.yaml")
    (tmp_path / "t.pgm").write_bytes(b"P6\n1 1\n255\n000")
    with pytest.raises(MapFormatError, match="not a PGM"):
        load_map(tmp_path / "t.yaml")


@pytest.mark.parametrize("text, message", [
    ("type tile\nheight 1\nwidth 2\nmap\n..\n", "octile"),
    ("type octile\nheight 3\nwidth 2\nmap\n..\n..\n", "truncated"),
    ("type octile\nheight 2\nwidth 3\nmap\n...\n..\n", "row 1"),
    ("type octile\nheight 1\nwidth 2\nmap\n.X\n", "unknown terrain"),
    ("type octile\nheight 1\nwidth 2\n", "no 'map' line"),
])
def test_malformed_movingai(tmp_path, text, message):
    (tmp_path / "bad.map").write_text(text)
    with pytest.raises(MapFormatError, match=message):
        load_map(tmp_path / "bad.map")


def test_unknown_format_and_missing(tmp_path):
    with pytest.raises(MapFormatError, match="no such file"):
        load_map(tmp_path / "nope.yaml")
    (tmp_path / "x.txt").write_text("hi")
    with pytest.raises(MapFormatError, match="unknown map format"):
        load_map(tmp_path / "x.txt")


def test_world_cell_conversions_with_yaw():
    grid = OccupancyGrid(np.zeros((10, 10), dtype=bool), 0.2, (1.0, -1.0, math.pi / 2))
    cells = np.array([[0, 0], [3, 7], [9, 9]])
    np.testing.assert_array_equal(grid.world_to_cell(grid.cell_to_world(cells)), cells)
    np.testing.assert_allclose(grid.cell_to_world([[0, 0]]), [[1.0 - 0.1, -1.0 + 0.1]])


def test_inflation_matches_brute_force():
    rng = np.random.default_rng(1)
    blocked = rng.random((25, 30)) < 0.05
    grid = OccupancyGrid(blocked, 0.1)
    inflated = grid.inflate(0.25)
    occ = np.argwhere(blocked)
    for y in range(25):
        for x in range(30):
            near = np.min(np.hypot(occ[:, 0] - y, occ[:, 1] - x)) * 0.1 <= 0.25 + 1e-12
            assert inflated.blocked[y, x] == near
    with pytest.raises(ValueError, match="radius"):
        grid.inflate(-1)


@pytest.mark.parametrize("w, h, seed", [(10, 10, 0), (15, 15, 1), (7, 3, 2)])
def test_maze_is_perfect_and_connected(w, h, seed):
    east, north = maze_walls(w, h, np.random.default_rng(seed))
    passages = (~east[:, :-1]).sum() + (~north[:-1, :]).sum()
    assert passages == w * h - 1  # a spanning tree: one path between any two cells
    assert east[:, -1].all() and north[-1, :].all()  # outer walls stand
    grid = make_maze(w, h, seed=seed)
    start = grid.world_to_cell(maze_cell_center(0, 0))
    for i, j in ((w - 1, h - 1), (w - 1, 0), (0, h - 1)):
        goal = grid.world_to_cell(maze_cell_center(i, j))
        assert plan(grid, tuple(start), tuple(goal)).success


def test_maze_bad_parameters():
    with pytest.raises(ValueError, match="cells_x"):
        make_maze(0, 5)
    with pytest.raises(ValueError, match="wall"):
        make_maze(5, 5, cell_size=0.1, wall=0.2)


@pytest.mark.parametrize("name", ["x\n4 4\n255\n", "a\rb\x1b[31m", "ünï"])
def test_a_grid_name_never_rewrites_the_saved_images_header(name, tmp_path):
    """The name goes into the PGM's comment line: a line break in it rewrote the header, and the map read
    back was 4 x 4 with other cells blocked (API attack, session 29)."""
    blocked = np.zeros((10, 10), bool)
    blocked[2:8, 5] = True
    save_map(OccupancyGrid(blocked, name=name), tmp_path / "m.yaml")
    assert np.array_equal(load_map(tmp_path / "m.yaml").blocked, blocked)


@pytest.mark.parametrize("grid, path, field", [("grid", "m.yaml", "grid"), (None, "m.yaml", "grid"),
                                               ("ok", None, "yaml_path"), ("ok", 5, "yaml_path"),
                                               ("ok", "s\x00.yaml", "yaml_path")])
def test_save_map_names_what_it_cannot_take(grid, path, field, tmp_path):
    from navlab.errors import ParameterError

    grid = OccupancyGrid(np.zeros((3, 3), bool)) if grid == "ok" else np.zeros((3, 3), bool) if grid else grid
    path = str(tmp_path / path) if isinstance(path, str) else path
    with pytest.raises(ParameterError, match=f"^{field}: "):
        save_map(grid, path)


@pytest.mark.parametrize("kwargs, message", [
    ({"seed": -1}, "seed must be a non-negative whole number"), ({"seed": "a"}, "seed must be"),
    ({"seed": 1.5}, "seed must be"), ({"progress": 5}, "progress must be a callable"),
    ({"cells_x": 0}, "cells_x must be a whole number of at least 1, got 0"),
])
def test_make_maze_names_what_it_cannot_take(kwargs, message):
    """numpy's ValueError and TypeError came through for these (API attack, session 29)."""
    from navlab.errors import ParameterError

    with pytest.raises(ParameterError, match=message):
        make_maze(**kwargs)
    assert make_maze(np.int64(3), np.int64(2), seed=np.int64(1)).blocked.shape == make_maze(3, 2).blocked.shape
