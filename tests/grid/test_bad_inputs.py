"""Bad maps, grids and CLI input (issue 13): a MapFormatError/ValueError naming
the file and field from the API; one line, exit 2 and no traceback from the CLI."""

import errno
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from navlab.cli import main
from navlab.grid import MAX_CELLS, MapFormatError, OccupancyGrid, load_map, make_maze, plan_world


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def assert_one_line_exit_2(res, *needles):
    assert res.exit_code == 2, res.output
    assert "Traceback" not in res.output and res.exception is None or isinstance(res.exception, SystemExit)
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("Error: "), res.output
    for needle in needles:
        assert needle in lines[0], lines[0]


def ros_yaml(tmp_path, image="m.pgm", **fields):
    meta = {"image": image, "resolution": 0.1, "origin": "[0.0, 0.0, 0.0]", **fields}
    path = tmp_path / "m.yaml"
    path.write_text("".join(f"{k}: {v}\n" for k, v in meta.items()))
    return path


def tiny_pgm(tmp_path, name="m.pgm"):
    (tmp_path / name).write_bytes(b"P5\n2 2\n255\n" + bytes([0, 254, 254, 254]))


def png_header_only(path: Path, width: int, height: int) -> None:
    """A PNG whose header claims width × height pixels, with a one-byte image
    stream: decoding it would need the full size; its header alone does not."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0"))
                     + chunk(b"IEND", b""))


# -- map files ----------------------------------------------------------------------
def test_image_name_too_long_for_the_file_system(tmp_path):
    """(attack, session 20: the OSError's 100 000-character name filled one 100 KB line, the field unnamed)"""
    path = ros_yaml(tmp_path, image="a" * 100_000 + ".pgm")
    with pytest.raises(MapFormatError, match=r"field 'image': a{150}\.\.\.a{71}\.pgm \(a name of 100004 characters\): "
                                             r"File name too long") as err:
        load_map(path)
    assert len(str(err.value)) < 400
    assert_one_line_exit_2(run("grid", "plan", path, "--start", 0, 0, "--goal", 1, 1), "too long", "image")


def test_image_that_is_a_directory(tmp_path):
    (tmp_path / "imgdir").mkdir()
    path = ros_yaml(tmp_path, image="imgdir")
    with pytest.raises(MapFormatError, match="field 'image' names a directory") as err:
        load_map(path)
    assert str(path) in str(err.value)
    assert_one_line_exit_2(run("grid", "plan", path, "--start", 0, 0, "--goal", 1, 1), "directory", "image")
    res = run("grid", "plan", tmp_path, "--start", 0, 0, "--goal", 1, 1)  # click's own usage error
    assert res.exit_code == 2 and "is a directory" in res.output and "Traceback" not in res.output


@pytest.mark.parametrize("size", [(12_000, 9_000), (20_000, 20_000)])  # ours, and past Pillow's own bomb limit
def test_huge_png_refused_from_its_header(tmp_path, size):
    png_header_only(tmp_path / "big.png", *size)
    path = ros_yaml(tmp_path, image="big.png")
    with pytest.raises(MapFormatError, match="1e\\+08 cells") as err:
        load_map(path)
    assert "big.png" in str(err.value)
    assert_one_line_exit_2(run("grid", "plan", path, "--start", 0, 0, "--goal", 1, 1), "big.png")


def test_huge_pgm_and_map_refused_before_allocating(tmp_path):
    (tmp_path / "big.pgm").write_bytes(b"P5\n100000 100000\n255\n" + bytes(10))
    with pytest.raises(MapFormatError, match="width 100000 x height 100000"):
        load_map(ros_yaml(tmp_path, image="big.pgm"))
    (tmp_path / "big.map").write_text("type octile\nheight 3\nwidth 100000000000\nmap\n...\n")
    with pytest.raises(MapFormatError, match="100000000000"):
        load_map(tmp_path / "big.map")
    assert_one_line_exit_2(run("grid", "plan", tmp_path / "big.map", "--start", 0, 0, "--goal", 1, 1), "big.map")


def test_a_map_beyond_the_memory_available_is_refused_from_its_header(tmp_path, monkeypatch):
    """Within MAX_CELLS, but the machine (here: 10 MiB free) cannot hold it decoded."""
    import navlab.limits

    monkeypatch.setattr(navlab.limits, "available_memory", lambda: 10 * 2**20)
    (tmp_path / "big.pgm").write_bytes(b"P5\n2000 2000\n255\n" + bytes(10))  # 4e6 px, header only
    with pytest.raises(MapFormatError, match=r"big.pgm: the 2000x2000 image .* needs about 68.7 MiB, more than the 10 MiB"):
        load_map(ros_yaml(tmp_path, image="big.pgm"))
    (tmp_path / "small.pgm").write_bytes(b"P5\n20 20\n255\n" + bytes(400))
    assert load_map(ros_yaml(tmp_path, image="small.pgm")).blocked.shape == (20, 20)


@pytest.mark.parametrize("rows, message", [
    ("...\n....\n", "row 1 has 4 characters, the header's width is 3"),
    ("....\n...\n", "row 0 has 4 characters"),
    ("...\n..\n", "row 1 has 2 characters"),
    ("...\n...\n...\n", "more map rows"),
])
def test_map_rows_must_match_the_header(tmp_path, rows, message):
    (tmp_path / "r.map").write_text("type octile\nheight 2\nwidth 3\nmap\n" + rows)
    with pytest.raises(MapFormatError, match=message):
        load_map(tmp_path / "r.map")
    assert_one_line_exit_2(run("grid", "plan", tmp_path / "r.map", "--start", 0, 0, "--goal", 1, 1), "r.map")


@pytest.mark.parametrize("field, value, message", [
    ("origin", "[.nan, 0.0, 0.0]", "'origin' x must be a finite number"),
    ("origin", "[0.0, .inf, 0.0]", "'origin' y must be a finite number"),
    ("origin", "[0.0, 0.0, -.inf]", "'origin' yaw"),
    ("origin", "[1e400, 0.0, 0.0]", "'origin' x"),
    ("origin", "[" + "9" * 400 + ", 0, 0]", "'origin' x"),
    ("origin", "[2e7, 0.0, 0.0]", "out of range"),
    ("origin", "[a, 0, 0]", "'origin' x"),
    ("resolution", ".nan", "'resolution' must be finite"),
    ("resolution", "1e-12", "'resolution' must be between"),
    ("resolution", "1e8", "'resolution' must be between"),
    ("resolution", "9" * 400, "'resolution' must be a finite number, got an integer of 400 digits"),
    ("resolution", "{a: 1}", "'resolution' must be a number"),
    ("resolution", "fine", "'resolution' must be a number"),
    ("negate", "0.5", "'negate'"),
    ("image", "{a: 1}", "'image' must be a file name"),
])
def test_bad_yaml_fields_are_named(tmp_path, field, value, message):
    tiny_pgm(tmp_path)
    path = ros_yaml(tmp_path, **{field: value})
    with pytest.raises(MapFormatError, match=message) as err:
        load_map(path)
    assert str(path) in str(err.value)
    assert_one_line_exit_2(run("grid", "plan", path, "--start", 0, 0, "--goal", 1, 1), field)


@pytest.mark.parametrize("kwargs, message", [
    ({"origin": (float("nan"), 0.0, 0.0)}, "origin x"),
    ({"origin": (0.0, float("inf"), 0.0)}, "origin y"),
    ({"origin": (0.0, 0.0, float("nan"))}, "origin yaw"),
    ({"origin": (3e7, 0.0, 0.0)}, "origin x"),
    ({"origin": (10**400, 0.0, 0.0)}, "origin x"),
    ({"resolution": float("inf")}, "resolution"),
    ({"resolution": 1e-10}, "resolution"),
    ({"resolution": 10**400}, "resolution"),
    ({"resolution": "0.1"}, "resolution"),
    ({"origin": 5}, "origin"),
])
def test_the_constructor_checks_its_frame(kwargs, message):
    with pytest.raises(ValueError, match=message):
        OccupancyGrid(np.zeros((2, 2), bool), **kwargs)


def test_the_constructor_refuses_more_than_max_cells():
    big = np.lib.stride_tricks.as_strided(np.zeros(1, bool), shape=(MAX_CELLS // 1000 + 1, 1000), strides=(0, 0))
    with pytest.raises(ValueError, match="cells"):
        OccupancyGrid(big)


# -- grid plan / scen / maze ----------------------------------------------------------
@pytest.mark.parametrize("start", [("inf", "0"), ("nan", "0"), ("0", "-inf")])
@pytest.mark.parametrize("world", [False, True])
def test_non_finite_start_is_one_line(tmp_path, start, world):
    maze = tmp_path / "maze.yaml"
    assert run("grid", "maze", "--cells", 3, 3, "--out", maze).exit_code == 0
    res = run("grid", "plan", maze, *(["--world"] if world else []), "--start", *start, "--goal", 20, 20)
    assert_one_line_exit_2(res, "--start must be finite")


def test_plan_world_refuses_non_finite_and_huge_points():
    grid = OccupancyGrid(np.zeros((4, 4), bool))
    for bad, field in (((float("nan"), 0.0), "start x"), ((0.0, 1e300), "start y")):
        with pytest.raises(ValueError, match=field):
            plan_world(grid, bad, (1.0, 1.0))


def test_huge_maze_refused_before_starting(tmp_path):
    res = run("grid", "maze", "--cells", 100000, 100000, "--out", tmp_path / "m.yaml")
    assert_one_line_exit_2(res, "1e+08")
    assert not list(tmp_path.iterdir())


def test_maze_memory_estimate_against_what_is_available(monkeypatch):
    import navlab.grid.maze as maze

    monkeypatch.setattr(maze, "available_memory", lambda: 10 * 2**20)  # a 10 MiB machine
    with pytest.raises(ValueError, match="GiB available"):
        make_maze(300, 300, resolution=0.05)  # 3001 x 3001 pixels: ~0.1 GiB
    make_maze(10, 10)  # small ones still fit


def test_coarse_maze_resolution_refused(tmp_path):
    res = run("grid", "maze", "--resolution", 1.0, "--out", tmp_path / "m.yaml")
    assert_one_line_exit_2(res, "resolution 1 m is coarser than the 0.1 m wall")
    with pytest.raises(ValueError, match="corridor"):
        make_maze(3, 3, cell_size=0.5, wall=0.45, resolution=0.1)


def test_maze_on_a_full_disk_leaves_no_file(tmp_path, monkeypatch):
    real = Path.write_bytes

    def full(self, data):
        real(self, data[: len(data) // 2])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Path, "write_bytes", full)
    res = run("grid", "maze", "--out", tmp_path / "m.yaml")
    assert_one_line_exit_2(res, "cannot write", "m.pgm", "No space left on device")
    assert not list(tmp_path.iterdir())  # no 0-byte or half file under any name


def test_failed_plot_shows_start_and_goal_without_warnings(tmp_path, recwarn):
    import matplotlib

    matplotlib.use("Agg")
    from navlab.grid import plan
    from navlab.viz.grid_plot import plot_grid_plan

    blocked = np.zeros((5, 5), bool)
    blocked[:, 2] = True
    grid = OccupancyGrid(blocked, 0.5)
    result = plan(grid, (0, 0), (4, 4))
    fig = plot_grid_plan(grid, result, start=(0.25, 0.25), goal=(2.25, 2.25))
    labels = [line.get_label() for line in fig.axes[0].get_lines()]
    assert labels == ["start", "goal"] and fig.axes[0].get_legend() is not None
    fig = plot_grid_plan(grid, result)  # nothing labelled: no legend, no warning
    assert fig.axes[0].get_legend() is None
    assert not [w for w in recwarn if "artists with labels" in str(w.message)]
    res = run("grid", "plan", _map(tmp_path, blocked), "--start", 0, 0, "--goal", 4, 4, "--plot", tmp_path / "f.png")
    assert res.exit_code == 1 and "FAILED" in res.output and "No artists" not in res.output
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"


def _map(tmp_path, blocked):
    rows = ["".join("@" if b else "." for b in row) for row in blocked]
    path = tmp_path / "f.map"
    path.write_text(f"type octile\nheight {len(rows)}\nwidth {len(rows[0])}\nmap\n" + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("kwargs, message", [
    ({"cell_size": float("inf")}, "cell_size must be finite"),
    ({"resolution": float("nan")}, "resolution must be finite"),
    ({"cell_size": 1e300}, r"cell_size = 1e\+300 is out of range"),
    ({"wall": 1.0, "cell_size": 0.5}, r"wall \(1 m\) must be thinner than cell_size \(0.5 m\)"),
    ({"cell_size": 1e6, "wall": 1e5, "resolution": 1e5}, "m across, more than the 1e\\+07 m navlab supports"),
])
def test_maze_sizes_out_of_range_are_named(kwargs, message):
    """cell_size=inf was an internal OverflowError; 1e6 m cells made a map navlab plan refused."""
    from navlab.grid.maze import make_maze, maze_size

    with pytest.raises(ValueError, match=message):
        maze_size(10, 10, **{"cell_size": 0.5, "wall": 0.1, "resolution": 0.05, **kwargs})
    with pytest.raises(ValueError, match=message):
        make_maze(10, 10, **kwargs)
