"""Entry points of the node processes, free of ROS until a node starts.

- Console scripts (``navlab-sim``, ``navlab-pathplanner``, ...) are
  ``navlab ros NODE``: the same arguments, help and errors — without the
  ``ros2`` extra the same one line and exit status 2, not a traceback.
- :func:`run_child` is how :class:`~navlab.ros.launch.NodeProcesses` starts
  a node (``launch.CHILD_BOOTSTRAP``): the process dies
  with its launcher (``PR_SET_PDEATHSIG`` on Linux), and an interrupt at any
  moment, even while Python is still importing, ends it without a traceback.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
from typing import List, Optional

#: <linux/prctl.h>
PR_SET_PDEATHSIG = 1
#: exit status of a process ended by SIGINT, as a shell reports it
INTERRUPTED = 128 + signal.SIGINT
#: exit status of a node that outlived its launcher by the grace period
ORPHANED = 128 + signal.SIGTERM
#: seconds a node whose launcher died has to shut down cleanly before it
#: exits regardless, and how often it looks for its launcher
ORPHAN_GRACE_S, PARENT_POLL_S = 5.0, 0.25


def die_with_parent(parent_pid: Optional[int], sig: int = signal.SIGTERM) -> bool:
    """Ask the kernel to send ``sig`` to this process when its parent dies
    (Linux; elsewhere nothing). Returns False when the parent is already gone
    (it died before the request could take effect), so nothing would come.

    The launcher keeps its own process group for the nodes (a terminal's
    Ctrl-C reaches only the launcher), so without this a SIGKILLed launcher
    would leave its nodes running forever.
    """
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, int(sig), 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_SET_PDEATHSIG) failed")
    return parent_pid is None or os.getppid() == parent_pid


def exit_when_orphaned(parent_pid: int, grace_s: float = ORPHAN_GRACE_S) -> threading.Thread:
    """Start a daemon thread that ends this process ``grace_s`` after its
    launcher ``parent_pid`` is gone, whatever the main thread is doing.

    ``PR_SET_PDEATHSIG`` asks for a clean shutdown, but a node busy in a
    long callback (or a shutdown that hangs in the middleware) would keep
    running for as long as that takes; a node must never outlive its launcher.
    """

    def watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(PARENT_POLL_S)
        time.sleep(grace_s)
        os._exit(ORPHANED)

    thread = threading.Thread(target=watch, name="navlab-orphan-watch", daemon=True)
    thread.start()
    return thread


def run_child(argv: List[str]) -> int:
    """Run node ``argv[0]`` with the ROS arguments that follow (see the module docstring)."""
    from .launch import PARENT_ENV

    parent = os.environ.get(PARENT_ENV)
    if not die_with_parent(int(parent) if parent else None):
        return INTERRUPTED
    if parent:
        exit_when_orphaned(int(parent))
    try:
        # from here on an interrupt is a KeyboardInterrupt (the launcher's
        # bootstrap exited at once until now), then rclpy's
        signal.signal(signal.SIGINT, signal.default_int_handler)
        from .base import run_node
        from .launch import node_class

        name = argv[0]
        return run_node(node_class(name), [f"navlab-{name}", *argv[1:]])
    except KeyboardInterrupt:  # interrupted before rclpy took over the signals (imports, start-up)
        return INTERRUPTED
