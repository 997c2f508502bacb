"""Small pieces of the English navlab's messages are written in."""

from __future__ import annotations

import re


def counted(n: int, noun: str) -> str:
    """``1 run``, ``4 runs``, ``0 runs``: a count with its noun, singular for one ("1 runs (1 run now)"
    was a BARN summary line until session 18). Regular plurals only."""
    return f"{n} {noun}" + ("" if n == 1 else "s")


def with_article(noun: str) -> str:
    """``noun`` after "a" or "an", by its first letter ("an experiment file", "a map YAML file")."""
    return ("an " if noun[:1].lower() in "aeiou" and noun[:1] else "a ") + noun


def listed(names) -> str:
    """``a``, ``a and b``, ``a, b and c``: names as a sentence lists them (a note read "heuristic and motion
    and sigma and turning_radius and weight": newcomer, session 24)."""
    names = list(names)
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def duration(seconds: float) -> str:
    """A duration as people read it (a first use's warm-up printed as "53881 ms"; newcomer run, session 21).

    Parameters
    ----------
    seconds : float

    Returns
    -------
    str
        Whole milliseconds below ten seconds as rounded (``41 ms``, ``9999 ms``), tenths of a second from
        there (``10.0 s``, ``53.9 s``).
    """
    ms = round(seconds * 1000)
    return f"{ms} ms" if ms < 10_000 else f"{seconds:.1f} s"


def decimal(x: float, places: int = 6) -> str:
    """``x`` to ``places`` decimals without trailing zeros (``0.3``, ``4.8``, ``1234.5678``, ``2``): a
    coordinate as a command line would take it (``{:g}`` keeps six significant digits, 12345.675 -> 12345.7)."""
    text = f"{x:.{places}f}"
    if "." in text:  # (10 to no places is "10": only a fraction's zeros go; review, session 31)
        text = text.rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def escaped(text: str) -> str:
    """``text`` with its control characters written as escapes (``\\n``, ``\\x1b``): a message shows them
    rather than obeying them (a file name holding ESC [31m turned the terminal red; newcomer run, session 21)."""
    return re.sub(r"[\x00-\x1f\x7f]", lambda m: repr(m.group())[1:-1], text)
