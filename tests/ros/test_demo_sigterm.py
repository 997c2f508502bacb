"""``navlab ros demo --processes`` stopped with SIGTERM ends cleanly, whenever
the signal lands: while the nodes start, while the robot drives (it used to
end 3 times in 7 in ``internal error: RCLError ... context is not valid``)."""

import sys

import pytest

pytest.importorskip("rclpy")

from ros_helpers import run_isolated  # noqa: E402

#: seconds after the start: importing and launching, nodes up, the robot on its way
DELAYS = (0.5, 2.5, 5.0)


@pytest.mark.parametrize("delay", DELAYS)
def test_sigterm_stops_the_demo_cleanly(delay):
    script = (f'"{sys.executable}" -m navlab ros demo --processes & pid=$!; sleep {delay}; '
              'kill -TERM $pid; wait $pid')
    done = run_isolated(["sh", "-c", script], timeout=90)
    assert done.returncode in (130, 143), done.stderr[-2000:]
    for bad in ("Traceback", "RCLError", "internal error", "Exception ignored"):
        assert bad not in done.stderr, done.stderr[-2000:]
