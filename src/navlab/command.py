"""The console scripts, ``navlab`` and ``navlab-<node>``, and ``python -m navlab``: :func:`navlab.cli.main`,
with a Ctrl-C that lands while the command's modules are still importing ending as one after them does.

The console script pip writes imports its entry point before calling it, outside any handler: Ctrl-C in the
first tenth of a second (click, gettext, locale being imported) printed a ``KeyboardInterrupt`` traceback and
ended the process by the signal (attack, session 29: 3 of 178 random Ctrl-Cs). This module imports nothing
but ``sys`` before its handler is in place; the ``navlab-<node>`` scripts (``navlab ros <node>``) live here
for the same reason (in ``navlab.cli.scripts`` their import went through ``navlab.cli``, click and all).
"""

import sys
from typing import Callable

from .errors import EXIT_INTERRUPTED


def _command() -> Callable:
    """:func:`navlab.cli.main`, imported under a Ctrl-C handler."""
    try:
        from .cli import main
    except KeyboardInterrupt:
        sys.stderr.write("Interrupted.\n")
        raise SystemExit(EXIT_INTERRUPTED) from None
    return main


def main() -> None:
    """The ``navlab`` command."""
    _command()()


def console_script(node: str) -> Callable[[], None]:
    """The ``navlab-<node>`` console script: ``navlab ros <node> ARGS``."""

    def script() -> None:
        _command()(["ros", node, *sys.argv[1:]], prog_name=f"navlab-{node.replace('_', '-')}")

    script.__doc__ = f"navlab ros {node}"
    return script


map_server = console_script("map_server")
sim = console_script("sim")
pathplanner = console_script("pathplanner")
astar_pathplanner = console_script("astar_pathplanner")
goto_waypoint = console_script("goto_waypoint")
potential_field_navigator = console_script("potential_field_navigator")
local_planner = console_script("local_planner")
