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


def test_a_ctrl_c_during_a_compile_is_raised_when_it_ends():
    """SIGINT landing in a compile is held and raised by the listener when the compile ends (a
    KeyboardInterrupt raised inside LLVM's ctypes callbacks was printed and dropped: the command ran
    on); the default handler is back afterwards."""
    import os
    import subprocess
    import sys

    child = r"""
import os, signal, sys, threading, traceback
import numpy as np
from numba import njit
from navlab.compile_clock import hold_interrupts_while_compiling
hold_interrupts_while_compiling()

@njit  # not cached: it compiles here, for longer than the timer's delay
def kernel(a):
    total = 0.0
    for i in range(a.shape[0]):
        total += np.sin(a[i]) * np.cos(a[i]) + np.sqrt(abs(a[i]))
    return total

njit(lambda x: x + 1)(1)  # numba's own first-compile set-up, which runs before the compile event starts
threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT)).start()
try:
    kernel(np.arange(10.0))
    print("not interrupted")
except KeyboardInterrupt as exc:
    where = traceback.extract_tb(exc.__traceback__)[-1].name
    print("interrupted in", where, signal.getsignal(signal.SIGINT) is signal.default_int_handler)
"""
    out = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=300,
                         env={**os.environ, "NUMBA_CACHE_DIR": os.devnull})
    assert out.stdout.strip() == "interrupted in on_end True", (out.stdout, out.stderr)


def test_a_first_compile_says_so_once_on_a_terminal_only():
    """navlab plan / grid plan on a cold cache compiled for a minute in silence (a newcomer took it for a
    hang): the first compile of the process writes one line to a terminal's stderr, none to a pipe."""
    import subprocess
    import sys

    child = r"""
import io, sys
from numba import njit
class Terminal(io.StringIO):
    def isatty(self):
        return {tty}
sys.stderr = said = Terminal()
from navlab.compile_clock import say_when_compiling
say_when_compiling()
say_when_compiling()  # registered once
njit(lambda x: x + 1)(1)
njit(lambda x: x * 2.0)(1.0)
sys.__stdout__.write(repr(said.getvalue()))
"""
    for tty, lines in ((True, 1), (False, 0)):
        out = subprocess.run([sys.executable, "-c", child.format(tty=tty)], capture_output=True, text=True,
                             timeout=300, check=True)
        said = eval(out.stdout)  # the repr of what the child's stderr got
        assert said.count("\n") == lines and said.count("compiling navlab's kernels for a first use, or code they hold changed") == lines, said


def test_a_ctrl_c_under_numbas_compiler_lock_is_raised_when_it_is_released():
    """Loading a cached kernel and compiling the runtime's module run LLVM under numba's compiler lock without a
    compile event; a Ctrl-C there was printed from LLVM's callback and lost (CI, under load). Held the same way."""
    import subprocess
    import sys

    child = r"""
import os, signal, time, traceback
from numba.core.compiler_lock import global_compiler_lock
from navlab.compile_clock import hold_interrupts_while_compiling
hold_interrupts_while_compiling()
try:
    with global_compiler_lock:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.2)  # the signal arrives and is only noted
        print("held", flush=True)
    print("not interrupted")
except KeyboardInterrupt as exc:
    print("interrupted in", traceback.extract_tb(exc.__traceback__)[-1].name,
          signal.getsignal(signal.SIGINT) is signal.default_int_handler)
"""
    out = subprocess.run([sys.executable, "-c", child], capture_output=True, text=True, timeout=120)
    assert out.stdout.split("\n")[:2] == ["held", "interrupted in on_end True"], (out.stdout, out.stderr)
