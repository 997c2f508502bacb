"""Reading YAML that navlab did not write: bounded in bytes, nodes and depth.

World files, map_server YAML and experiment files are read by one function,
:func:`read_yaml`, so every one of them gets the same limits:

- only a regular file is opened (a FIFO would block for ever, a device
  would never end), and at most ``max_bytes`` are read;
- aliases cannot multiply a small file: the document's size *as expanded*
  (each alias counted at every use) is computed on the composed node graph
  before anything is built, and refused past :data:`MAX_NODES` (a 918 KB file
  of aliased polygons expanded to 10.8 GB);
- a key given twice in one mapping is an error naming it and its line
  (``trials: 2`` then ``trials: 1000000`` silently kept the second);
- nesting too deep for the parser is an error, not a ``RecursionError``;
- plain scalars are typed by YAML 1.2's core schema, as Nav2's yaml-cpp and
  ROS 2 read them, not by PyYAML's YAML 1.1 rules: ``1e-3`` is a number,
  ``010`` is ten (not eight), and ``1:00``, ``0b11``, ``1_000``, ``yes``,
  ``off`` and ``2024-01-01`` are text (1.1 read them as 60, 3, 1000, true,
  false and a date).

:func:`load_value` reads one value (a ``--param`` value, a ROS parameter's
text) by the same rules. It imports nothing from navlab: callers pass the
error type to raise.
"""

from __future__ import annotations

import math
import os
import re
import stat
from pathlib import Path
from typing import Any, Dict, Optional, Type, Union

import numpy as np
import yaml

from .yamlcore import CORE, CORE_PATTERN, core_float
from .wording import with_article

#: most nodes a document may expand to (scalars, sequences and mappings, aliases counted at each use);
#: a 2 MiB file without aliases has fewer than this
MAX_NODES = 1_000_000
#: the largest integer read, in bits: about 4 300 decimal digits, Python's limit for writing one out
MAX_INT_BITS = 14_000
#: nesting beyond this is parsed by PyYAML's own parser: libyaml's recursion has no limit and crashes the
#: process (a segmentation fault) on ~100 000 nested "[" or "- ", where Python raises RecursionError
_C_PARSER_MAX_NESTING = 64


def _unique_mapping(loader, node) -> Dict[Any, Any]:
    """A mapping, refusing a key written twice in it (a key a merge (``<<``) brings
    in may still be overridden: that is what merging is for)."""
    written: Dict[Any, Any] = {}
    for key_node, _ in node.value:
        if key_node.tag == "tag:yaml.org,2002:merge":
            continue
        key = loader.construct_object(key_node, deep=True)
        try:
            hash(key)
        except TypeError:
            raise yaml.constructor.ConstructorError(None, None, "a mapping key must be plain text or a number",
                                                    key_node.start_mark) from None
        if key in written:
            first = written[key]
            if isinstance(first.value, str) and isinstance(key_node.value, str) and first.value != key_node.value:
                # written differently, equal as values (true and 1, 1 and 1.0): name both as written
                what = f"keys '{first.value}' and '{key_node.value}' are one key (equal values)"
            else:
                what = f"key '{key}' is given twice"
            raise yaml.constructor.ConstructorError(
                None, None, f"{what} (first on line {first.start_mark.line + 1}); keep one", key_node.start_mark)
        written[key] = key_node
    loader.flatten_mapping(node)
    return {loader.construct_object(k, deep=True): loader.construct_object(v, deep=True) for k, v in node.value}


_RETYPED = {f"tag:yaml.org,2002:{name}" for name in ("bool", "int", "float", "null", "timestamp")}


def _tagged_error(node, text: str, what: str) -> yaml.constructor.ConstructorError:
    return yaml.constructor.ConstructorError(None, None, f"{text[:40]!r} is not {what}", node.start_mark)


def _core_int(loader, node) -> int:
    """An int as YAML 1.2's core schema writes one (also under an explicit ``!!int`` tag, which
    YAML 1.1 let through as 0b1, 1_000 or 1:00)."""
    text = loader.construct_scalar(node)
    if not CORE_PATTERN["int"].fullmatch(text):
        raise _tagged_error(node, text, "an integer (YAML 1.2: digits, 0o octal or 0x hexadecimal)")
    try:
        value = int(text[2:], 8 if text[1] == "o" else 16) if text[:2] in ("0o", "0x") else int(text)
    except ValueError:  # Python's int() limit (4 300 decimal digits): no setting is that large
        value = None
    # hexadecimal and octal have no such limit, but str() of the value does: every message showing it would fail
    if value is None or value.bit_length() > MAX_INT_BITS:
        raise _tagged_error(node, text, f"an integer navlab reads ({len(text)} digits)")
    return value  # (decimal even with leading zeros: 010 is ten)


def _core_float(loader, node) -> float:
    text = loader.construct_scalar(node)
    if not (CORE_PATTERN["float"].fullmatch(text) or CORE_PATTERN["int"].fullmatch(text)):
        raise _tagged_error(node, text, "a number")
    if text[:2] in ("0o", "0x"):
        value = _core_int(loader, node)
        return float(value) if value.bit_length() <= 1024 else math.inf  # (past the largest float, as 1e999 reads)
    return core_float(text)  # (digits alone: float() reads them)


def _core_null(loader, node) -> None:
    text = loader.construct_scalar(node)
    if not CORE_PATTERN["null"].fullmatch(text):  # (!!null 5 read as None)
        raise _tagged_error(node, text, "null")
    return None


def _core_bool(loader, node) -> bool:
    text = loader.construct_scalar(node)
    if not CORE_PATTERN["bool"].fullmatch(text):
        raise _tagged_error(node, text, "true or false")
    return text.lower() == "true"


def _core_timestamp(loader, node):
    """A date under an explicit ``!!timestamp`` tag (plain dates are text in YAML 1.2), read by PyYAML;
    text that is no date is a YAML error (PyYAML raised AttributeError or ValueError: internal errors)."""
    try:
        return yaml.constructor.SafeConstructor.construct_yaml_timestamp(loader, node)
    except (AttributeError, ValueError, TypeError):
        raise _tagged_error(node, loader.construct_scalar(node), "a date") from None


def _loader_class(base: type) -> type:
    cls = type(f"Strict{base.__name__}", (base,), {})
    cls.add_constructor("tag:yaml.org,2002:map", _unique_mapping)
    # YAML 1.2's core schema in place of PyYAML's 1.1 resolvers for these tags (the others stay)
    cls.yaml_implicit_resolvers = {first: [(tag, rx) for tag, rx in rules if tag not in _RETYPED]
                                   for first, rules in base.yaml_implicit_resolvers.items()}
    for name, pattern, first in CORE:
        cls.add_implicit_resolver(f"tag:yaml.org,2002:{name}", re.compile(f"^(?:{pattern})$"), list(first))
    for name, construct in (("int", _core_int), ("float", _core_float), ("bool", _core_bool), ("null", _core_null),
                            ("timestamp", _core_timestamp)):
        cls.add_constructor(f"tag:yaml.org,2002:{name}", construct)
    return cls


_LOADERS = {base: _loader_class(base) for base in
            (yaml.SafeLoader,) + ((yaml.CSafeLoader,) if hasattr(yaml, "CSafeLoader") else ())}


def expanded_size(node) -> int:
    """Nodes the document has once every alias is expanded, computed without expanding:
    each distinct node's size once, in one depth-first pass over an explicit stack (no
    recursion limit). A node that contains itself (``&a [*a]``) expands without end."""
    size: Dict[int, int] = {}
    entered = set()
    stack = [(node, False)]
    while stack:
        current, done = stack.pop()
        key = id(current)
        if isinstance(current, yaml.ScalarNode):
            size[key] = 1
            continue
        children = [c for pair in current.value for c in pair] if isinstance(current, yaml.MappingNode) \
            else current.value
        if done:
            missing = [c for c in children if id(c) not in size]
            if missing:  # a child still open: it is an ancestor, so the document refers to itself
                raise yaml.YAMLError("an alias refers to a node that contains it: the document never ends")
            size[key] = 1 + sum(size[id(c)] for c in children)
        elif key not in entered:
            entered.add(key)
            stack.append((current, True))
            stack.extend((c, False) for c in children if id(c) not in size and id(c) not in entered)
        elif key not in size:
            raise yaml.YAMLError("an alias refers to a node that contains it: the document never ends")
    return size[id(node)]


def _nesting(raw: bytes, text: str) -> int:
    """An upper estimate of the document's nesting (flow brackets, block dashes on one line)."""
    b = np.frombuffer(raw, dtype=np.uint8)
    step = (b == ord("[")).astype(np.int64) + (b == ord("{")) - (b == ord("]")) - (b == ord("}"))
    flow = int(np.cumsum(step).max(initial=0))
    block = max((line.count("- ") + line.count("? ") for line in text.splitlines()), default=0)
    return max(flow, block)


def parse_yaml(raw: bytes, where: str, error: Type[Exception], what: str = "file",
               max_nodes: int = MAX_NODES) -> Any:
    """The YAML document in ``raw`` (UTF-8), with the limits above; ``error(message)`` otherwise."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{where}: not a UTF-8 text file (byte {exc.start}); a {what} is YAML text") from None
    base = yaml.CSafeLoader if hasattr(yaml, "CSafeLoader") and _nesting(raw, text) <= _C_PARSER_MAX_NESTING \
        else yaml.SafeLoader

    def too_many(size: int) -> Exception:
        return error(f"{where}: expands to {size:,} YAML nodes (aliases counted at each use), more than the "
                     f"{max_nodes:,} a {what} may have")

    try:
        return _bounded(_LOADERS[base](text), max_nodes, too_many)
    except yaml.YAMLError as exc:
        raise error(f"{where}: not valid YAML: {_one_line(exc)}") from None
    except RecursionError:
        raise error(f"{where}: nested too deeply to be a {what}") from None


def load_value(text: str, max_nodes: int = MAX_NODES) -> Any:
    """One YAML value from ``text``, read as :func:`parse_yaml` reads a file.

    Parameters
    ----------
    text : str
        A ``--param`` value or a ROS parameter's text (``"{goal: 0.1}"``, ``"[[0, 0], [1, 0]]"``).
    max_nodes : int
        The most nodes the value may expand to, aliases counted at each use.

    Returns
    -------
    Any
        The value, plain scalars typed by YAML 1.2's core schema (:mod:`navlab.yamlcore`), each mapping
        key given once.

    Raises
    ------
    yaml.YAMLError
        Not YAML, a key given twice, a tagged scalar that is not its type, an integer too long to read,
        or more than ``max_nodes`` nodes.
    RecursionError
        Nesting too deep for the parser.
    """
    return _bounded(_LOADERS[yaml.SafeLoader](text), max_nodes, lambda size: yaml.YAMLError(
        f"expands to {size:,} YAML nodes (aliases counted at each use), more than {max_nodes:,}"))


def _bounded(loader, max_nodes: int, too_many) -> Any:
    """The loader's one document, built only if it expands to at most ``max_nodes`` nodes
    (:func:`expanded_size`; else ``too_many(size)`` is raised)."""
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        size = expanded_size(node)
        if size > max_nodes:
            raise too_many(size)
        return loader.construct_document(node)
    finally:
        loader.dispose()


def regular_file(path: Union[str, os.PathLike], where: str, error: Type[Exception], what: str = "file") -> int:
    """The size of ``path`` if it is a regular file; ``error(message)`` for a
    missing path, a folder, or a FIFO, device or socket (which would block or never end)."""
    try:
        info = os.stat(path)
    except OSError as exc:
        raise error(f"{where}: cannot read: {exc.strerror or exc}") from None
    if stat.S_ISDIR(info.st_mode):
        raise error(f"{where}: cannot read: is a folder, not {with_article(what)}")  # ("not a experiment file")
    if not stat.S_ISREG(info.st_mode):
        raise error(f"{where}: not a regular file (a FIFO, device or socket); {with_article(what)} must be a file")
    return info.st_size


def read_bounded(path: Union[str, os.PathLike], where: str, error: Type[Exception], max_bytes: int,
                 what: str = "file") -> bytes:
    """At most ``max_bytes`` of a regular file; ``error(message)`` for anything
    else (missing, a folder, a FIFO or device, unreadable, too large)."""
    p = Path(path)
    size = regular_file(p, where, error, what)
    if size > max_bytes:
        raise error(f"{where}: larger than {_size(max_bytes)}, the limit for a {what} ({size:,} bytes)")
    try:
        with open(p, "rb") as f:
            raw = f.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"{where}: cannot read: {exc.strerror or exc}") from None
    if len(raw) > max_bytes:  # it grew while we looked
        raise error(f"{where}: larger than {_size(max_bytes)}, the limit for a {what}")
    return raw


def read_yaml(path: Union[str, os.PathLike], error: Type[Exception], max_bytes: int, what: str = "file",
              where: Optional[str] = None, max_nodes: int = MAX_NODES) -> Any:
    """:func:`read_bounded`, then :func:`parse_yaml`."""
    where = str(path) if where is None else where
    return parse_yaml(read_bounded(path, where, error, max_bytes, what), where, error, what, max_nodes)


def _size(n: int) -> str:
    return f"{n // 2**20} MiB" if n >= 2**20 and n % 2**20 == 0 else f"{n:,} bytes"


def _one_line(exc: Exception) -> str:
    """A YAML error as one line: what is wrong and where (line, column)."""
    mark = getattr(exc, "problem_mark", None)
    problem = getattr(exc, "problem", None)
    if problem and mark is not None:
        context = getattr(exc, "context", None)
        return " ".join(f"{context + ': ' if context else ''}{problem} (line {mark.line + 1}, column "
                        f"{mark.column + 1})".split())[:300]
    return " ".join(str(exc).split())[:300]


__all__ = ["MAX_NODES", "expanded_size", "load_value", "parse_yaml", "read_bounded", "read_yaml", "regular_file"]
