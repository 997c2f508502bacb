"""Starting navlab nodes without ros2 launch: as child processes (each its
own Python, as a real system runs them) or as node objects in one process."""

from __future__ import annotations

import importlib
import json
import os
import signal
import subprocess
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple
from ..errors import ParameterError

#: node name → (module, class)
NODES: Dict[str, Tuple[str, str]] = {
    "map_server": ("navlab.ros.map_server", "MapServer"),
    "sim": ("navlab.ros.sim", "SimNode"),
    "pathplanner": ("navlab.ros.pathplanner", "PathPlanner"),
    "astar_pathplanner": ("navlab.ros.astar_pathplanner", "AStarPathPlanner"),  # its first name
    "goto_waypoint": ("navlab.ros.goto_waypoint", "GotoWaypointNode"),
    "potential_field_navigator": ("navlab.ros.potential_field_navigator", "PotentialFieldNavigator"),
    "local_planner": ("navlab.ros.local_planner", "LocalPlannerNode"),
}

NodeSpec = Tuple[str, Dict[str, Any]]

#: a node process's first instructions: quiet on Ctrl-C from the start
#: set by the launcher to its pid: the child checks it is still its parent
PARENT_ENV = "NAVLAB_LAUNCHER_PID"

#: (importing navlab takes a second or two), then navlab.ros.entry.run_child
CHILD_BOOTSTRAP = ("import os, signal, sys; signal.signal(signal.SIGINT, lambda *_: os._exit(130)); "
                   "from navlab.ros.entry import run_child; sys.exit(run_child(sys.argv[1:]))")


def check_node_name(name: str) -> None:
    if name not in NODES:
        from ..registry import suggest

        raise ParameterError(f"unknown node '{name}'.{suggest(name, list(NODES))} Nodes: {', '.join(NODES)}")


def node_class(name: str) -> type:
    check_node_name(name)
    module, cls = NODES[name]
    return getattr(importlib.import_module(module), cls)


def ros_value(value: Any) -> str:
    """A parameter value as ``-p name:=value`` reads it (YAML). Strings are
    quoted (a path or a YAML mapping stays a string); a mapping, which ROS
    parameters cannot hold, becomes its YAML text (see
    :func:`navlab.ros.pathplanner.PathPlanner.planner_params`)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, dict):
        value = mapping_text(value)
    if isinstance(value, str):
        return json.dumps(value)  # a double-quoted YAML scalar
    return str(value)


def mapping_text(value: Dict[str, Any]) -> str:
    """A mapping as one line of YAML (the form a string parameter carries it in)."""
    import yaml

    return yaml.safe_dump(value, default_flow_style=True, width=10**9).strip()


def ros_args(params: Dict[str, Any]) -> List[str]:
    args = ["--ros-args"]
    for key, value in params.items():
        args += ["-p", f"{key}:={ros_value(value)}"]
    return args


class NodeProcesses:
    """Child processes running nodes; a context manager that stops them on
    exit (SIGTERM, on which rclpy shuts a node down cleanly) and kills those
    that hang.

    Each node runs in a process group of its own, so a terminal's Ctrl-C
    reaches only the launcher, which then stops each node once: a SIGINT
    would raise KeyboardInterrupt in a node still starting Python, and a
    second one would break a node's shutdown, each with a traceback. Each
    node dies with the launcher, even a SIGKILLed one
    (:func:`navlab.ros.entry.die_with_parent`).

    Parameters
    ----------
    specs : [(node name, parameters)]
    log_dir : path, optional
        Each node's output goes to ``<log_dir>/<node>.log``; by default it
        goes to this process's stderr.
    """

    def __init__(self, specs: Sequence[NodeSpec], log_dir: Optional[Path] = None) -> None:
        for name, _ in specs:
            check_node_name(name)
        self.specs, self.log_dir = list(specs), log_dir
        self.procs: List[Tuple[str, subprocess.Popen]] = []

    def __enter__(self) -> "NodeProcesses":

        env = {**os.environ, PARENT_ENV: str(os.getpid())}
        try:
            for name, params in self.specs:
                out = None
                if self.log_dir is not None:
                    Path(self.log_dir).mkdir(parents=True, exist_ok=True)
                    out = open(Path(self.log_dir) / f"{name}.log", "w")
                cmd = [sys.executable, "-c", CHILD_BOOTSTRAP, name, *ros_args(params)]
                try:
                    proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT if out else None, env=env,
                                            process_group=0)
                finally:
                    if out is not None:
                        out.close()  # the child holds its own copy
                self.procs.append((name, proc))
        except BaseException:  # Ctrl-C or an OSError half-way: stop the nodes already started
            self.__exit__()
            raise
        return self

    def failed(self) -> List[Tuple[str, int]]:
        """Nodes that have exited, with their exit status."""
        return [(name, p.returncode) for name, p in self.procs if p.poll() is not None]

    def __exit__(self, *exc) -> None:
        for _, p in self.procs:
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for _, p in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
