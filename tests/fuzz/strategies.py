"""Hypothesis strategies shared by the fuzz suite: values a file or a flag can hold.

Every strategy mixes sane values (so that most examples get past the first
check and exercise the algorithms) with the values that broke navlab before:
non-finite, huge and tiny numbers, wrong types, degenerate shapes.
"""

from __future__ import annotations

import math
import re
from typing import Any, Dict, List, Tuple

from hypothesis import settings
from hypothesis import strategies as st

#: [bytes] what one fuzzed call may allocate (tracemalloc peak; the largest legal
#: fuzz input is far smaller, so anything near this is a size check that failed)
MEMORY_BUDGET = 256 * 2**20


def examples(n: int) -> settings:
    """``n`` examples in the default (CI) profile, scaled with the loaded profile (``long``: ×10)."""
    scale = settings.default.max_examples / 40
    return settings(max_examples=max(1, int(n * scale)))


# --- numbers ---------------------------------------------------------------------------------

HUGE_INTS = st.integers(min_value=20, max_value=400).flatmap(
    lambda k: st.sampled_from([10 ** k, -(10 ** k), 10 ** k + 7, 2 ** 63, 2 ** 64 - 1, -(2 ** 63)]))
NON_FINITE = st.sampled_from([math.inf, -math.inf, math.nan])
EXTREME_FLOATS = st.sampled_from([1e308, -1e308, 1.7976931348623157e308, 1e154, -1e154, 1e30, 1e10,
                                  5e-324, -5e-324, 1e-300, 1e-12, 1e-10, -0.0, 0.0])
WRONG_TYPES = st.one_of(
    st.none(), st.booleans(), st.text(max_size=8), st.sampled_from(["abc", "1e5", "nan", "", "[1, 2]"]),
    st.just([]), st.lists(st.integers(-3, 3), min_size=1, max_size=3), st.just({"a": 1}),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2), st.just([[1, 2], [3]]))


def wild_numbers() -> st.SearchStrategy:
    """Numbers that are not what a coordinate should be."""
    return st.one_of(HUGE_INTS, NON_FINITE, EXTREME_FLOATS)


def wild_values() -> st.SearchStrategy:
    """Anything a YAML value can be that is not a sane coordinate."""
    return st.one_of(wild_numbers(), WRONG_TYPES)


def coordinate(lo: float, hi: float) -> st.SearchStrategy:
    return st.one_of(st.floats(lo, hi, allow_nan=False, allow_infinity=False), st.integers(int(lo), int(hi)))


# --- world documents -------------------------------------------------------------------------

@st.composite
def obstacle_docs(draw, size: float) -> Dict[str, Any]:
    kind = draw(st.sampled_from(["circle", "rectangle", "polygon"]))
    c = coordinate(0, size)
    if kind == "circle":
        return {"type": "circle", "center": [draw(c), draw(c)],
                "radius": draw(st.one_of(st.floats(0.01, size / 4), st.sampled_from([0, 1e-12, 1e-9])))}
    if kind == "rectangle":
        x0, y0 = draw(c), draw(c)
        return {"type": "rectangle", "min": [x0, y0],
                "max": [x0 + draw(st.floats(-0.5, size / 3)), y0 + draw(st.floats(-0.5, size / 3))]}
    n = draw(st.integers(0, 7))
    points = [[draw(c), draw(c)] for _ in range(n)]
    if n >= 3 and draw(st.booleans()):  # degenerate: collinear, repeated or spiky
        trick = draw(st.sampled_from(["collinear", "repeat", "sliver"]))
        if trick == "collinear":
            points = [[i, 2 * i] for i in range(n)]
        elif trick == "repeat":
            points[1] = list(points[0])
        else:
            points[2] = [points[0][0] + 1e-12, points[0][1] + 1e-12]
    return {"type": "polygon", "points": points}


@st.composite
def world_documents(draw) -> Dict[str, Any]:
    """A world document that is usually valid: a square of ``size`` metres with up to 6 obstacles."""
    size = draw(st.sampled_from([1.0, 10.0, 50.0, 1e6]))
    c = coordinate(0, size)
    doc: Dict[str, Any] = {"bounds": {"x": [0, size], "y": [0, size]},
                           "start": [draw(c), draw(c)], "goal": [draw(c), draw(c)]}
    if draw(st.booleans()):
        doc["robot_radius"] = draw(st.one_of(st.floats(0, size / 20), st.sampled_from([0, 1e-9, 1e-10])))
    if draw(st.booleans()):
        doc["goal_tolerance"] = draw(st.floats(0, size / 10))
    doc["obstacles"] = draw(st.lists(obstacle_docs(size), max_size=6))
    if draw(st.booleans()):
        doc["name"] = draw(st.text(max_size=10))
    return doc


def leaf_paths(doc: Any, prefix: str = "") -> List[Tuple[str, Tuple[Any, ...]]]:
    """Every value in a document: (the field name navlab's messages use, the key path)."""
    out: List[Tuple[str, Tuple[Any, ...]]] = []

    def walk(value, name, keys):
        if keys:
            out.append((name, keys))
        if isinstance(value, dict):
            for k, v in value.items():
                walk(v, f"{name}.{k}" if name else str(k), keys + (k,))
        elif isinstance(value, list):
            for i, v in enumerate(value):
                walk(v, f"{name}[{i}]", keys + (i,))

    walk(doc, prefix, ())
    return out


def set_path(doc: Any, keys: Tuple[Any, ...], value: Any) -> None:
    for k in keys[:-1]:
        doc = doc[k]
    doc[keys[-1]] = value


FIELD = re.compile(r"field '([^']*)'")


def field_in(message: str) -> str:
    """The field a WorldFormatError/MapFormatError message names ('' when none)."""
    m = FIELD.search(message)
    return m.group(1) if m else ""


def same_field(reported: str, mutated: str) -> bool:
    """Whether an error about ``reported`` is about the field that was changed.

    Equal, or one contains the other (``start`` for ``start[0]``), or both in
    the same obstacle (a rectangle's ``max`` is wrong once its ``min`` moved).
    """
    def within(inner, outer):
        return inner == outer or (inner.startswith(outer) and inner[len(outer)] in ".[")

    if reported and (within(reported, mutated) or within(mutated, reported)):
        return True
    obstacle = re.match(r"obstacles\[\d+\]", mutated)
    return bool(obstacle and reported.startswith(obstacle.group(0)))
