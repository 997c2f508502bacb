"""Map files: ROS map_server YAML + PGM/PNG, and Moving AI ``.map``.

ROS map_server maps are read as Nav2's ``nav2_map_server`` reads them (the
ROS 2 standard; ``rule="nav2"``, the default), or as ROS 1's ``map_server``
did (``rule="ros1"``). Both turn each pixel into a value of a ROS
``nav_msgs/OccupancyGrid`` (−1 unknown, 0 free, 100 occupied, 1–99 in
between); navlab then blocks the cells of value 100, marks −1 unknown, and
keeps the in-between values (``scale``/``raw`` modes) as probabilities in
``OccupancyGrid.probability``. docs/grid.md states both rules in full.

The image's first row is the top of the map, so row 0 of ``blocked`` is the
image's last row (at ``origin``).
"""

from __future__ import annotations

import math
import os
import warnings
from pathlib import Path
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np
import yaml

from ..atomic import atomic_path
from ..errors import NavlabError, ParameterError
from ..limits import MAX_COORDINATE, MIN_LENGTH, check_memory, check_path, finite_number, short_name, shown
from ..wording import escaped
from ..yamlio import read_yaml, regular_file
from ..yamlcore import number_text
from .occupancy import MAX_CELLS, OccupancyGrid

PathLike = Union[str, os.PathLike]


class MapFormatError(NavlabError):
    """A map file is malformed; the message names the file and the problem."""


MOVINGAI_PASSABLE = set(".GS")
MOVINGAI_BLOCKED = set("@OTW")
MAP_RULES = ("nav2", "ros1")
MAP_MODES = ("trinary", "scale", "raw")
UNKNOWN, FREE, OCCUPIED = -1, 0, 100  #: nav_msgs/OccupancyGrid cell values


#: [bytes] largest map_server YAML read (a dozen fields; a 200 MB one took 105 s to refuse)
MAX_MAP_YAML_BYTES = 2**20

#: Bytes a map pixel costs at the peak of loading (decoded image, cell values,
#: the grid's arrays; measured 17 with ``mode: scale``).
BYTES_PER_MAP_PIXEL = 18


def _check_size(path: Path, width: int, height: int) -> None:
    """Refuse, from the header and before decoding, a map over MAX_CELLS or
    one whose loading would need more memory than the machine has."""
    cells = width * height
    if cells > MAX_CELLS:
        raise MapFormatError(f"{path}: width {width} x height {height} = {cells} cells is more than the "
                             f"{MAX_CELLS:.0e} cells navlab reads (navlab.grid.MAX_CELLS)")
    try:
        check_memory(cells * BYTES_PER_MAP_PIXEL, f"the {width}x{height} image (width x height)")
    except ValueError as exc:
        raise MapFormatError(f"{path}: {exc}") from None


# -- PGM ---------------------------------------------------------------------------
def _pgm_header(path: Path, f) -> Tuple[bytes, int, int, int]:
    """Magic, width, height and maxval, leaving ``f`` at the first data byte."""
    head = f.read(1 << 16)  # a header (with comments) longer than 64 KiB is not a map's
    magic = head[:2]
    if magic not in (b"P5", b"P2"):
        raise MapFormatError(f"{path}: not a PGM file (magic {magic!r}, expected P5 or P2)")
    tokens, pos = [], 2
    while len(tokens) < 3:
        while pos < len(head) and head[pos:pos + 1].isspace():
            pos += 1
        if head[pos:pos + 1] == b"#":
            while pos < len(head) and head[pos:pos + 1] not in (b"\n", b"\r"):
                pos += 1
            continue
        start = pos
        while pos < len(head) and not head[pos:pos + 1].isspace() and head[pos:pos + 1] != b"#":
            pos += 1
        if start == pos or pos == len(head):
            raise MapFormatError(f"{path}: truncated PGM header")
        tokens.append(head[start:pos])
    try:
        width, height, maxval = (int(t) for t in tokens)
    except ValueError:
        raise MapFormatError(f"{path}: bad PGM header values {tokens}") from None
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapFormatError(f"{path}: bad PGM size {width}x{height} or maxval {maxval}")
    _check_size(path, width, height)
    f.seek(pos + 1)  # the single whitespace after maxval
    return magic, width, height, maxval


def read_pgm(path: PathLike) -> np.ndarray:
    """Read a binary (P5) or plain (P2) PGM as 8-bit grey levels (first row = top).

    Other ``maxval`` are scaled to 0–255 and rounded, as an image library
    converting to 8-bit grey does. The size is checked against
    :data:`~navlab.grid.occupancy.MAX_CELLS` before the pixels are read.
    """
    p = check_path("path", path)
    with open(p, "rb") as f:
        magic, width, height, maxval = _pgm_header(p, f)
        count = width * height
        if magic == b"P5":
            dtype = np.dtype(np.uint8) if maxval < 256 else np.dtype(">u2")
            data = f.read(count * dtype.itemsize)
            raw = np.frombuffer(data, dtype=dtype, count=len(data) // dtype.itemsize)
        else:
            # at most 6 bytes ("65535 ") a pixel; a longer file is not this image
            data = f.read(count * 8 + 4096)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)  # a stray token ends the parse
                try:
                    raw = np.fromstring(data.decode("latin-1"), dtype=np.int64, sep=" ")
                except ValueError:  # numpy ≥ 2.x: "could not be read to its end due to unmatched data"
                    raise MapFormatError(f"{p}: PGM pixel data must be whitespace-separated whole numbers "
                                         f"0..{maxval} (found something else)") from None
    if raw.size < count:
        raise MapFormatError(f"{p}: truncated PGM data: {raw.size} of {count} pixels ({width}x{height})")
    raw = raw[:count].reshape(height, width)
    if np.any((raw < 0) | (raw > maxval)):
        raise MapFormatError(f"{p}: PGM pixel values outside 0..{maxval}")
    if maxval == 255:
        return raw.astype(np.uint8)
    return np.floor(raw.astype(np.float64) * (255.0 / maxval) + 0.5).astype(np.uint8)


# -- images: grey levels and alpha ------------------------------------------------
class _Image:
    """The parts of an image the two rules read: 8-bit grey (luma, as Nav2's
    GraphicsMagick converts), the per-pixel sum of the colour channels and
    their count (ROS 1 averages them), and alpha (None when opaque)."""

    def __init__(self, gray: np.ndarray, colour_sum: np.ndarray, channels: int, alpha: Optional[np.ndarray]):
        self.gray, self.colour_sum, self.channels, self.alpha = gray, colour_sum, channels, alpha


def _read_image(path: Path) -> _Image:
    regular_file(path, str(path), MapFormatError, "map image")  # a FIFO would block the read for ever
    if path.suffix.lower() == ".pgm":
        gray = read_pgm(path)
        return _Image(gray, gray, 1, None)
    from PIL import Image, UnidentifiedImageError

    with warnings.catch_warnings():
        # navlab's own limit (MAX_CELLS) is checked on the header just below
        warnings.simplefilter("ignore", Image.DecompressionBombWarning)
        try:
            with Image.open(path) as img:
                width, height = img.size
                _check_size(path, width, height)
                img.load()
                if img.mode == "P" or img.mode.startswith("I") or img.mode == "F":
                    # palettes and 16-bit/float grey: through RGBA (keeps transparency)
                    img = img.convert("RGBA") if img.mode == "P" else _gray16_to_l(img, path)
                bands = img.getbands()
                alpha = np.asarray(img.getchannel("A")) if "A" in bands else None
                gray = np.asarray(img.convert("L"))
                colour_bands = [b for b in bands if b != "A"]
                if colour_bands == ["L"]:
                    colour_sum, channels = gray, 1
                else:
                    rgb = np.asarray(img.convert("RGB"))
                    colour_sum, channels = rgb.sum(axis=2, dtype=np.uint16), 3
        except Image.DecompressionBombError as exc:
            raise MapFormatError(f"{path}: image too large ({exc}); navlab reads at most "
                                 f"{MAX_CELLS:.0e} cells") from None
        except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
            if isinstance(exc, MapFormatError):
                raise
            raise MapFormatError(f"{path}: cannot read image: {exc}") from None
    return _Image(gray, colour_sum, channels, alpha)


def _gray16_to_l(img, source):
    """16-bit or float grey to 8-bit, scaled (Pillow's own conversion clips)."""
    from PIL import Image

    arr = np.asarray(img, dtype=np.float64)
    if not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))[0]
        raise MapFormatError(f"{source}: pixel (row {bad[0]}, column {bad[1]}) is {arr[tuple(bad)]}: "
                             "a float image's grey levels must be finite numbers")
    top = 65535.0 if img.mode.startswith("I;16") or arr.max(initial=0) > 255 else 255.0
    return Image.fromarray(np.clip(np.floor(arr * (255.0 / top) + 0.5), 0, 255).astype(np.uint8), "L")


# -- the two rules ------------------------------------------------------------------
def nav2_cell_values(gray: np.ndarray, alpha: Optional[np.ndarray], mode: str, negate: bool,
                     occupied_thresh: float, free_thresh: float) -> np.ndarray:
    """ROS OccupancyGrid values (int8) of 8-bit grey pixels as Nav2's map_io assigns them.

    trinary/scale: ``occ = 1 − g/255`` (``g/255`` with ``negate``) in single
    precision; ``occ >= occupied_thresh`` → 100, ``occ <= free_thresh`` → 0,
    else −1 (trinary) or ``round(100·(occ − free)/(occupied − free))``
    (scale); a pixel with alpha below 255 → −1. raw: the grey level itself
    when 0–100, else −1 (alpha and negate ignored).
    """
    g = np.arange(256, dtype=np.float32) / np.float32(255.0)
    if mode == "raw":
        lut = np.where(np.arange(256) <= OCCUPIED, np.arange(256), UNKNOWN)
        return lut.astype(np.int8)[gray]
    occ = g if negate else np.float32(1.0) - g
    o, f = np.float32(occupied_thresh), np.float32(free_thresh)
    lut = np.full(256, UNKNOWN, dtype=np.int64)
    lut[occ >= o] = OCCUPIED
    lut[occ <= f] = FREE
    if mode == "scale":
        between = (occ > f) & (occ < o)
        scaled = (occ[between] - f) / (o - f) * np.float32(100.0)
        lut[between] = np.floor(scaled + np.float32(0.5)).astype(np.int64)  # round half away from zero
    values = lut.astype(np.int8)[gray]
    if alpha is not None:
        values[alpha < 255] = UNKNOWN
    return values


def ros1_cell_values(colour_sum: np.ndarray, channels: int, alpha: Optional[np.ndarray], mode: str,
                     negate: bool, occupied_thresh: float, free_thresh: float) -> np.ndarray:
    """ROS OccupancyGrid values (int8) as ROS 1's map_server assigns them.

    The mean of the colour channels (in trinary mode the alpha byte is
    averaged in too, as ROS 1 does), ``255 − mean`` with ``negate``; raw:
    that mean truncated when 0–100, else −1. Otherwise ``occ = (255 −
    mean)/255``; ``occ > occupied_thresh`` → 100, ``occ < free_thresh`` →
    0, else −1 in trinary mode or for a fully transparent pixel, else
    ``int(99·(occ − free)/(occupied − free))`` (scale).
    """
    total, n = colour_sum.astype(np.int64), channels
    if alpha is not None and mode == "trinary":
        total, n = total + alpha, n + 1
    sums = np.arange(255 * n + 1)
    mean = sums / n
    if negate:
        mean = 255.0 - mean
    if mode == "raw":
        lut = np.where(mean <= OCCUPIED, np.trunc(mean), UNKNOWN).astype(np.int8)
        return lut[total]
    occ = (255.0 - mean) / 255.0
    lut = np.full(sums.size, UNKNOWN, dtype=np.int64)
    between = (occ <= occupied_thresh) & (occ >= free_thresh)
    if mode == "scale" and occupied_thresh > free_thresh:  # equal thresholds: ROS 1 divided 0 by 0; unknown here
        lut[between] = np.trunc(99.0 * (occ[between] - free_thresh) / (occupied_thresh - free_thresh))
    lut[occ > occupied_thresh] = OCCUPIED
    lut[occ < free_thresh] = FREE
    values = lut.astype(np.int8)[total]
    if mode == "scale" and alpha is not None:
        # only an in-between pixel becomes unknown when transparent
        values[(alpha == 0) & between[total]] = UNKNOWN
    return values


def grid_from_values(values: np.ndarray, resolution: float, origin, name: str, keep_probability: bool,
                     flip: bool = True) -> OccupancyGrid:
    """An OccupancyGrid from ROS cell values: 100 blocked, −1 unknown, and
    (``keep_probability``) 0–100 as probabilities in ``grid.probability``."""
    if flip:
        values = np.flipud(values)  # first image row is the top of the map
    probability = None
    if keep_probability:
        probability = np.where(values >= 0, values.astype(np.float32) / np.float32(100.0), np.float32(np.nan))
    return OccupancyGrid(values == OCCUPIED, resolution, origin, values < 0, name=name, probability=probability)


# -- YAML fields ---------------------------------------------------------------------
def _number(meta: Dict[str, Any], key: str, source: Path, default: Any = None) -> float:
    value = meta.get(key, default)
    if value is None:
        raise MapFormatError(f"{source}: field '{key}' is missing")
    value = number_text(value)  # a quoted '5e-2' too, as Nav2's yaml-cpp reads it
    try:
        return finite_number(f"field '{key}'", value)
    except ValueError as exc:
        raise MapFormatError(f"{source}: {exc}") from None


def _origin(meta: Dict[str, Any], source: Path) -> Tuple[float, float, float]:
    origin = meta.get("origin", [0.0, 0.0, 0.0])
    if not (isinstance(origin, list) and len(origin) == 3):
        raise MapFormatError(f"{source}: field 'origin' must be [x, y, yaw], got {shown(origin)}")
    out = []
    for label, v in zip(("x", "y", "yaw"), origin):
        v = number_text(v)
        try:
            ok = not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(float(v))
        except OverflowError:
            ok = False
        if not ok:
            raise MapFormatError(f"{source}: field 'origin' {label} must be a finite number, got {shown(v)}")
        if label != "yaw" and abs(float(v)) > MAX_COORDINATE:
            raise MapFormatError(f"{source}: field 'origin' {label} = {float(v):g} is out of range "
                                 f"(|{label}| <= {MAX_COORDINATE:g} m)")
        out.append(float(v))
    return out[0], out[1], out[2]


def _image_path(meta: Dict[str, Any], source: Path) -> Path:
    if "image" not in meta:
        raise MapFormatError(f"{source}: field 'image' is missing")
    name = meta["image"]
    if not isinstance(name, str) or not name.strip():
        raise MapFormatError(f"{source}: field 'image' must be a file name, got {shown(name)}")
    image = Path(name)
    image = image if image.is_absolute() else source.parent / image
    try:
        if image.is_dir():
            raise MapFormatError(f"{source}: field 'image' names a directory, not an image: {image}")
        if not image.exists():
            raise MapFormatError(f"{source}: field 'image': {image}: map image not found")
    except OSError as exc:  # (a name too long for the file system, say: named by the field, and cut to a line)
        raise MapFormatError(f"{source}: field 'image': {short_name(name)}: {exc.strerror or exc}") from None
    return image


def load_ros_map(yaml_path: PathLike, rule: str = "nav2") -> OccupancyGrid:
    """Read a ROS map_server map (YAML + PGM or PNG).

    Parameters
    ----------
    yaml_path : path
    rule : {"nav2", "ros1"}
        How pixels become cells: Nav2's map_io (ROS 2; inclusive thresholds,
        alpha < 255 unknown) or ROS 1's map_server (strict thresholds, see
        :func:`ros1_cell_values`).

    Raises
    ------
    MapFormatError
        Naming the file and the field for every malformed input, an image
        that is missing or a directory, and an image of more than
        :data:`~navlab.grid.occupancy.MAX_CELLS` pixels (refused from its
        header, before it is decoded).
    """
    if rule not in MAP_RULES:
        raise ParameterError(f"rule must be one of {', '.join(MAP_RULES)}, got {rule!r}")
    src = check_path("yaml_path", yaml_path)
    # a map YAML is a dozen fields: a megabyte is generous (a 200 MB one took 105 s to refuse)
    meta = read_yaml(src, MapFormatError, MAX_MAP_YAML_BYTES, what="map YAML file")
    if not isinstance(meta, dict):
        raise MapFormatError(f"{src}: expected a mapping of map fields")
    image = _image_path(meta, src)
    resolution = _number(meta, "resolution", src)
    if not MIN_LENGTH <= resolution <= MAX_COORDINATE:
        raise MapFormatError(f"{src}: field 'resolution' must be between {MIN_LENGTH:g} and {MAX_COORDINATE:g} "
                             f"m per cell, got {shown(meta['resolution'])}")
    origin = _origin(meta, src)
    occ_t = _number(meta, "occupied_thresh", src, 0.65)
    free_t = _number(meta, "free_thresh", src, 0.196)
    if not (0.0 <= free_t <= occ_t <= 1.0):
        raise MapFormatError(f"{src}: thresholds need 0 <= free_thresh ({free_t}) <= occupied_thresh ({occ_t}) <= 1")
    negate = meta.get("negate", 0)
    if negate not in (0, 1) or isinstance(negate, (float, bool)):  # (true read as 1 inverted the map)
        raise MapFormatError(f"{src}: field 'negate' must be 0 or 1, got {shown(negate)}")
    mode = meta.get("mode", "trinary")
    if mode not in MAP_MODES:
        raise MapFormatError(f"{src}: field 'mode' must be trinary, scale or raw, got {shown(mode)}")
    pixels = _read_image(image)
    if rule == "nav2":
        values = nav2_cell_values(pixels.gray, pixels.alpha, mode, bool(negate), occ_t, free_t)
    else:
        values = ros1_cell_values(pixels.colour_sum, pixels.channels, pixels.alpha, mode, bool(negate), occ_t, free_t)
    return grid_from_values(values, resolution, origin, src.stem, keep_probability=mode != "trinary")


# -- Moving AI ---------------------------------------------------------------------
def load_movingai_map(path: PathLike) -> OccupancyGrid:
    """Read a Moving AI ``.map``; ``blocked[y, x]`` uses the file's row order.

    Every row must have exactly ``width`` characters; ``width × height`` is
    checked against :data:`~navlab.grid.occupancy.MAX_CELLS` before the rows
    are read.
    """
    p = check_path("path", path)
    regular_file(p, str(p), MapFormatError, "Moving AI map")
    try:
        with open(p, "r", encoding="latin-1", newline=None) as f:
            header: Dict[str, str] = {}
            n = 0
            while True:
                line = f.readline(4096)
                n += 1
                if not line:
                    raise MapFormatError(f"{p}: no 'map' line after the header")
                if line.strip() == "map":
                    break
                parts = line.split()
                if len(parts) != 2 or n > 16:
                    raise MapFormatError(f"{p}: line {n}: bad header line {line.rstrip()!r}")
                header[parts[0]] = parts[1]
            if header.get("type") != "octile":
                raise MapFormatError(f"{p}: header 'type' must be octile, got {header.get('type')!r}")
            size = {}
            for key in ("height", "width"):
                text = header.get(key)
                if text is None or not text.isdigit() or int(text) < 1:
                    raise MapFormatError(f"{p}: header '{key}' must be a positive integer, got {text!r}")
                size[key] = int(text)
            height, width = size["height"], size["width"]
            _check_size(p, width, height)
            rows = f.read((width + 2) * (height + 1)).splitlines()
            extra = f.read(1)
    except OSError as exc:
        raise MapFormatError(f"{p}: cannot read: {exc.strerror or exc}") from None
    while rows and not rows[-1].strip():
        rows.pop()
    if len(rows) < height:
        raise MapFormatError(f"{p}: truncated: {len(rows)} of {height} map rows")
    if len(rows) > height or extra.strip():
        raise MapFormatError(f"{p}: more map rows than the header's height {height}")
    grid = np.zeros((height, width), dtype=bool)
    passable = np.frombuffer(b".GS", dtype=np.uint8)
    for y, row in enumerate(rows):
        if len(row) != width:
            raise MapFormatError(f"{p}: map row {y} has {len(row)} characters, the header's width is {width}")
        bad = set(row) - MOVINGAI_PASSABLE - MOVINGAI_BLOCKED
        if bad:
            raise MapFormatError(f"{p}: map row {y} has unknown terrain {sorted(bad)}")
        grid[y] = ~np.isin(np.frombuffer(row.encode("latin-1"), dtype=np.uint8), passable)
    return OccupancyGrid(grid, 1.0, (0.0, 0.0, 0.0), name=p.stem)


def load_map(path: PathLike, rule: str = "nav2") -> OccupancyGrid:
    """Read a map: ROS map_server YAML (``.yaml``/``.yml``) or Moving AI ``.map``.

    ``rule`` chooses how a map_server image is read (see :func:`load_ros_map`).
    """
    p = check_path("path", path)
    if p.is_dir():
        raise MapFormatError(f"{p}: is a directory, not a map file")
    if not p.exists():
        raise MapFormatError(f"{p}: no such file")
    if p.suffix.lower() in (".yaml", ".yml"):
        return load_ros_map(p, rule=rule)
    if p.suffix.lower() == ".map":
        return load_movingai_map(p)
    raise MapFormatError(f"{p}: unknown map format (expected a map_server .yaml or a Moving AI .map)")


def check_map_yaml_path(yaml_path: PathLike) -> Path:
    """``yaml_path`` as the Path of a map_server YAML that :func:`save_map` can write: a file name ending in
    .yaml or .yml; else a ParameterError saying what to give (the CLI asks before it builds a map)."""
    ypath = check_path("yaml_path", yaml_path)
    if ypath.name in ("", ".", ".."):  # '' is Path('.'): with_suffix's ValueError was an internal error
        raise ParameterError(f"{os.fspath(yaml_path)!r}: not a file name for the map's YAML (say maze.yaml)")
    if ypath.suffix.lower() not in (".yaml", ".yml"):
        # (maze.pgm: the YAML was written over its own image; maze.png or maze: a map load_map cannot read as
        # one; newcomer, session 30)
        raise ParameterError(f"{os.fspath(yaml_path)!r}: the map's YAML file name must end in .yaml or .yml (its "
                             f"image is written beside it as .pgm): say {ypath.with_suffix('.yaml').name}")
    return ypath


def save_map(grid: OccupancyGrid, yaml_path: PathLike) -> Path:
    """Write map_server YAML + binary PGM (trinary: 0 occupied, 254 free, 205
    unknown, as map_saver does); returns the image path.

    Both files are written to temporary names and renamed (:mod:`navlab.atomic`),
    so a full disk leaves no truncated file; the OSError names the file.
    Probabilities (``grid.probability``) are not written.
    """
    if not isinstance(grid, OccupancyGrid):
        raise ParameterError(f"grid: expected an OccupancyGrid, got {type(grid).__name__}")
    ypath = check_map_yaml_path(yaml_path)
    image = ypath.with_suffix(".pgm")
    pixels = np.full(grid.blocked.shape, 254, dtype=np.uint8)
    pixels[grid.unknown] = 205
    pixels[grid.blocked] = 0
    pixels = np.flipud(pixels)
    # the name on one line of printable text: a line break in it rewrote the header, and the map read back
    # was 4 x 4 with other cells blocked (API attack, session 29)
    header = f"P5\n# navlab {escaped(' '.join(str(grid.name).split()))}\n{grid.width} {grid.height}\n255\n"
    header = header.encode()
    meta = {
        "image": image.name,
        "mode": "trinary",
        "resolution": grid.resolution,
        "origin": [float(v) for v in grid.origin],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    for target, data in ((image, header + pixels.tobytes()), (ypath, yaml.safe_dump(meta, sort_keys=False).encode())):
        try:
            with atomic_path(target) as tmp:
                tmp.write_bytes(data)
        except OSError as exc:
            raise OSError(exc.errno, f"cannot write {target}: {exc.strerror or exc}") from None
    return image
