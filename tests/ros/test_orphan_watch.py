"""A node whose launcher died ends even when its main thread never returns
(``exit_when_orphaned``); ROS-free, so it runs without the ros2 extra."""

import os
import signal
import subprocess
import sys
import time

from ros_helpers import alive

#: the grandchild ignores SIGTERM and sleeps forever: only the watch can end it
GRANDCHILD = """
import signal, sys, time
from navlab.ros.entry import exit_when_orphaned
signal.signal(signal.SIGTERM, signal.SIG_IGN)
exit_when_orphaned(int(sys.argv[1]), grace_s=0.2)
print("watching", flush=True)
time.sleep(600)
"""

#: the launcher stand-in starts the grandchild, prints its pid and waits
LAUNCHER = """
import os, subprocess, sys
child = subprocess.Popen([sys.executable, "-c", sys.argv[1], str(os.getpid())], stdout=subprocess.PIPE, text=True)
assert child.stdout.readline().strip() == "watching"
print(child.pid, flush=True)
child.wait()
"""


def test_a_node_that_ignores_sigterm_still_ends_after_its_launcher_is_killed():
    launcher = subprocess.Popen([sys.executable, "-c", LAUNCHER, GRANDCHILD], stdout=subprocess.PIPE, text=True)
    try:
        node = int(launcher.stdout.readline())
        time.sleep(0.5)
        assert alive(node), "the watch ended the node while its launcher was alive"
        os.kill(launcher.pid, signal.SIGKILL)
        launcher.wait(timeout=60)
        end = time.monotonic() + 60  # a ceiling on waiting, not a measurement
        while alive(node) and time.monotonic() < end:
            time.sleep(0.05)
        assert not alive(node), "the node outlived its launcher"
    finally:
        launcher.kill()
