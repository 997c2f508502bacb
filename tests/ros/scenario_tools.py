"""What the ROS scenario scripts (run in a private network namespace by the
tests beside them) share."""

import time


def spinner(executor):
    """``spin(seconds, until=None)``: spin ``executor`` for up to ``seconds`` of wall-clock
    time, returning True as soon as ``until()`` holds (False if it never did)."""

    def spin(seconds, until=None):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.02)
            if until is not None and until():
                return True
        return False

    return spin
