"""Fuzzing maps (map_server YAML + PGM/PNG, Moving AI .map/.scen) and grid queries.

A file gives an OccupancyGrid in the supported range or one MapFormatError naming
the file; a query gives a Result that a plain cell check (scipy's Dijkstra for the
optimum) accepts, or navlab's error (a ValueError) naming start or goal.
"""

import io
import math
import warnings

import numpy as np
import yaml
from hypothesis import assume, example, given
from hypothesis import strategies as st
from PIL import Image

from navlab.errors import NavlabError
from navlab.grid.mapio import MapFormatError, load_map
from navlab.grid.occupancy import OccupancyGrid
from navlab.grid.planner import plan, plan_world
from navlab.grid.scen import read_scen
from navlab.limits import MAX_COORDINATE, MIN_LENGTH

from fuzz.checks import check_grid_result
from fuzz.strategies import HUGE_INTS, examples, wild_values

# --- grid queries ------------------------------------------------------------------------------


@st.composite
def grids(draw, max_side=12):
    h, w = draw(st.integers(1, max_side)), draw(st.integers(1, max_side))
    density = draw(st.sampled_from([0.0, 0.2, 0.4]))
    seed = draw(st.integers(0, 2**16))
    return np.random.default_rng(seed).random((h, w)) < density


def free_cell(draw, blocked):
    free = np.argwhere(~blocked)
    assume(len(free))
    y, x = free[draw(st.integers(0, len(free) - 1))]
    return int(x), int(y)


INT64 = st.integers(-(2**63), 2**63 - 1)
ANY_INT = st.one_of(st.integers(-3, 14), INT64, HUGE_INTS, INT64.map(np.int64), st.integers(-3, 14).map(np.int32))
ALGORITHMS = st.sampled_from(["astar", "dijkstra", "jps", "theta_star"])


@examples(120)
@given(grids(), st.data(), ALGORITHMS, st.sampled_from(["octile", "euclidean", "chebyshev"]))
def test_grid_query_with_integer_cells_anywhere(blocked, data, algorithm, heuristic):
    grid = OccupancyGrid(blocked)
    def cell(label):
        if data.draw(st.booleans(), label=f"{label} is a free cell"):
            return free_cell(data.draw, blocked)
        return data.draw(st.tuples(ANY_INT, ANY_INT), label=label)

    start, goal = cell("start"), cell("goal")
    result = plan(grid, start, goal, algorithm=algorithm, heuristic=heuristic)
    check_grid_result(grid.passable(), (int(start[0]), int(start[1])), (int(goal[0]), int(goal[1])), result, algorithm)


WILD_CELL = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([math.inf, -math.inf, math.nan]),
                      st.just("3"), st.just(None), st.just([1]))


@examples(60)
@given(grids(), st.tuples(WILD_CELL, WILD_CELL), ALGORITHMS)
@example(np.zeros((3, 3), bool), (math.inf, 0), "astar")
def test_grid_query_with_any_number_names_the_cell(blocked, start, algorithm):
    grid = OccupancyGrid(blocked)
    try:
        result = plan(grid, start, (0, 0), algorithm=algorithm)
    except NavlabError as exc:
        assert "start" in str(exc)
    else:
        check_grid_result(grid.passable(), (int(start[0]), int(start[1])), (0, 0), result, algorithm)


@examples(40)
@given(st.tuples(st.one_of(st.floats(), st.sampled_from([math.nan, math.inf, 1e300])), st.floats(-2, 12)))
@example((math.nan, 1.0))
def test_grid_query_in_metres_with_any_float(start_xy):
    grid = OccupancyGrid(np.zeros((10, 10), bool), resolution=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a RuntimeWarning is the symptom of an unchecked NaN
        try:
            result = plan_world(grid, start_xy, (1.0, 1.0))
        except NavlabError as exc:
            assert "start" in str(exc)
            return
    assert "-9223372036854775808" not in result.reason


# --- map_server maps -----------------------------------------------------------------------------


@st.composite
def images(draw):
    """(file name, bytes, (height, width) or None when the bytes are not meant to decode)."""
    kind = draw(st.sampled_from(["png", "pgm5", "pgm2", "garbage"]))
    h, w = draw(st.integers(1, 24)), draw(st.integers(1, 24))
    pixels = np.random.default_rng(draw(st.integers(0, 2**16))).integers(0, 256, (h, w), dtype=np.uint8)
    if kind == "png":
        mode = draw(st.sampled_from(["L", "LA", "RGB", "RGBA", "P", "1", "I;16"]))
        img = Image.fromarray(pixels).convert(mode) if mode != "I;16" else Image.fromarray(pixels.astype(np.uint16))
        buf = io.BytesIO()
        img.save(buf, format="PNG")
        return "map.png", buf.getvalue(), (h, w)
    if kind.startswith("pgm"):
        maxval = draw(st.sampled_from([255, 1, 100, 65535]))
        header = f"P{kind[-1]}\n# fuzz\n{w} {h}\n{maxval}\n".encode()
        pixels = pixels.astype(np.int64) % (maxval + 1)  # a valid PGM has no value above maxval (those are refused)
        if kind == "pgm5":
            body = pixels.astype(">u2" if maxval > 255 else np.uint8).tobytes()
        else:
            body = " ".join(str(v) for v in pixels.ravel()).encode()
        if draw(st.booleans()):
            cut = draw(st.integers(0, len(body)))
            return "map.pgm", header + body[:cut], None if cut < len(body) else (h, w)
        return "map.pgm", header + body, (h, w)
    name = draw(st.sampled_from(["map.png", "map.pgm", "map.bmp"]))
    return name, draw(st.binary(max_size=64)), None


SANE_META = st.fixed_dictionaries(
    {"resolution": st.floats(0.01, 2.0), "origin": st.lists(st.floats(-100, 100), min_size=3, max_size=3)},
    optional={"occupied_thresh": st.floats(0.5, 1.0), "free_thresh": st.floats(0.0, 0.5),
              "negate": st.sampled_from([0, 1]), "mode": st.sampled_from(["trinary", "scale", "raw"])})


def load_or_error(path):
    try:
        return load_map(path)
    except MapFormatError as exc:
        assert str(path.parent) in str(exc) and "\n" not in str(exc), str(exc)  # the YAML or its image
        return exc


def check_grid_in_range(grid: OccupancyGrid) -> None:
    assert MIN_LENGTH <= grid.resolution <= MAX_COORDINATE
    assert all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in grid.origin), grid.origin
    assert grid.blocked.shape == grid.unknown.shape and grid.blocked.ndim == 2


@examples(80)
@given(images(), SANE_META, st.data())
def test_map_server_images_load_or_one_error(tmp_path_factory, image, meta, data):
    name, content, shape = image
    folder = tmp_path_factory.mktemp("map")
    (folder / name).write_bytes(content)
    (folder / "map.yaml").write_text(yaml.safe_dump({"image": name, **meta}))
    out = load_or_error(folder / "map.yaml")
    if shape is not None and name != "map.bmp":
        assert isinstance(out, OccupancyGrid), str(out)
    if isinstance(out, OccupancyGrid):
        check_grid_in_range(out)
        if shape is not None:
            assert out.blocked.shape == shape
        passable = out.passable()
        free = np.argwhere(passable)
        if len(free):
            a = free[data.draw(st.integers(0, len(free) - 1))][::-1]
            b = free[data.draw(st.integers(0, len(free) - 1))][::-1]
            check_grid_result(passable, tuple(a), tuple(b), plan(out, tuple(a), tuple(b)), "astar")


@examples(80)
@given(st.sampled_from(["resolution", "origin", "occupied_thresh", "free_thresh", "negate", "mode", "image"]),
       st.one_of(wild_values(), st.lists(wild_values(), min_size=3, max_size=3)))
@example("origin", [math.nan, 0, 0])
@example("resolution", 10 ** 400)
def test_map_server_fields_in_range_or_named(tmp_path_factory, field, value):
    folder = tmp_path_factory.mktemp("map")
    Image.fromarray(np.full((4, 5), 254, np.uint8)).save(folder / "map.png")
    meta = {"image": "map.png", "resolution": 0.05, "origin": [0.0, 0.0, 0.0], field: value}
    (folder / "map.yaml").write_text(yaml.safe_dump(meta))
    out = load_or_error(folder / "map.yaml")
    if isinstance(out, OccupancyGrid):
        check_grid_in_range(out)
    else:
        assert field in str(out) or "image" in str(out), str(out)


def test_map_server_image_that_is_a_directory(tmp_path):
    (tmp_path / "d").mkdir()
    (tmp_path / "map.yaml").write_text("image: d\nresolution: 0.05\n")
    assert isinstance(load_or_error(tmp_path / "map.yaml"), MapFormatError)


# --- Moving AI maps and scenarios ----------------------------------------------------------------

TERRAIN = st.sampled_from(list(".GS@OTW") + ["x", " ", "é"])


@st.composite
def movingai_maps(draw):
    """(text, (height, width) or None when the text is not a valid map)."""
    h, w = draw(st.integers(1, 12)), draw(st.integers(1, 12))
    rows = ["".join(draw(st.lists(st.sampled_from(list(".@TGSOW")), min_size=w, max_size=w))) for _ in range(h)]
    header = {"type": "octile", "height": str(h), "width": str(w)}
    valid = True
    trick = draw(st.sampled_from([None, None, "height", "width", "type", "row", "extra"]))
    if trick in ("height", "width"):
        header[trick] = draw(st.sampled_from(["abc", "1.5", "0x10", "1e3"]))
        valid = False
    elif trick == "type":
        header["type"] = draw(st.sampled_from(["tile", "", "OCTILE"]))
        valid = False
    elif trick == "row":
        i = draw(st.integers(0, h - 1))
        rows[i] = draw(st.sampled_from([rows[i][:-1], rows[i][:-1] + draw(TERRAIN)]))  # longer: see below
        valid = len(rows[i]) == w and set(rows[i]) <= set(".GS@OTW")
    elif trick == "extra":
        rows = rows[: draw(st.integers(0, h - 1))]
        valid = False
    text = "".join(f"{k} {v}\n" for k, v in header.items()) + "map\n" + "\n".join(rows) + "\n"
    return text, (h, w) if valid else None


@examples(80)
@given(movingai_maps())
def test_movingai_maps_load_or_one_error(tmp_path_factory, case):
    text, shape = case
    path = tmp_path_factory.mktemp("m") / "fuzz.map"
    path.write_text(text, encoding="utf-8")
    out = load_or_error(path)
    if shape is None:
        assert isinstance(out, MapFormatError), f"accepted a malformed map:\n{text}"
    else:
        assert isinstance(out, OccupancyGrid), str(out)
        assert out.blocked.shape == shape


@examples(30)
@given(st.integers(1, 6), st.integers(1, 6), st.sampled_from(["long", "0", "-1", str(10**30)]), st.booleans())
@example(1, 2, "long", True)
@example(1, 2, "-1", True)
def test_movingai_bad_sizes_are_refused(tmp_path_factory, h, w, trick, in_height):
    rows = ["." * (w + (trick == "long"))] * h
    if trick != "long":
        h, w = (trick, w) if in_height else (h, trick)
    text = f"type octile\nheight {h}\nwidth {w}\nmap\n" + "\n".join(rows) + "\n"
    path = tmp_path_factory.mktemp("l") / "bad.map"
    path.write_text(text)
    assert isinstance(load_or_error(path), MapFormatError)


@examples(60)
@given(st.one_of(
    st.lists(st.lists(st.one_of(st.integers(-5, 50).map(str), st.sampled_from(["a.map", "nan", "inf", "1e999", ""])),
                      min_size=9, max_size=9).map("\t".join), max_size=4).map(lambda rows: "version 1\n" + "\n".join(rows)),
    st.text(max_size=80)))
def test_scenarios_parse_or_one_error(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("s") / "fuzz.scen"
    path.write_text(text, encoding="utf-8")
    try:
        rows = read_scen(path)
    except MapFormatError as exc:
        assert path.name in str(exc)
    else:
        assert all(isinstance(r.start[0], int) and isinstance(r.goal[1], int) for r in rows)


@examples(10)
@given(st.sampled_from(["fuzz.map", "fuzz.scen"]), st.binary(min_size=1, max_size=40))
@example("fuzz.scen", b"version 1\n\xff\n")
def test_binary_map_files_give_one_error(tmp_path_factory, name, content):
    path = tmp_path_factory.mktemp("b") / name
    path.write_bytes(content)
    try:
        load_map(path) if name.endswith(".map") else read_scen(path)
    except MapFormatError as exc:
        assert name in str(exc)
