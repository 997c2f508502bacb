"""Name → component registries with "did you mean" errors.

Every pluggable part (planner, sampler, scene, heuristic, ...) is registered
by name with a decorator, so the CLI, YAML files and the benchmark harness
reach it by name without if/elif factories (STYLE.md rule 8).
"""

from __future__ import annotations

import difflib
import inspect
from typing import Any, Callable, Dict, Generic, Iterator, Optional, TypeVar
from .errors import NavlabError, ParameterError

T = TypeVar("T")


class UnknownNameError(KeyError, NavlabError):
    """Raised for a name no registry entry has; the message lists valid names."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0])


def closest(name: Any, valid) -> Optional[str]:
    """The name among ``valid`` that ``name`` most likely meant, or None: the one written the same but for
    case, else the one closest in spelling (difflib's ratio at least 0.6, its default: at 0.5, ``ackermann`` was
    told ``jackal``; none when two are equally close), else the one name that ``name`` begins (``pur`` for
    ``pure_pursuit``, ``turn`` for ``turning_radius``: too short to be close by spelling). Every "did you mean"
    of navlab (names, settings, choice options) asks this."""
    if not isinstance(name, str):  # a number or a list where a name belongs: nothing is "close"
        return None
    valid = [v for v in dict.fromkeys(valid) if isinstance(v, str)]
    # compared without case throughout: RRT, TRAP and MPPI had no hint (difflib is case-sensitive), nor Theta
    # once the cutoff rose (attack and second review, session 25)
    folded = name.casefold()
    same = [v for v in valid if v.casefold() == folded]
    if same:
        return same[0] if len(same) == 1 else None
    scores = {v: difflib.SequenceMatcher(None, folded, v.casefold()).ratio() for v in valid}
    best = max(scores.values(), default=0.0)
    # two names equally close is no guess: difflib's own pick among them is the alphabetically last, so
    # 'seed003' was told 'seed004', not 'seed002', and 'cal' 'jackal', not 'car' (attack, session 25)
    close = [v for v, score in scores.items() if score == best and best >= 0.6]
    if not close and len(name) >= 2:
        close = [v for v in valid if v.casefold().startswith(folded)]
    return close[0] if len(close) == 1 else None


def suggest(name: str, valid: list[str]) -> str:
    """Return a ``did you mean`` hint for ``name`` among ``valid`` (may be ''), by :func:`closest`."""
    close = closest(name, valid)
    return f" Did you mean '{close}'?" if close else ""


class Registry(Generic[T]):
    """A named collection of factories of one kind.

    Parameters
    ----------
    kind : str
        What the entries are ("planner", "sampler", ...), used in messages.
    """

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._entries: Dict[str, T] = {}

    def register(self, name: str) -> Callable[[T], T]:
        """Decorator registering a class or function under ``name``."""

        def decorate(obj: T) -> T:
            if name in self._entries:
                raise ParameterError(f"{self.kind} '{name}' is registered twice")
            self._entries[name] = obj
            try:
                obj.registered_name = name  # type: ignore[attr-defined]
            except (AttributeError, TypeError):
                pass
            return obj

        return decorate

    def get(self, name: str) -> T:
        """Return the entry called ``name`` or raise :class:`UnknownNameError`."""
        try:
            return self._entries[name]
        except (KeyError, TypeError):  # TypeError: an unhashable value (a list) where a name belongs
            valid = sorted(self._entries)
            raise UnknownNameError(
                f"unknown {self.kind} {name!r}; valid: {', '.join(valid)}."
                + suggest(name, valid)
            ) from None

    def names(self) -> list[str]:
        return sorted(self._entries)

    def __contains__(self, name: object) -> bool:
        return name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __len__(self) -> int:
        return len(self._entries)


def parameters_of(factory: Callable[..., Any]) -> Dict[str, Any]:
    """Keyword parameters of a factory with their defaults (for ``navlab list``)."""
    out: Dict[str, Any] = {}
    for p in inspect.signature(factory).parameters.values():
        if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) and p.name != "self":
            out[p.name] = None if p.default is p.empty else p.default
    return out


def check_params(factory: Callable[..., Any], params: Dict[str, Any], what: str) -> None:
    """Raise ``TypeError``-free, readable errors for unknown keyword parameters."""
    valid = list(parameters_of(factory))
    for key in params:
        if key not in valid:
            raise ParameterError(
                f"unknown parameter '{key}' for {what}; valid: {', '.join(valid) or 'none'}."
                + suggest(key, valid)
            )


def check_finite(params: Dict[str, Any], what: str, factory: Optional[Callable[..., Any]] = None) -> None:
    """Refuse NaN and infinite numbers anywhere in ``params`` (lists included),
    naming the parameter: a robot or controller setting of ``.nan`` or
    ``.inf`` would otherwise run, and end in NaN poses or a robot that never
    turns. (For "no limit", a setting says so in its own terms, e.g. ``None``.)
    The on/off settings of ``factory`` (a bool default) are left to its own
    check: ``replan=.nan`` was told "replan must be finite", as if a number
    would do (attack, session 25)."""
    from .limits import is_finite_real, shown  # (numpy: by now a robot or a controller has loaded it)

    def bad(value: Any) -> bool:
        if isinstance(value, bool):
            return False
        if isinstance(value, (int, float)):  # an int past float's range (10**400) is as unusable as inf
            return not is_finite_real(value)
        if isinstance(value, (list, tuple)):
            return any(bad(v) for v in value)
        try:  # numpy scalars and arrays
            import numpy as np

            arr = np.asarray(value)
            return arr.dtype.kind in "fc" and not bool(np.all(np.isfinite(arr)))
        except Exception:  # not numeric: left to the factory's own checks
            return False

    flags = {k for k, default in parameters_of(factory).items() if isinstance(default, bool)} if factory else set()
    for key, value in params.items():
        if key not in flags and bad(value):
            raise ParameterError(f"{what}: {key} must be finite, got {shown(value)}")
