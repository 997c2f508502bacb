"""The ``navlab`` console script and ``python -m navlab``: :func:`navlab.cli.main`, with a Ctrl-C that lands
while the command's modules are still importing ending as one after them does.

The console script pip writes imports its entry point before calling it, outside any handler: Ctrl-C in the
first tenth of a second (click, gettext, locale being imported) printed a ``KeyboardInterrupt`` traceback and
ended the process by the signal (attack, session 29: 3 of 178 random Ctrl-Cs). This module imports nothing
but ``sys`` before its handler is in place."""

import sys


def main() -> None:
    try:
        from .cli import main as navlab
    except KeyboardInterrupt:
        sys.stderr.write("Interrupted.\n")
        raise SystemExit(130) from None  # (cli.common.EXIT_INTERRUPTED, not imported yet)
    navlab()
