"""Map files: ROS map_server YAML + PGM/PNG, and Moving AI ``.map``.

ROS map_server semantics (nav2_map_server): for each pixel, with ``v`` its
value (averaged over colour channels) scaled to [0, 1], occupancy
``p = 1 − v`` (or ``v`` with ``negate: 1``); ``p > occupied_thresh`` is
occupied, ``p < free_thresh`` free, anything between unknown (``trinary``).
``scale`` keeps the in-between values as probabilities (unknown only for
transparent pixels); ``raw`` takes pixel values as occupancy 0–100 directly
(255 unknown). The image's first row is the top of the map, so row 0 of
``blocked`` is the image's last row (at ``origin``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Dict, Union

import numpy as np
import yaml

from .occupancy import OccupancyGrid

PathLike = Union[str, os.PathLike]


class MapFormatError(ValueError):
    """A map file is malformed; the message names the file and the problem."""


MOVINGAI_PASSABLE = set(".GS")
MOVINGAI_BLOCKED = set("@OTW")


def read_pgm(path: PathLike) -> np.ndarray:
    """Read a binary (P5) or plain (P2) PGM into a 2D array (first row = top)."""
    p = Path(path)
    data = p.read_bytes()
    magic = data[:2]
    if magic not in (b"P5", b"P2"):
        raise MapFormatError(f"{p}: not a PGM file (magic {magic!r}, expected P5 or P2)")
    # Header: magic, width, height, maxval, separated by whitespace and comments.
    tokens, pos = [], 2
    while len(tokens) < 3:
        while pos < len(data) and chr(data[pos]).isspace():
            pos += 1
        if pos < len(data) and data[pos:pos + 1] == b"#":
            while pos < len(data) and data[pos:pos + 1] not in (b"\n", b"\r"):
                pos += 1
            continue
        start = pos
        while pos < len(data) and not chr(data[pos]).isspace():
            pos += 1
        if start == pos:
            raise MapFormatError(f"{p}: truncated PGM header")
        tokens.append(data[start:pos])
    try:
        width, height, maxval = (int(t) for t in tokens)
    except ValueError:
        raise MapFormatError(f"{p}: bad PGM header values {tokens}") from None
    if width <= 0 or height <= 0 or not 0 < maxval < 65536:
        raise MapFormatError(f"{p}: bad PGM size {width}x{height} or maxval {maxval}")
    pos += 1  # the single whitespace after maxval
    count = width * height
    if magic == b"P5":
        dtype = np.uint8 if maxval < 256 else np.dtype(">u2")
        raw = np.frombuffer(data, dtype=dtype, count=min(count, (len(data) - pos) // np.dtype(dtype).itemsize), offset=pos)
    else:
        raw = np.array(data[pos:].split(), dtype=np.int64) if len(data) > pos else np.empty(0, dtype=np.int64)
    if raw.size < count:
        raise MapFormatError(f"{p}: truncated PGM data: {raw.size} of {count} pixels ({width}x{height})")
    return raw[:count].reshape(height, width).astype(np.float64) / maxval * 255.0


def _read_image(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Pixel values in [0, 255] (colour averaged) and an alpha mask (True = opaque)."""
    if not path.exists():
        raise MapFormatError(f"{path}: map image not found")
    if path.suffix.lower() == ".pgm":
        values = read_pgm(path)
        return values, np.ones(values.shape, dtype=bool)
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as img:
            img.load()
            arr = np.asarray(img.convert("RGBA" if "A" in img.getbands() else "RGB"), dtype=np.float64)
    except (UnidentifiedImageError, OSError) as exc:
        raise MapFormatError(f"{path}: cannot read image: {exc}") from None
    opaque = arr[..., 3] > 0 if arr.shape[-1] == 4 else np.ones(arr.shape[:2], dtype=bool)
    return arr[..., :3].mean(axis=-1), opaque


def _number(meta: Dict[str, Any], key: str, source: Path, default: Any = None) -> float:
    value = meta.get(key, default)
    if value is None:
        raise MapFormatError(f"{source}: field '{key}' is missing")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise MapFormatError(f"{source}: field '{key}' must be a number, got {value!r}")
    return float(value)


def load_ros_map(yaml_path: PathLike) -> OccupancyGrid:
    """Read a ROS map_server map (YAML + PGM or PNG)."""
    src = Path(yaml_path)
    try:
        meta = yaml.safe_load(src.read_text())
    except OSError as exc:
        raise MapFormatError(f"{src}: cannot read: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise MapFormatError(f"{src}: not valid YAML: {exc}") from None
    if not isinstance(meta, dict):
        raise MapFormatError(f"{src}: expected a mapping of map fields")
    if "image" not in meta:
        raise MapFormatError(f"{src}: field 'image' is missing")
    resolution = _number(meta, "resolution", src)
    if resolution <= 0:
        raise MapFormatError(f"{src}: field 'resolution' must be positive, got {resolution}")
    origin = meta.get("origin", [0.0, 0.0, 0.0])
    if not (isinstance(origin, list) and len(origin) == 3 and all(isinstance(v, (int, float)) for v in origin)):
        raise MapFormatError(f"{src}: field 'origin' must be [x, y, yaw], got {origin!r}")
    occ_t = _number(meta, "occupied_thresh", src, 0.65)
    free_t = _number(meta, "free_thresh", src, 0.196)
    if not (0.0 <= free_t <= occ_t <= 1.0):
        raise MapFormatError(f"{src}: thresholds need 0 <= free_thresh ({free_t}) <= occupied_thresh ({occ_t}) <= 1")
    negate = meta.get("negate", 0)
    if negate not in (0, 1, True, False):
        raise MapFormatError(f"{src}: field 'negate' must be 0 or 1, got {negate!r}")
    mode = meta.get("mode", "trinary")
    if mode not in ("trinary", "scale", "raw"):
        raise MapFormatError(f"{src}: field 'mode' must be trinary, scale or raw, got {mode!r}")
    image = Path(str(meta["image"]))
    image = image if image.is_absolute() else src.parent / image
    values, opaque = _read_image(image)
    values = np.flipud(values)  # first image row is the top of the map
    opaque = np.flipud(opaque)
    if mode == "raw":
        blocked = values >= 100 * occ_t
        unknown = (values >= 255) | ~opaque
        blocked &= ~unknown
    else:
        occ = values / 255.0 if negate else (255.0 - values) / 255.0
        blocked = occ > occ_t
        free = occ < free_t
        unknown = ~blocked & ~free if mode == "trinary" else ~opaque
        if mode == "scale":
            blocked &= opaque
    return OccupancyGrid(blocked, resolution, tuple(float(v) for v in origin), unknown, name=src.stem)


def load_movingai_map(path: PathLike) -> OccupancyGrid:
    """Read a Moving AI ``.map``; ``blocked[y, x]`` uses the file's row order."""
    p = Path(path)
    try:
        lines = p.read_text().splitlines()
    except OSError as exc:
        raise MapFormatError(f"{p}: cannot read: {exc.strerror}") from None
    header: Dict[str, str] = {}
    i = 0
    while i < len(lines) and lines[i].strip() != "map":
        parts = lines[i].split()
        if len(parts) != 2:
            raise MapFormatError(f"{p}: line {i + 1}: bad header line {lines[i]!r}")
        header[parts[0]] = parts[1]
        i += 1
    if i == len(lines):
        raise MapFormatError(f"{p}: no 'map' line after the header")
    if header.get("type") != "octile":
        raise MapFormatError(f"{p}: header 'type' must be octile, got {header.get('type')!r}")
    try:
        height, width = int(header["height"]), int(header["width"])
    except (KeyError, ValueError):
        raise MapFormatError(f"{p}: header needs integer 'height' and 'width'") from None
    rows = lines[i + 1: i + 1 + height]
    if len(rows) < height:
        raise MapFormatError(f"{p}: truncated: {len(rows)} of {height} map rows")
    grid = np.zeros((height, width), dtype=bool)
    for y, row in enumerate(rows):
        if len(row) < width:
            raise MapFormatError(f"{p}: map row {y} has {len(row)} of {width} characters")
        chars = np.frombuffer(row[:width].encode("latin-1"), dtype=np.uint8)
        bad = set(row[:width]) - MOVINGAI_PASSABLE - MOVINGAI_BLOCKED
        if bad:
            raise MapFormatError(f"{p}: map row {y} has unknown terrain {sorted(bad)}")
        grid[y] = ~np.isin(chars, np.frombuffer(b".GS", dtype=np.uint8))
    return OccupancyGrid(grid, 1.0, (0.0, 0.0, 0.0), name=p.stem)


def load_map(path: PathLike) -> OccupancyGrid:
    """Read a map: ROS map_server YAML (``.yaml``/``.yml``) or Moving AI ``.map``."""
    p = Path(path)
    if not p.exists():
        raise MapFormatError(f"{p}: no such file")
    if p.suffix.lower() in (".yaml", ".yml"):
        return load_ros_map(p)
    if p.suffix.lower() == ".map":
        return load_movingai_map(p)
    raise MapFormatError(f"{p}: unknown map format (expected a map_server .yaml or a Moving AI .map)")


def save_map(grid: OccupancyGrid, yaml_path: PathLike) -> Path:
    """Write map_server YAML + binary PGM (trinary: 0 occupied, 254 free, 205
    unknown, as map_saver does); returns the image path."""
    ypath = Path(yaml_path)
    image = ypath.with_suffix(".pgm")
    pixels = np.full(grid.blocked.shape, 254, dtype=np.uint8)
    pixels[grid.unknown] = 205
    pixels[grid.blocked] = 0
    pixels = np.flipud(pixels)
    header = f"P5\n# navlab {grid.name}\n{grid.width} {grid.height}\n255\n".encode()
    image.write_bytes(header + pixels.tobytes())
    meta = {
        "image": image.name,
        "mode": "trinary",
        "resolution": grid.resolution,
        "origin": [float(v) for v in grid.origin],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    ypath.write_text(yaml.safe_dump(meta, sort_keys=False))
    return image
