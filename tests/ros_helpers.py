"""Running ROS 2 processes in a private network namespace for the tests.

``unshare -n`` gives the processes a network of their own (only a loopback,
brought up first), so tests never talk to other ROS systems on the machine
and parallel runs never meet. Where unprivileged users cannot create one,
the processes fall back to localhost-only discovery on a random domain id.
"""

import functools
import os
import random
import shutil
import subprocess
import sys
from pathlib import Path

DOMAIN_ID = 42


@functools.lru_cache(maxsize=1)
def can_unshare() -> bool:
    if shutil.which("unshare") is None or shutil.which("ip") is None:
        return False
    return subprocess.run(["unshare", "-n", "true"], capture_output=True).returncode == 0


def ros_env(domain_id: int) -> dict:
    env = os.environ.copy()
    env.update(ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", ROS_DOMAIN_ID=str(domain_id), MPLBACKEND="Agg",
               RMW_IMPLEMENTATION="rmw_fastrtps_cpp", PYTHONUNBUFFERED="1")
    return env


def run_isolated(args, timeout: float) -> subprocess.CompletedProcess:
    """Run ``args`` in a private network namespace; output captured as text."""
    if can_unshare():
        cmd = ["unshare", "-n", "sh", "-c", 'ip link set lo up && exec "$@"', "sh", *args]
        env = ros_env(DOMAIN_ID)
    else:
        cmd, env = list(args), ros_env(random.randint(100, 200))
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def navlab_cmd(*args) -> list:
    return [sys.executable, "-m", "navlab", *args]


def alive(pid: int) -> bool:
    """Whether a process runs (a zombie, waiting for a reaper, does not)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state not in ("Z", "X")
