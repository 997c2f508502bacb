"""navlab.compile_clock: numba compiles inside a planner's timed call are moved to its warm-up."""

import threading

from numba import njit

from navlab.compile_clock import compile_clock
from navlab.result import Result, Status


def _fresh_kernel():
    @njit  # not cached: every call with a new signature compiles
    def add(x):
        return x + 1

    return add


def test_compiles_count_for_the_innermost_clock_once():
    add = _fresh_kernel()
    with compile_clock() as outer:
        add(1)
        with compile_clock() as inner:
            add(1.0)
        after_inner = outer.seconds
        add(1)  # compiled already: no event
    assert inner.seconds > 0 and after_inner > 0  # each saw its own compile
    assert outer.seconds == after_inner  # not the inner's, and nothing for a signature already compiled


def test_another_threads_compile_is_not_this_calls():
    add = _fresh_kernel()
    with compile_clock() as clock:
        worker = threading.Thread(target=add, args=(2,))
        worker.start()
        worker.join()
    assert clock.seconds == 0.0


def test_moved_seconds_leave_the_planning_time_and_join_the_warmup():
    add = _fresh_kernel()
    with compile_clock() as clock:
        add(1)
    result = Result(status=Status.EXACT, stats={"time_s": clock.seconds + 0.25, "warmup_s": 0.5})
    clock.moved_to_warmup(result)
    assert abs(result.stats["time_s"] - 0.25) < 1e-12 and abs(result.stats["warmup_s"] - 0.5 - clock.seconds) < 1e-12
    short = Result(status=Status.FAILED, stats={"time_s": clock.seconds / 2})  # never below zero
    clock.moved_to_warmup(short)
    assert short.stats["time_s"] == 0.0 and short.stats["warmup_s"] == clock.seconds / 2
