"""YAML 1.2's core schema for plain scalars: what navlab's YAML reading (:mod:`navlab.yamlio`) types
as a bool, an int, a float or null, and :func:`number_text` for fields that also take a quoted number.

Apart from :mod:`navlab.yamlio` so that a module checking numbers needs no PyYAML (a built-in scene
reads no file).
"""

from __future__ import annotations

import re
from typing import Any

#: YAML 1.2 core schema's plain scalars (https://yaml.org/spec/1.2.2/#1032-tag-resolution)
CORE = (("bool", r"true|True|TRUE|false|False|FALSE", "tTfF"),
        ("int", r"[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+", "-+0123456789"),
        ("float", r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)",
         "-+0123456789."),
        ("null", r"~|null|Null|NULL|", ["~", "n", "N", ""]))
#: the patterns above, compiled, by tag name
CORE_PATTERN = {name: re.compile(f"(?:{pattern})") for name, pattern, _ in CORE}


def core_float(text: str) -> float:
    """The float a YAML 1.2 core-schema number (:data:`CORE_PATTERN` ``float`` or decimal ``int``) spells:
    ``.inf``, ``-.Inf`` and ``.NaN`` as Python reads them."""
    return float(text.lower().replace(".inf", "inf").replace(".nan", "nan"))


def number_text(value: Any) -> Any:
    """``value``, or the number a string holds when it is written as YAML 1.2 writes a number (``'5e-2'``:
    the fields that took PyYAML's YAML 1.1 strings as numbers still take a quoted one, as yaml-cpp's
    ``as<double>()`` does in Nav2); other text (``'1_000'``, ``'infinity'``) stays text for the caller
    to refuse."""
    if isinstance(value, str):
        text = value.strip()
        if (CORE_PATTERN["int"].fullmatch(text) and text[:2] not in ("0o", "0x")) or \
                CORE_PATTERN["float"].fullmatch(text):
            return core_float(text)
    return value
