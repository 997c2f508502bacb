"""numba's compiles, seen through its events: their seconds inside a planner's timed call
are moved to its warm-up, and a Ctrl-C during one takes effect when it ends.

A planner's kernels are compiled or loaded before its clock starts (the
``warmup_s`` of :mod:`navlab.warmup` and ``grid.planner.warm_kernels``), but
the warm-up compiles the argument types navlab's own worlds and maps give;
another map (a PNG's image, a robot without a footprint, ...) can ask a kernel
for a signature it has never compiled, and numba then compiles it inside the
timed call: a first query of 5 ms reported as 580 ms of planning. The clock
below listens to numba's ``numba:compile`` events, which fire for compiles
only (a signature found in numba's cache loads without one), and
:meth:`CompileClock.moved_to_warmup` moves their seconds from the result's
``time_s`` to its ``warmup_s``.

Clocks nest (navlab.plan around a grid planner's own): an event counts for
the innermost clock of the thread that compiles, so no second is moved twice,
and another thread's compiles are not this call's.

:func:`say_when_compiling` (for the command line) writes one line to a
terminal's standard error when a process's first compile starts, so that a
first use that compiles for a minute does not look like a hang.

Ctrl-C during a compile: LLVM calls back into Python while it compiles
(llvmlite's object cache, through ctypes), and a KeyboardInterrupt raised
inside such a callback is printed as "Exception ignored on calling ctypes
callback function" and dropped: the command ran on to its end (a plan with
``--max-time 120`` interrupted during its first compile finished, exit 0).
:func:`hold_interrupts_while_compiling` makes SIGINT, while a compile runs on
the main thread under Python's default handler, only noted, and raises the
KeyboardInterrupt when the compile ends, outside any callback. It does the
same while numba's compiler lock is held (its ``numba:compiler_lock``
events): loading a cached kernel and the runtime's own module, which LLVM
compiles in every process, run LLVM outside any compile event.

References
----------
Numba documentation, "Event API" (``numba.core.event``: ``install_listener``,
the ``numba:compile`` event kind).
"""

from __future__ import annotations

import functools
import signal
import threading
import time
from contextlib import contextmanager
from typing import Iterator, List

from .result import Result

_local = threading.local()  # this thread's open clocks, innermost last


class CompileClock:
    """Seconds of numba compiling seen while it was the thread's innermost open clock."""

    def __init__(self) -> None:
        self.seconds = 0.0

    def moved_to_warmup(self, result: Result) -> Result:
        """``result`` with the compile seconds taken from ``stats["time_s"]`` (never below 0)
        and added to ``stats["warmup_s"]``."""
        stats = result.stats
        moved = min(self.seconds, stats.get("time_s") or 0.0)
        if moved > 0.0:
            stats["time_s"] -= moved
            stats["warmup_s"] = (stats.get("warmup_s") or 0.0) + moved
        return result


def _open_clocks() -> List[CompileClock]:
    if not hasattr(_local, "clocks"):
        _local.clocks = []
    return _local.clocks


@contextmanager
def compile_clock() -> Iterator[CompileClock]:
    """A :class:`CompileClock` running for the ``with`` block (this thread's compiles only)."""
    from numba.core import event

    clock = CompileClock()
    clocks = _open_clocks()
    clocks.append(clock)
    try:
        with event.install_listener("numba:compile", _listener_class()(threading.get_ident())):
            yield clock
    finally:
        clocks.remove(clock)


@functools.lru_cache(maxsize=1)
def _listener_class():
    """numba's Listener subclass, made on first use (importing numba here would put it in ``navlab --help``)."""
    from numba.core import event

    class OutermostCompiles(event.Listener):
        """Times outermost compiles (a kernel's includes its callees') into the thread's innermost clock."""

        def __init__(self, thread: int) -> None:
            self._started: List[float] = []
            self._thread = thread

        def on_start(self, ev) -> None:
            if threading.get_ident() == self._thread:
                self._started.append(time.perf_counter())

        def on_end(self, ev) -> None:
            if threading.get_ident() != self._thread or not self._started:
                return
            began = self._started.pop()
            clocks = _open_clocks()
            if not self._started and clocks:
                clocks[-1].seconds += time.perf_counter() - began

    return OutermostCompiles


def first_call_seconds(warm, *args) -> float:
    """The seconds ``warm(*args)`` returns (an ``functools.lru_cache``'d warm-up that times itself) the
    first time in this process with these arguments, 0.0 afterwards (a cache hit compiled nothing)."""
    hits = warm.cache_info().hits
    seconds = warm(*args)
    return 0.0 if warm.cache_info().hits > hits else seconds


@functools.lru_cache(maxsize=1)
def hold_interrupts_while_compiling() -> None:
    """Register, once per process, the listener that holds a Ctrl-C until the compile (or anything
    else done under numba's compiler lock) it lands in ends (see the module's docstring). A SIGINT
    handler other than Python's default is left alone."""
    from numba.core import event

    class HoldInterrupts(event.Listener):
        def __init__(self) -> None:
            self._depth = 0
            self._noted = False
            self._previous = None

        def _note(self, signum, frame) -> None:
            self._noted = True

        def on_start(self, ev) -> None:
            if threading.current_thread() is not threading.main_thread():
                return  # only the main thread receives signals, and only it may set their handlers
            self._depth += 1
            if self._depth == 1 and signal.getsignal(signal.SIGINT) is signal.default_int_handler \
                    and not _ros_owns_sigint():
                self._previous = signal.signal(signal.SIGINT, self._note)

        def on_end(self, ev) -> None:
            if threading.current_thread() is not threading.main_thread():
                return
            self._depth -= 1
            if self._depth == 0 and self._previous is not None:
                # put the handler back only if nobody replaced ours meanwhile (the navlab command's end-of-run
                # handler, cli.common.end_at_ctrl_c, was overwritten with Python's default, and a second
                # Ctrl-C then ended a bench run by the signal: session 29)
                mine = signal.getsignal(signal.SIGINT) == self._note
                if mine:
                    signal.signal(signal.SIGINT, self._previous)
                self._previous = None
                if self._noted:
                    self._noted = False
                    if mine and signal.getsignal(signal.SIGINT) is signal.default_int_handler:
                        raise KeyboardInterrupt  # here, in numba's own Python frame: it reaches the caller
                    signal.raise_signal(signal.SIGINT)  # to whoever handles it now

    held = HoldInterrupts()
    event.register("numba:compile", held)
    # numba's compiler lock is held around every compile and also around what runs LLVM without a compile
    # event: loading a cached kernel, and the runtime's own module, compiled in every process (rtsys.initialize);
    # a Ctrl-C landing there was lost the same way (fuzz test_real_command_ctrl_c_is_one_line, CI under load)
    event.register("numba:compiler_lock", held)


def _ros_owns_sigint() -> bool:
    """Whether rclpy is initialised in this process: it handles SIGINT in C, below what
    ``signal.getsignal`` sees (Python still reports its default handler), and setting a Python
    handler, even to put the default back, replaces rclpy's for good: a ROS node that loaded a
    kernel after ``rclpy.init`` then ignored Ctrl-C, its executor never woken (the pathplanner
    node: attack run, session 18). Under rclpy, Ctrl-C shuts the executor down instead."""
    import sys

    rclpy = sys.modules.get("rclpy")
    try:
        return rclpy is not None and bool(rclpy.ok())
    except Exception:  # an rclpy too old or half-imported to say: leave its signals alone too
        return rclpy is not None


@functools.lru_cache(maxsize=1)
def say_when_compiling() -> None:
    """Register, once per process, a listener that writes one line to standard error when the
    process's first compile starts, if standard error is a terminal (a log or a pipe gets none:
    the warm-up line after the plan gives the seconds)."""
    import sys

    from numba.core import event

    class SayOnce(event.Listener):
        def __init__(self) -> None:
            self._said = False

        def on_start(self, ev) -> None:
            if self._said:
                return
            self._said = True
            stream = sys.stderr
            if stream is not None and stream.isatty():
                # (also after an edit to the code a kernel holds: "for a first use" puzzled a contributor there)
                stream.write("compiling navlab's kernels for a first use, or code they hold changed (once: they "
                             "are cached afterwards; up to a few minutes on a busy machine) ...\n")
                stream.flush()

        def on_end(self, ev) -> None:
            pass

    event.register("numba:compile", SayOnce())
