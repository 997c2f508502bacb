"""Maps as benchmark worlds: a map with a list of start/goal queries.

An experiment's ``worlds`` may hold, beside scene names and world files, a
mapping naming a map and its queries::

    worlds:
      - {map: arena.map, scen: arena.map.scen, queries: 5}     # 5 rows of a Moving AI scenario file
      - {map: maze.yaml, queries: [[0.3, 0.3, 4.8, 4.8]]}      # start x, y and goal x, y in metres
      - {map: office.yaml, name: office, robot_radius: 0.2, queries: [[1, 1, 20, 14], [2, 9, 30, 3]]}

Trial *i* of a cell on such a world plans query ``i mod len(queries)``, so
with ``trials`` equal to the number of queries every planner solves each
query once (a tree planner with that trial's seed). From a scenario file,
``queries: N`` takes N rows spread evenly over the file (Moving AI files run
from short to long queries), with the stored optimum (8-connected octile
length, corners not cut) kept beside each, so reports can give path length
against the optimum. A cell of a Moving AI map is 1 m: scenario cell (x, y)
is the point (x + 0.5, y + 0.5).
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any, Dict, List, Optional

import numpy as np

from ..limits import check_coordinate, check_length
from .errors import ExperimentError

MAP_FIELDS = ("map", "scen", "queries", "name", "robot_radius")


def is_map_entry(entry: Any) -> bool:
    return isinstance(entry, dict)


def map_entry(entry: Dict[str, Any], folder: Optional[Path] = None) -> Dict[str, Any]:
    """A checked map world: ``{name, map, robot_radius, queries: [{index,
    start, goal, optimum}]}`` (paths made relative to ``folder`` when given)."""
    for key in entry:
        if key not in MAP_FIELDS:
            from ..registry import suggest

            raise ExperimentError(f"unknown field '{key}' in a map world; valid: {', '.join(MAP_FIELDS)}."
                                  + suggest(str(key), list(MAP_FIELDS)))
    if "map" not in entry:
        raise ExperimentError(f"a world given as a mapping needs 'map' (a map_server YAML or Moving AI .map), "
                              f"got {entry!r}")
    path = _beside(entry["map"], folder)
    grid = load_grid(path)
    queries = entry.get("queries")
    if "scen" in entry:
        count = queries if queries is not None else 10
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise ExperimentError(f"{path}: with 'scen', 'queries' is how many scenario rows to use (a positive "
                                  f"integer), got {queries!r}")
        chosen = scen_queries(_beside(entry["scen"], folder), grid, count)
    else:
        if not isinstance(queries, list) or not queries:
            raise ExperimentError(f"{path}: a map has no start or goal: give 'scen' (a Moving AI scenario file) "
                                  "or 'queries' as a list of [start x, start y, goal x, goal y] in metres")
        chosen = []
        for k, q in enumerate(queries):
            if not isinstance(q, (list, tuple)) or len(q) != 4:
                raise ExperimentError(f"{path}: query {k} must be [start x, start y, goal x, goal y] in metres, "
                                      f"got {q!r}")
            try:
                q = [check_coordinate(f"query {k} {axis}", v)
                     for axis, v in zip(("start x", "start y", "goal x", "goal y"), q)]
            except ValueError as exc:
                raise ExperimentError(f"{path}: {exc}") from None
            chosen.append({"index": k, "start": q[:2], "goal": q[2:], "optimum": None})
    out = {"name": str(entry.get("name") or Path(path).stem), "map": str(path), "queries": chosen}
    if entry.get("robot_radius") is not None:
        try:
            out["robot_radius"] = check_length("robot_radius", entry["robot_radius"])
        except ValueError as exc:
            raise ExperimentError(f"{path}: {exc}") from None
    return out


def _beside(path: Any, folder: Optional[Path]) -> str:
    p = Path(str(path))
    return str(p if p.is_absolute() or folder is None else folder / p)


@functools.lru_cache(maxsize=16)
def load_grid(path: str):
    """The map at ``path`` (read once per process)."""
    from ..grid.mapio import load_map

    if not Path(path).is_file():
        raise ExperimentError(f"{path}: no such map file")
    return load_map(path)


def scen_queries(scen: str, grid, count: int) -> List[Dict[str, Any]]:
    """``count`` rows spread evenly over a Moving AI scenario file, as queries
    in metres with their stored optimum."""
    from ..grid.scen import read_scen

    if not Path(scen).is_file():
        raise ExperimentError(f"{scen}: no such scenario file")
    rows = read_scen(scen)
    if not rows:
        raise ExperimentError(f"{scen}: no scenarios")
    if (rows[0].width, rows[0].height) != (grid.width, grid.height):
        raise ExperimentError(f"{scen}: its scenarios are for a {rows[0].width}x{rows[0].height} map, "
                              f"the map is {grid.width}x{grid.height}")
    picks = np.unique(np.linspace(0, len(rows) - 1, min(count, len(rows))).round().astype(int))
    out = []
    for k in picks:
        sc = rows[int(k)]
        for label, (x, y) in (("start", sc.start), ("goal", sc.goal)):
            if not (0 <= x < grid.width and 0 <= y < grid.height):  # (a 400-digit cell was an internal error)
                shown = f"({x}, {y})" if max(abs(x), abs(y)) < 10 ** 20 else "with a coordinate of over 20 digits"
                raise ExperimentError(f"{scen}: scenario {int(k) + 1}'s {label} cell {shown} is outside the "
                                      f"{grid.width}x{grid.height} map")
        ends = grid.cell_to_world(np.array([sc.start, sc.goal]))
        out.append({"index": int(k), "start": ends[0].tolist(), "goal": ends[1].tolist(),
                    "optimum": sc.optimal * grid.resolution})
    return out


def map_world(entry: Dict[str, Any], query: Dict[str, Any]):
    """The World of one query on a map world."""
    from ..world import World

    return World.from_grid(load_grid(entry["map"]), tuple(query["start"]), tuple(query["goal"]),
                           robot_radius=entry.get("robot_radius", 0.0), name=entry["name"])
