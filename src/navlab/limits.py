"""The numeric range navlab supports, in one place.

Geometry kernels square coordinates; near 1e154 those squares overflow and a
segment can pass straight through a circle. navlab therefore accepts only
finite coordinates and lengths within :data:`MAX_COORDINATE` metres (far
beyond any robot's workspace, and small enough that every squared distance
and every sum of them stays exact enough in float64), and positive lengths
(radii, resolutions, tolerances) of at least :data:`MIN_LENGTH`. Input is
checked against these at the boundary (world and map files, the CLI, the
``World`` constructor); kernels may rely on them.
"""

from __future__ import annotations

import datetime
import math
import numbers
import os
from typing import Any, Optional

import numpy as np
from .errors import ParameterError
from .wording import escaped

MAX_COORDINATE = 1.0e7  #: [m] largest |x| or |y| of any point, and largest length
MIN_LENGTH = 1.0e-9  #: [m] smallest positive length (radius, resolution, tolerance)


def finite_number(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite real number (Python or numpy;
    not a bool, not a string), else ParameterError naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        if isinstance(value, str) and _reads_as_non_finite(value):  # (--param expand_dis=inf: YAML keeps 'inf'
            # text, and "must be a number" read as if infinity were none: newcomer, session 31)
            raise ParameterError(f"{name} must be finite, got {shown(value)}")
        raise ParameterError(f"{name} must be a number, got {shown(value)}")
    try:
        v = float(value)
    except OverflowError:  # (the value's own bound, if any, is its caller's to say)
        raise ParameterError(f"{name} must be a finite number, got {shown(value)}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite, got {shown(value)}")
    return v


def _reads_as_non_finite(text: str) -> bool:
    try:
        return not math.isfinite(float(text))
    except ValueError:
        return False


#: the largest heuristic weight (A*'s and Hybrid A*'s ``weight``): past it a search orders nodes by the
#: heuristic alone already (greedy best-first), and at 1e306 weight × heuristic overflowed to inf, which
#: ordered nothing (a Berlin query cost 665.6 against 394.5 at 1e305: final newcomer run, session 19)
MAX_WEIGHT = 1e6


def too_heavy(weight: Any) -> str:
    """The message for a weight past :data:`MAX_WEIGHT`."""
    return (f"weight must be at most {MAX_WEIGHT:g} (beyond it A* is greedy best-first already), "
            f"got {shown(weight)}")


def check_weight(weight: Any) -> float:
    """A heuristic's ``weight`` (weighted A*: keys g + weight·h) as a float in [1, :data:`MAX_WEIGHT`]: any
    real number (numpy's, a Fraction), not a bool; else ParameterError naming it."""
    try:
        as_float = float(weight) if isinstance(weight, numbers.Real) else math.nan
    except OverflowError:  # an int past float's range (10**400)
        as_float = math.inf
    if isinstance(weight, (bool, np.bool_)) or not as_float >= 1 or not math.isfinite(as_float):
        raise ParameterError(f"weight must be a finite number >= 1, got {shown(weight)}")
    if as_float > MAX_WEIGHT:
        raise ParameterError(too_heavy(weight))
    return as_float


#: the longest value a message shows (:func:`shown`)
SHOWN_LENGTH = 80


def plain_values(value: Any) -> Any:
    """``value`` with numpy's scalars as Python's (``np.True_``, ``np.int64(4)``), also inside lists, tuples (as
    plain tuples: a namedtuple's class takes no sequence) and mappings; anything else unchanged."""
    if isinstance(value, dict):
        return {plain_values(k): plain_values(v) for k, v in value.items()}
    if isinstance(value, list):
        return [plain_values(v) for v in value]
    if isinstance(value, tuple):
        return tuple(plain_values(v) for v in value)
    return value.item() if isinstance(value, np.generic) else value


def check_flag(name: str, value: Any) -> bool:
    """``value`` as a Python bool if it is one (or numpy's), else ParameterError naming ``name``: a string
    or a number is refused, since ``bool("false")`` and ``bool(2)`` are true and a typo must not switch a
    setting on."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be true or false, got {shown(value)}")
    return bool(value)


def is_finite_real(value: Any) -> bool:
    """Whether ``value`` is a finite real number (Python or numpy, not a bool) that fits a float:
    ``math.isfinite`` raises OverflowError on an int past float's range (10**400), which
    reached the command as an internal error from four settings' checks."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def shown(value: Any, limit: int = SHOWN_LENGTH) -> str:
    """``repr(value)`` for a message, on one line and at most ``limit`` characters (cut with "..."); an
    integer too long to read, alone or in a list or tuple, as its number of digits."""
    if isinstance(value, (list, tuple)):
        items = [_one_value(v) for v in value[:limit]]  # (no deeper: the first level is what messages show)
        inner = ", ".join(items) + ("," if isinstance(value, tuple) and len(value) == 1 else "")
        text = f"[{inner}]" if isinstance(value, list) else f"({inner})"
    else:
        text = _one_value(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def short_name(name: str, limit: int = 300) -> str:
    """A file name for a one-line message: control characters escaped (``\\n``: a name holding newlines
    printed 74 lines), and its start and end only when longer than ``limit`` characters (a 100 000-character
    name, too long for the file system, filled 100 KB of one line; attacks, sessions 20 and 21)."""
    size = len(name)
    name = escaped(name)  # first: the cut keeps the limit
    if len(name) <= limit:
        return name
    return f"{name[:limit // 2]}...{name[-limit // 4:]} (a name of {size} characters)"


def digit_count(value: int) -> int:
    """The decimal digits of ``value``, without writing it out (``str()`` refuses past 4 300 digits: an
    internal ValueError where a message meant to say how long the number was; review, session 20)."""
    n = abs(int(value))
    digits = max(1, int(n.bit_length() * 0.30102999566398120) + 1)  # log10(2): exact or one too many
    return digits - 1 if digits > 1 and 10 ** (digits - 1) > n else digits


def value_text(value: datetime.date) -> str:
    """A date (or date and time) in YAML's own spelling, ``2001-12-14 21:59:43.1-05:00``."""
    if not isinstance(value, datetime.datetime):
        return value.isoformat()
    text = value.isoformat(sep=" ")
    if value.microsecond:  # (isoformat pads to six digits: .100000 where .1 was written)
        head, _, rest = text.partition(".")
        digits = rest[:6].rstrip("0")
        text = f"{head}.{digits}{rest[6:]}"
    return text


def _one_value(value: Any) -> str:
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool) and abs(int(value)) >= 10 ** 20:
        return f"an integer of {digit_count(value)} digits"
    if isinstance(value, datetime.date):  # (a !!timestamp in a file): as written, not datetime.date(2001, 1, 1)
        return f"{value_text(value)} ({'a date and time' if isinstance(value, datetime.datetime) else 'a date'})"
    try:
        return " ".join(repr(value).split())  # a numpy array's repr spans lines
    except RecursionError:  # a list nested thousands deep
        return f"a {type(value).__name__} nested too deeply to show"


def check_coordinate(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite number within ±MAX_COORDINATE [m], else ParameterError
    naming ``name`` (headings are not coordinates: any finite one is taken and wrapped,
    :func:`navlab.angles.planned_heading`)."""
    v = finite_number(name, value)
    if abs(v) > MAX_COORDINATE:
        # (ten digits: "1e+07 is out of range (≤ 1e+07)" hid a 10000000.4 just past the bound)
        raise ParameterError(f"{name} = {v:.10g} is out of range (|{name}| ≤ {MAX_COORDINATE:g} m)")
    return v


def check_length(name: str, value: Any, allow_zero: bool = True) -> float:
    """A non-negative (or positive) length within [MIN_LENGTH, MAX_COORDINATE], else ParameterError naming ``name``."""
    v = check_coordinate(name, value)
    if v < 0 or (v == 0 and not allow_zero):
        raise ParameterError(f"{name} must be {'non-negative' if allow_zero else 'positive'}, got {value!r}")
    if 0 < v < MIN_LENGTH:
        raise ParameterError(f"{name} = {v:g} is below the smallest supported length {MIN_LENGTH:g} m")
    return v


#: the largest count (iterations, expansions) navlab's compiled loops take: they count in int64
MAX_COUNT = 2 ** 62

#: the most worker processes a benchmark run takes (``navlab bench --jobs``, ``run_experiment(jobs=)``)
MAX_JOBS = 256


def float_array(value: Any) -> np.ndarray:
    """``value`` as a float array, or an empty one when it is not numbers (text, None, an object): for the
    callers' own shape check to refuse with a message naming the field, instead of numpy's "could not
    convert string to float" (or "int too large to convert to float" for a whole number such as 10**400)."""
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return np.empty(0)


def check_path(name: str, value: Any):
    """``value`` as a :class:`pathlib.Path`: a file name given as text or a path object, without NUL;
    else a ParameterError naming ``name`` (``load_map(None)`` raised Python's own TypeError: API attack,
    session 29)."""
    from pathlib import Path

    if not isinstance(value, (str, os.PathLike)) or "\0" in os.fspath(value):
        raise ParameterError(f"{name}: expected a file name (text without NUL), got {shown(value)}")
    return Path(value)


def check_count(name: str, value: Any, low: int = 1, high: Optional[float] = MAX_COUNT) -> int:
    """``value`` as an int if it is a whole number in [low, high] (``high`` None: no upper bound), else
    ParameterError naming ``name``. A float that is a whole number counts (``1e6`` from a command line or a
    YAML file); bools, strings and fractions do not."""
    if isinstance(value, (float, np.floating)) and math.isfinite(value) and float(value).is_integer():
        value = int(value)
    if isinstance(value, np.integer):
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int) or value < low or (high is not None and value > high):
        # MAX_COUNT, the compiled loops' own bound, is named only to a number past it: "from 1 to 4.61e+18,
        # got 0" read as a limit that means something (newcomer, session 29)
        past = isinstance(value, int) and not isinstance(value, bool) and high is not None and value > high
        span = f"of at least {low}" if high is None or (high == MAX_COUNT and not past) else \
            f"from {low} to {high:.3g}" if high > 1e6 else f"from {low} to {high}"
        shown = f"a number of {digit_count(value)} digits" if isinstance(value, int) and abs(value) >= 10 ** 20 \
            else repr(value)
        raise ParameterError(f"{name} must be a whole number {span}, got {shown}")
    return value


def available_memory() -> Optional[int]:
    """Bytes this process can still allocate, or None when unknown: the
    least of the machine's ``MemAvailable``, the container's cgroup limit
    (``memory.max`` minus ``memory.current``) and the address-space limit
    (``ulimit -v``) minus what the process has mapped already."""
    bounds = [_meminfo_available(), _cgroup_room(), _address_space_room()]
    bounds = [b for b in bounds if b is not None]
    return max(0, min(bounds)) if bounds else None


def _meminfo_available() -> Optional[int]:
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def _read_int(path: str) -> Optional[int]:
    try:
        with open(path) as f:
            return int(f.read().split()[0])
    except (OSError, ValueError, IndexError):
        return None  # absent, or "max" (no limit)


def _cgroup_room() -> Optional[int]:
    limit, used = _read_int("/sys/fs/cgroup/memory.max"), _read_int("/sys/fs/cgroup/memory.current")
    return None if limit is None or used is None else limit - used


def _address_space_room() -> Optional[int]:
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft == resource.RLIM_INFINITY:
            return None
        mapped = _read_int("/proc/self/statm")
        return soft - (mapped or 0) * os.sysconf("SC_PAGE_SIZE")
    except (ImportError, OSError, ValueError, AttributeError):
        return None


def check_memory(need: int, what: str) -> None:
    """Refuse, with a ParameterError, a request whose memory estimate ``need``
    (bytes) exceeds what this process can have now: better one line before
    starting than an out-of-memory kill later. ``what`` starts the message
    and should name the field (``"max_iter=10**12 could grow a tree that"``)."""
    have = available_memory()
    if have is not None and need > have:
        raise ParameterError(f"{what} needs about {_bytes(need)}, more than the {_bytes(have)} this machine has available")


def _bytes(n: int) -> str:
    """``n`` bytes for a person: MiB below a GiB, else GiB."""
    n = min(n, 10**300)
    return f"{n / 2**20:.3g} MiB" if n < 2**30 else f"{n / 2**30:.3g} GiB"


def check_seed(seed: Any) -> None:
    """A seed is a non-negative whole number, None, or a numpy Generator
    (``ParameterError`` naming ``seed`` otherwise: a dict or -5 would reach numpy
    as a ``TypeError``)."""
    if seed is None or isinstance(seed, np.random.Generator):
        return
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ParameterError(f"seed must be a non-negative whole number or a numpy Generator, got {seed!r}")
