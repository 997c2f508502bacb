"""The ``navlab-<node>`` console scripts: each runs ``navlab ros <node> ARGS``.

They live with the CLI, not in :mod:`navlab.ros`, so that nothing in the ROS
package imports the command line (``navlab.cli`` → ``navlab.ros`` only).
"""

from __future__ import annotations

import sys
from typing import Callable

from ..ros.entry import INTERRUPTED


def console_script(node: str) -> Callable[[], None]:
    """The ``navlab-<node>`` console script: ``navlab ros <node> ARGS``."""

    def main() -> None:
        try:
            from . import main as navlab
        except KeyboardInterrupt:  # Ctrl-C while importing
            sys.exit(INTERRUPTED)
        navlab(["ros", node, *sys.argv[1:]], prog_name=f"navlab-{node.replace('_', '-')}")

    main.__doc__ = f"navlab ros {node}"
    return main


map_server = console_script("map_server")
sim = console_script("sim")
pathplanner = console_script("pathplanner")
astar_pathplanner = console_script("astar_pathplanner")
goto_waypoint = console_script("goto_waypoint")
potential_field_navigator = console_script("potential_field_navigator")
local_planner = console_script("local_planner")
