"""Maps read as Nav2's map_io reads them, and as ROS 1's map_server did.

Every expected value below is derived by hand from the rules in docs/grid.md
(Nav2: grey g, occ = 1 − g/255 in single precision, inclusive thresholds,
alpha < 255 unknown, raw 0–100 kept; ROS 1: channel mean, strict thresholds,
99·ratio truncated).
"""

from pathlib import Path

import numpy as np
import pytest
import yaml
from PIL import Image

from navlab.grid import load_map

NAV2_DATA = Path(__file__).resolve().parents[1] / "data" / "nav2"


def write_map(tmp_path, pixels, mode="trinary", name="m.pgm", **meta):
    pixels = np.asarray(pixels, dtype=np.uint8)
    img = tmp_path / name
    if img.suffix == ".pgm":
        h, w = pixels.shape
        img.write_bytes(f"P5\n{w} {h}\n255\n".encode() + pixels.tobytes())
    else:
        Image.fromarray(pixels).save(img)
    data = {"image": img.name, "mode": mode, "resolution": 0.1, "origin": [0.0, 0.0, 0.0], "negate": 0,
            "occupied_thresh": 0.65, "free_thresh": 0.196, **meta}
    out = tmp_path / (img.stem + ".yaml")
    out.write_text(yaml.safe_dump(data))
    return out


def test_thresholds_are_inclusive_under_nav2_and_strict_under_ros1(tmp_path):
    # black: occ = 1.0 exactly; white: occ = 0.0 exactly
    path = write_map(tmp_path, [[0, 255]], occupied_thresh=1.0, free_thresh=0.0)
    nav2, ros1 = load_map(path), load_map(path, rule="ros1")
    assert nav2.blocked.tolist() == [[True, False]] and nav2.unknown.tolist() == [[False, False]]
    assert ros1.blocked.tolist() == [[False, False]] and ros1.unknown.tolist() == [[True, True]]


def test_a_threshold_met_exactly_in_single_precision(tmp_path):
    # Nav2 compares occ = 1 − g/255 in float32 with the threshold as float32
    occ_89 = float(np.float32(1.0) - np.float32(89) / np.float32(255))
    occ_210 = float(np.float32(1.0) - np.float32(210) / np.float32(255))
    path = write_map(tmp_path, [[89, 210, 150]], occupied_thresh=occ_89, free_thresh=occ_210)
    grid = load_map(path)
    assert grid.blocked.tolist() == [[True, False, False]]
    assert grid.unknown.tolist() == [[False, False, True]]  # 150: occ 0.41, between


def test_partly_transparent_pixels_are_unknown_in_trinary_mode(tmp_path):
    rgba = np.zeros((1, 4, 4), dtype=np.uint8)
    rgba[0, :, :3] = [[255, 255, 255], [255, 255, 255], [0, 0, 0], [0, 0, 0]]
    rgba[0, :, 3] = [255, 254, 255, 0]
    path = write_map(tmp_path, rgba, name="a.png")
    nav2 = load_map(path)
    assert nav2.blocked.tolist() == [[False, False, True, False]]
    assert nav2.unknown.tolist() == [[False, True, False, True]]
    # ROS 1 averaged the alpha byte into the colour: (255·3 + 254)/4 is still white,
    # (0 + 0 + 0 + 0)/4 still black; nothing becomes unknown
    ros1 = load_map(path, rule="ros1")
    assert ros1.blocked.tolist() == [[False, False, True, True]] and not ros1.unknown.any()


def test_raw_mode_keeps_0_to_100_as_probabilities(tmp_path):
    path = write_map(tmp_path, [[0, 37, 99, 100, 101, 254, 255]], mode="raw")
    grid = load_map(path)
    assert grid.blocked.tolist() == [[False, False, False, True, False, False, False]]
    assert grid.unknown.tolist() == [[False, False, False, False, True, True, True]]
    np.testing.assert_allclose(grid.probability, [[0.0, 0.37, 0.99, 1.0, np.nan, np.nan, np.nan]], rtol=1e-6)
    # 99 % occupied is passable (Nav2's static layer: lethal only at 100)
    assert grid.passable().tolist() == [[True, True, True, False, False, False, False]]


def test_scale_mode_keeps_the_in_between_probability(tmp_path):
    # g = 128: occ = 127/255 = 0.49804; (0.49804 − 0.196)/(0.65 − 0.196) = 0.66528
    path = write_map(tmp_path, [[0, 128, 254]], mode="scale")
    nav2, ros1 = load_map(path), load_map(path, rule="ros1")
    assert nav2.blocked.tolist() == [[True, False, False]] and not nav2.unknown.any()
    np.testing.assert_allclose(nav2.probability, [[1.0, 0.67, 0.0]], rtol=1e-6)  # round(66.53)
    np.testing.assert_allclose(ros1.probability, [[1.0, 0.65, 0.0]], rtol=1e-6)  # int(99 · 0.66528)
    assert nav2.passable().tolist() == [[False, True, True]]


def test_scale_mode_transparent_pixels(tmp_path):
    la = np.array([[[128, 255], [128, 200], [0, 200]]], dtype=np.uint8)
    path = write_map(tmp_path, la, mode="scale", name="la.png")
    nav2, ros1 = load_map(path), load_map(path, rule="ros1")
    assert nav2.unknown.tolist() == [[False, True, True]]
    # ROS 1: only a fully transparent in-between pixel was unknown; occupied stays occupied
    assert ros1.unknown.tolist() == [[False, False, False]] and ros1.blocked.tolist() == [[False, False, True]]


def test_negate(tmp_path):
    path = write_map(tmp_path, [[0, 255]], negate=1)
    assert load_map(path).blocked.tolist() == [[False, True]]
    assert load_map(path, rule="ros1").blocked.tolist() == [[False, True]]


def test_colour_is_read_as_luma_by_nav2_and_as_the_channel_mean_by_ros1(tmp_path):
    # pure green: luma 0.587·255 = 150 → occ 0.41, unknown; mean 85 → occ 0.667 > 0.65, occupied
    path = write_map(tmp_path, np.array([[[0, 255, 0]]]), name="g.png")
    assert load_map(path).unknown.tolist() == [[True]]
    assert load_map(path, rule="ros1").blocked.tolist() == [[True]]


def test_nav2s_depot_speed_mask_loads_with_its_walls_occupied():
    path = NAV2_DATA / "depot_speed.yaml"
    pixels = np.asarray(Image.open(NAV2_DATA / "depot_speed.pgm"))
    walls = np.flipud(pixels == 0)
    grid = load_map(path)
    assert (grid.width, grid.height) == (604, 307) and grid.resolution == 0.05
    np.testing.assert_array_equal(grid.blocked, walls)
    assert walls.sum() == 3735 and not grid.unknown.any()
    # the speed zones are kept as percentages: 127 → occ 0.502 → 50, 191 → 25, 205 → 20, 254 → 0
    values = {int(round(100 * v)) for v in np.unique(grid.probability)}
    assert values == {0, 20, 25, 50, 100}
    # ROS 1's strict rule left these walls at 99 and passable: the bug Nav2's rule fixes
    assert not load_map(path, rule="ros1").blocked.any()


def test_unknown_rule_is_refused(tmp_path):
    with pytest.raises(ValueError, match="rule"):
        load_map(write_map(tmp_path, [[0]]), rule="ros3")
