"""The ``navlab`` command: one module per verb, sharing only :mod:`.common`."""

from __future__ import annotations

import atexit
import contextlib
import gc
import os
import sys
import threading
import time

#: when the navlab command started (its first import): `navlab bench` reports its start-up from here, not
#: from the process's start (a `sleep 6 &&` before it, or the shell's own start, is not navlab's time)
STARTED = time.perf_counter()

import click  # noqa: E402 - after the clock starts

from ..errors import interrupted_by_ctrl_c
from .common import (CUT_STATUS, EXIT_INTERRUPTED, THE_COMMAND, SuggestingGroup, debug_enabled, describe_error,
                     end_at_ctrl_c)


def _quick_exit() -> None:
    """Skip the garbage collection of everything numba built, when this process exits.

    A process that loaded one compiled function holds about 110 000 objects the
    garbage collector tracks (numba's typing and lowering registries; 19 000
    after ``import numpy``), and the collections Python runs while it shuts
    down walk them again and again: 0.4-0.5 s after ``navlab plan clutter``'s
    work is done, 0.05-0.1 s with them frozen (this machine, load 5-7).
    ``gc.freeze()`` moves every object to the permanent generation, which
    collections skip. It is registered with ``atexit`` when a command starts
    (once: a second call moves it, never doubles it), so it runs after the
    command's work and before Python's final collections; only the memory of
    objects in reference cycles is then left to the operating system, which
    takes it back anyway. Objects freed by reference counting (files included)
    are closed as before, and other ``atexit`` handlers still run. In a process
    that calls :func:`main` many times (tests) it runs once, at that
    process's exit.

    References
    ----------
    Python documentation, ``gc.freeze``:
    https://docs.python.org/3/library/gc.html#gc.freeze, and "Python shutdown",
    ``Py_FinalizeEx`` (atexit handlers, then the final collections).
    """
    atexit.unregister(_freeze_at_exit)
    atexit.register(_freeze_at_exit)


def _freeze_at_exit() -> None:
    """:func:`_quick_exit`'s handler: ``gc.freeze()``, unless OMPL is loaded.

    A module's objects are freed by the final collections as the interpreter
    ends; frozen, OMPL's outlive it, and nanobind, OMPL's binding library,
    then lists 1 600 of them as "leaked" as the process ends (`navlab bench`
    with an `ompl:` planner printed 25 such lines to the terminal). A run that
    loaded OMPL exits the ordinary way, about 0.4 s slower."""
    if "ompl" not in sys.modules:
        gc.freeze()


#: the thread-count settings of the BLAS libraries numpy and SciPy may be built with; the navlab command
#: sets the first two to 1 unless the user set any of them (OpenBLAS falls back on OMP_NUM_THREADS and
#: GOTO_NUM_THREADS when its own is unset, so a user's value there must win too)
BLAS_THREAD_SETTINGS = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS", "GOTO_NUM_THREADS")


def _is_the_command() -> bool:
    """Whether this process is the ``navlab`` command: its ``__main__`` is the console script
    (a file named ``navlab``) or ``python -m navlab``. A program that calls :func:`main` itself is
    not, and keeps its environment and its process."""
    entry = sys.modules.get("__main__")
    spec = getattr(entry, "__spec__", None)
    if spec is not None and spec.name == "navlab.__main__":
        return True
    name = os.path.basename(getattr(entry, "__file__", None) or "")
    return name in ("navlab", "navlab.exe", "navlab-script.py")


def _one_blas_thread(the_command: bool) -> None:
    """Run numpy's and SciPy's BLAS on one thread in this command's process, unless the user said otherwise.

    OpenBLAS starts one thread per core when its library loads (numpy's at
    ``import numpy``, SciPy's when numba's BLAS check loads it), and the new
    threads spin before they sleep: ``import numpy`` costs 0.18 s of CPU
    with one thread against 0.23 s without (medians of 21 interleaved fresh
    processes, 2 cores, load 5), ``navlab plan clutter`` 0.94 against 0.97 s
    of CPU and 1.62 against 1.74 s wall (15 pairs, load 5-6). No verb needs
    threaded BLAS: navlab's products are of 2-vectors and 2 x 2 matrices,
    below OpenBLAS's threading threshold, and its hot loops are numba
    kernels, which call BLAS single-threaded or not at all; ``navlab bench``'s
    worker processes then do not oversubscribe the cores either.

    Only ``OPENBLAS_NUM_THREADS`` and ``MKL_NUM_THREADS`` are set, and only
    when none of :data:`BLAS_THREAD_SETTINGS` is (a user's own setting wins);
    ``OMP_NUM_THREADS`` is never set, as it governs more than BLAS. Nothing
    changes when numpy is already imported, or when the process is not the
    ``navlab`` command (``the_command`` False, :func:`_is_the_command` asked
    once per run by the caller: a program or a test calling :func:`main`
    keeps its environment, which its child processes inherit). ``import
    navlab`` never calls this.

    References
    ----------
    OpenBLAS, "Setting the number of threads using environment variables"
    (https://github.com/OpenMathLib/OpenBLAS/wiki/Faq#multi-threaded);
    ``blas_thread_init`` in ``driver/others/blas_server.c`` (threads made
    when the library loads).
    """
    if not the_command or "numpy" in sys.modules or any(name in os.environ for name in BLAS_THREAD_SETTINGS):
        return
    for name in BLAS_THREAD_SETTINGS[:2]:
        os.environ[name] = "1"


def _exit_now(code) -> None:
    """End the process at once after a verb that declared it safe: flush, run the ``atexit`` handlers, ``os._exit``.

    What an ordinary exit does after the ``atexit`` handlers, tearing down
    every module and destroying numba's compiled code and LLVM's objects, is
    work for nothing in a process that is about to end: 0.07 s -> 0.03 s of
    wall time from the last line written to the process's end after
    ``navlab plan clutter`` (medians of 11 interleaved runs, load 6; what is
    left is the kernel unmapping the process). Only a verb that writes its
    output with ``click.echo`` and closes every file it opens (``--plot``'s
    PNG: matplotlib closes it) sets ``exits_quickly`` on its command. The
    ``atexit`` handlers still run (coverage measurement, numba's
    ``NUMBA_CHROME_TRACE``, :func:`_quick_exit`'s), and standard output and
    error are flushed before and after them. It returns, leaving the
    ordinary exit to run, when the status is not a number (a message for
    Python to print), another Python thread is alive (the ordinary exit
    joins it), a flush fails (a reader that went away: the ordinary exit
    reports it as usual), or this Python has no ``atexit._run_exitfuncs``
    (a private function, CPython's: without it the handlers could not run
    here, and the ordinary exit runs them).

    References
    ----------
    Python documentation, ``os._exit`` (https://docs.python.org/3/library/os.html#os._exit:
    "exit the process ... without calling cleanup handlers, flushing stdio
    buffers, etc.") and "Python shutdown", ``Py_FinalizeEx``.
    """
    if code is None:
        code = 0
    run_exit_handlers = getattr(atexit, "_run_exitfuncs", None)  # noqa: SLF001 - the ordinary exit's first step
    if run_exit_handlers is None or not isinstance(code, int) or threading.active_count() > 1:
        return
    streams = [stream for stream in (sys.stdout, sys.stderr) if stream is not None]  # None: started with it closed
    try:
        for stream in streams:
            stream.flush()
    except (OSError, ValueError):  # a closed pipe or stream: the ordinary exit deals with it
        return
    run_exit_handlers()  # what the ordinary exit would run first, in the same order
    for stream in streams:
        try:
            stream.flush()  # what the handlers wrote
        except (OSError, ValueError):
            pass
    os._exit(code)


def _pacified(stream) -> bool:
    """Whether click's EPIPE branch wrapped ``stream`` (newer click names the
    wrapper ``_PacifyFlushWrapper``, and its old public name warns as deprecated)."""
    wrapper = getattr(click.utils, "_PacifyFlushWrapper", None)
    if wrapper is None:  # an older click: the public name only
        wrapper = click.utils.PacifyFlushWrapper
    return isinstance(stream, wrapper)


def _stdout_reader_gone() -> bool:
    """Whether standard output is a pipe whose reader went away (``navlab list | head -1``).

    The pipe is asked, not the exception: polled with no event requested, a
    pipe's writing end reports an error (Linux: ``POLLERR``; a hang-up
    elsewhere) once no reader is left; a file, a terminal or a live pipe
    reports nothing, and a BrokenPipeError from another pipe (a worker's, a
    socket) stays an ordinary error. If the reader is gone, standard output
    is pointed at ``os.devnull`` (its file descriptor, so no later flush
    fails: the interpreter's own at exit would print ``Exception ignored ...
    BrokenPipeError`` and end with status 120), and the command ends quietly
    with status 0, as ``ls | head -1`` looks to the shell; click alone ends
    it with status 1. Without ``select.poll`` (Windows) the answer is no.

    References
    ----------
    Python documentation, "Note on SIGPIPE" in the ``signal`` module
    (https://docs.python.org/3/library/signal.html#note-on-sigpipe): Python
    ignores SIGPIPE, so a write to a closed pipe raises BrokenPipeError; send
    the rest of the output to ``os.devnull``. POSIX ``poll()``: POLLERR and
    POLLHUP are reported whatever the events asked.
    """
    import select

    try:
        fd = sys.stdout.fileno()
        poller = select.poll()
    except (AttributeError, OSError, ValueError):  # no stream, no file descriptor (a test's stream), no poll
        return False
    poller.register(fd, 0)
    if not any(events & (select.POLLERR | select.POLLHUP) for _, events in poller.poll(0)):
        return False
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)
    return True


class NavlabGroup(SuggestingGroup):
    """The top-level group: no Python traceback ever reaches a user.

    Bad input (navlab's own error types, ``NavlabError``, unreadable files, a missing
    optional package, a request too large for memory) prints one
    ``Error: ...`` line and exits 2; Ctrl-C prints one line and exits 130; an
    unexpected exception (a bug) prints one ``Error: internal error: ...``
    line and exits 1. ``NAVLAB_DEBUG=1`` re-raises instead, showing the
    traceback.
    """

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, the_command=None, **extra):
        """click's main, with its usage errors on one line (click prints the
        usage and a hint on lines of their own): ``Error: <what> (see
        'navlab plan --help')``, exit 2. ``the_command``: whether this process
        is the ``navlab`` command, if the caller asked :func:`_is_the_command`
        already (None: ask it here)."""
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        the_command = _is_the_command() if the_command is None else the_command
        _one_blas_thread(the_command)  # before a verb imports numpy
        _quick_exit()
        self.the_command = the_command  # (for invoke: the verbs' context says it, THE_COMMAND)
        try:
            self._main(args, prog_name, complete_var, **extra)
        except SystemExit as exc:
            if the_command:
                end_at_ctrl_c(exc.code)
            raise

    def _main(self, args, prog_name, complete_var, **extra):
        """:meth:`main`'s run of the command, ending in ``SystemExit`` with its status."""
        try:
            code = super().main(args, prog_name, complete_var, False, **extra)
        except SystemExit as exc:
            # click's own EPIPE branch (output outside a verb, as `navlab --help | true`) exits 1 after
            # wrapping stdout in PacifyFlushWrapper; a reader that went away ends quietly, as in invoke
            if exc.code == 1 and _pacified(sys.stdout) and _stdout_reader_gone():
                sys.exit(0)
            raise
        except click.exceptions.UsageError as exc:
            if isinstance(exc, getattr(click.exceptions, "NoArgsIsHelpError", ())):  # `navlab` or `navlab grid`
                # alone: click 8.2+ raises the group's help as a usage error; it is shown whole, not as one line
                exc.show()
                sys.exit(exc.exit_code)
            where = f" (see '{exc.ctx.command_path} --help')" if exc.ctx is not None else ""
            message = " ".join(exc.format_message().splitlines())  # one line, even for a value holding newlines
            # click's own full stop goes after the pointer to --help (an ellipsis stays whole)
            if where and message.endswith(".") and not message.endswith("..."):
                message, where = message[:-1], where + "."
            click.echo(f"Error: {message}{where}", err=True)
            sys.exit(exc.exit_code)
        except click.exceptions.ClickException as exc:
            exc.show()
            sys.exit(exc.exit_code)
        except click.exceptions.Abort:
            click.echo("Aborted!", err=True)
            sys.exit(1)
        sys.exit(code if isinstance(code, int) else 0)

    def invoke(self, ctx):
        ctx.meta[THE_COMMAND] = getattr(self, "the_command", False)
        try:
            with heading_notes():
                return super().invoke(ctx)
        except (click.exceptions.ClickException, click.exceptions.Exit, click.exceptions.Abort, SystemExit):
            raise  # click's own messages and exit statuses
        except KeyboardInterrupt:
            if debug_enabled():
                raise
            end_at_ctrl_c(EXIT_INTERRUPTED, ctx)  # a second Ctrl-C now ends it as this one does
            click.echo("Interrupted.", err=True)
            sys.exit(EXIT_INTERRUPTED)
        except Exception as exc:
            if interrupted_by_ctrl_c(exc) and not debug_enabled():
                end_at_ctrl_c(EXIT_INTERRUPTED, ctx)
                click.echo("Interrupted.", err=True)
                sys.exit(EXIT_INTERRUPTED)
            if isinstance(exc, BrokenPipeError) and _stdout_reader_gone():
                # `navlab list | head -1`: the reader has what it wanted; no message, like ls or cat (and the
                # status of the answer, where a verb answers with one: status_if_output_is_cut)
                sys.exit(ctx.meta.get(CUT_STATUS, 0))
            if debug_enabled():
                raise
            status, line = describe_error(exc)
            click.echo(line, err=True)
            sys.exit(status)


@contextlib.contextmanager
def heading_notes():
    """Within it, a heading beyond ±2π (``navlab.angles.HeadingWarning``, from the flags or a world
    file) prints one ``note: ...`` line on standard error, each distinct one once, instead of
    Python's two-line warning naming a line of navlab's own code."""
    import warnings

    from ..angles import HeadingWarning

    said = set()
    with warnings.catch_warnings():
        shown = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):
            if not issubclass(category, HeadingWarning):
                return shown(message, category, filename, lineno, file, line)
            if str(message) not in said:
                said.add(str(message))
                click.echo(f"note: {message}", err=True)

        warnings.showwarning = show
        warnings.simplefilter("always", HeadingWarning)
        yield


#: every verb: the module (in navlab.cli) and the command object in it, and the one-line help that
#: `navlab --help` shows without importing the module (a verb's imports load only when it runs)
VERBS = {
    "plan": ("plan", "plan_cmd", "Plan a path in SOURCE: a built-in scene, a world or map file."),
    "list": ("listing", "list_cmd", "Every registered part with its description and parameters."),
    "grid": ("grid", "grid_group", "Grid planning on ROS map_server maps, Moving AI maps and mazes."),
    "bench": ("bench", "bench_cmd", "Run a benchmark: an experiment file, a suite, or flags."),
    "sim": ("sim", "sim_cmd", "Simulate a robot driving to a goal, or run an --experiment."),
    "ros": ("ros", "ros_group", "ROS 2 nodes: map_server, sim, pathplanner, ... and the demo."),
}


class LazyNavlabGroup(NavlabGroup):
    """The top-level group, importing a verb's module only when the verb runs."""

    def __call__(self, *args, **kwargs):
        """``main()`` called bare, the way the console script and ``python -m navlab`` call it: this
        process is the command, so a verb that declared it safe (``exits_quickly``) ends it at once
        (:func:`_exit_now`). Any call with arguments, or from a program that is not the command
        (:func:`_is_the_command`), is click's: its SystemExit can be caught."""
        the_command = _is_the_command()  # once per run: main() gets the answer
        if args or kwargs or not the_command:
            return self.main(*args, the_command=the_command, **kwargs)  # what click's __call__ does
        try:
            return self.main(the_command=True)
        except SystemExit as exc:
            if getattr(self._loaded_verb(sys.argv[1:2]), "exits_quickly", False):
                _exit_now(exc.code)
            raise

    def _loaded_verb(self, first: list):
        """The command of the verb named by the first argument (the group takes no option with a value), if its
        module is loaded; never imports one (a verb whose import failed must not fail again here)."""
        if not first or first[0] not in VERBS:
            return None
        module, attr, _ = VERBS[first[0]]
        return getattr(sys.modules.get(f"{__name__}.{module}"), attr, None)

    def list_commands(self, ctx):
        return list(VERBS)

    def get_command(self, ctx, name):
        if name not in VERBS:
            return None
        import importlib

        module, attr, _ = VERBS[name]
        return getattr(importlib.import_module(f".{module}", __name__), attr)

    def format_commands(self, ctx, formatter):
        with formatter.section("Commands"):
            formatter.write_dl([(name, summary) for name, (_, _, summary) in VERBS.items()])


@click.group(cls=LazyNavlabGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="navlab")
def main() -> None:
    """navlab: 2D mobile-robot path planning and navigation.

    Worlds are YAML world files or built-in scene names (see `navlab list`).
    Units are metres and radians unless a flag says otherwise.

    Exit status: 0 on success; 1 when a plan or simulation ended without
    reaching its goal (the output says why) or for an internal error (one
    line, Error: internal error: ...); 2 for bad input (one line, Error:
    ...); 130 after Ctrl-C. Set NAVLAB_DEBUG=1 to see Python tracebacks.

    numpy's BLAS runs on one thread (OPENBLAS_NUM_THREADS=1,
    MKL_NUM_THREADS=1) unless you set one of these, OMP_NUM_THREADS or
    GOTO_NUM_THREADS.
    """


if __name__ == "__main__":  # pragma: no cover
    main()
