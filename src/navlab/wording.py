"""Small pieces of the English navlab's messages are written in."""

from __future__ import annotations


def counted(n: int, noun: str) -> str:
    """``1 run``, ``4 runs``, ``0 runs``: a count with its noun, singular for one ("1 runs (1 run now)"
    was a BARN summary line until session 18). Regular plurals only."""
    return f"{n} {noun}" + ("" if n == 1 else "s")
