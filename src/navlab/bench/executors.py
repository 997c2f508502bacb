"""Where trials run: in this process, in a local process pool, or on a Dask
cluster. Each executor yields one row per trial as trials finish; the rows
do not depend on which executor computed them (seeds travel with the trials).
"""

from __future__ import annotations

import contextlib
import glob
import logging
import os
import shutil
import signal
import tempfile
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import Any, Callable, Dict, Iterator, List, Optional

from ..registry import Registry
from ..warmup import claim_warm_up_role
from .experiment import ExperimentError
from .trial import error_fields, identity_fields, run_trial

Spec = Dict[str, Any]
EXECUTORS: Registry[Callable[..., Iterator[Dict[str, Any]]]] = Registry("executor")


def crash_row(spec: Spec, message: str) -> Dict[str, Any]:
    """The row of a trial whose worker died (no Python traceback exists)."""
    return identity_fields(spec) | error_fields(message)


@EXECUTORS.register("serial")
def serial(specs: List[Spec], jobs: Optional[int] = None, scheduler: Optional[str] = None,
           trial: Callable[[Spec], Dict[str, Any]] = run_trial) -> Iterator[Dict[str, Any]]:
    """Run the trials one after another in this process."""
    for spec in specs:
        yield trial(spec)


@EXECUTORS.register("process")
def process(specs: List[Spec], jobs: Optional[int] = None, scheduler: Optional[str] = None,
            trial: Callable[[Spec], Dict[str, Any]] = run_trial) -> Iterator[Dict[str, Any]]:
    """A local process pool, all cores by default.

    At most two trials per worker are in flight, so when a worker dies (a
    crash in compiled code, the OOM killer) only those few are in doubt:
    each is then rerun alone in a fresh process, and the one that kills its
    process again is recorded as an ``ERROR`` row. The run goes on.
    """
    jobs = jobs or os.cpu_count() or 1
    queue = list(reversed(specs))
    in_doubt: List[Spec] = []
    remove_abandoned_pool_folders()
    with tempfile.TemporaryDirectory(prefix=POOL_PREFIX) as folder:
        with open(os.path.join(folder, OWNER_FILE), "w") as f:
            f.write(str(os.getpid()))
        yield from _pool_rounds(queue, in_doubt, jobs, trial, os.path.join(folder, "warm-up.lock"))


#: the process pool's scratch folders in the temporary directory, and the file naming their owner
POOL_PREFIX, OWNER_FILE = "navlab-pool-", "owner.pid"
#: [s] how often a worker looks whether its parent is still there
PARENT_POLL_S = 1.0


def remove_abandoned_pool_folders() -> int:
    """Delete pool folders left by runs that were killed (their owner pid is gone); returns how many."""
    removed = 0
    for folder in glob.glob(os.path.join(tempfile.gettempdir(), POOL_PREFIX + "*")):
        try:
            with open(os.path.join(folder, OWNER_FILE)) as f:
                owner = int(f.read().strip())
        except (OSError, ValueError):
            continue  # not ours to judge (no owner recorded yet, or unreadable)
        if not _alive(owner):
            shutil.rmtree(folder, ignore_errors=True)
            removed += 1
    return removed


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True  # someone else's process
    return True


def _worker_start(lock_path: Optional[str], parent: int) -> None:
    """Pool worker set-up: leave Ctrl-C to the parent, die with it, then the warm-up role (with ``lock_path``).

    A killed ``navlab bench`` left its workers running with PPID 1 (and, with
    the old flock, holding the folder's lock). Linux's PR_SET_PDEATHSIG sends
    the worker SIGKILL when its parent dies; a watchdog thread that polls the
    parent's pid covers other systems and a parent that died before the
    signal was armed. A terminal's Ctrl-C reaches the whole process group: the
    parent stops its workers (:func:`_stop_workers`), and an idle worker that
    took it too printed "Process ForkProcess-4: ... KeyboardInterrupt" above
    the resume line (newcomer, session 30).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):  # forked with Ctrl-C blocked (_Pool.submit): ignored from here on
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    _die_with_parent()
    # (the parent by pid, not as getppid(): under the forkserver start method, the default on Linux from
    # Python 3.14, a worker's parent is the fork server, and every worker exited here: review, session 30)
    if not _alive(parent):
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True, name="navlab-parent-watch").start()
    if lock_path is not None:
        claim_warm_up_role(lock_path)


class _Pool(ProcessPoolExecutor):
    """A process pool that forks its workers (at a submit) with Ctrl-C blocked in the forking thread, so that a
    worker cannot take one before :func:`_worker_start` ignores it: a terminal's Ctrl-C as the report's plot
    pool started printed "Exception ignored in: <function _releaseLock>" and a KeyboardInterrupt traceback, from
    a worker still in its fork handlers (1 in 6 double Ctrl-Cs, session 30)."""

    def submit(self, fn, /, *args, **kwargs):
        with _ctrl_c_blocked():
            return super().submit(fn, *args, **kwargs)


@contextlib.contextmanager
def _ctrl_c_blocked():
    """SIGINT blocked in this thread within the block (where the system can): a process forked here inherits
    the mask, so a terminal's Ctrl-C, sent to the whole process group, cannot reach it before it sets its own
    handling."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@contextlib.contextmanager
def stoppable_pool(jobs: int, lock_path: Optional[str] = None, mp_context=None) -> Iterator[ProcessPoolExecutor]:
    """A process pool for this block, its workers set up by :func:`_worker_start` (they die with this process
    and leave Ctrl-C to it; ``lock_path``: the warm-up role's lock) and killed, not waited for, when the block
    or the wait for its workers to finish ends by an exception (a Ctrl-C). The report's plot pool was a plain
    one: a double Ctrl-C while it drew hung ``navlab bench`` for good (5 of 7 tries), and its workers outlived
    a ``kill -9`` of the run (newcomer, session 30)."""
    pool = _Pool(jobs, mp_context=mp_context, initializer=_worker_start, initargs=(lock_path, os.getpid()))
    try:
        yield pool
        pool.shutdown(wait=True)
    except BaseException:  # Ctrl-C, an error, or the consumer of a generator stopped
        _stop_workers(pool)
        raise


def _die_with_parent() -> None:
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        pass  # not Linux: the watchdog alone


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(PARENT_POLL_S)
        if not _alive(parent):
            os._exit(1)


def _pool_rounds(queue: List[Spec], in_doubt: List[Spec], jobs: int, trial: Callable[[Spec], Dict[str, Any]],
                 lock_path: str) -> Iterator[Dict[str, Any]]:
    while queue:
        with stoppable_pool(jobs, lock_path) as pool:  # (Ctrl-C, or the consumer stopped: no wait for trials)
            running: Dict[Any, Spec] = {}
            try:
                while queue or running:
                    while queue and len(running) < 2 * jobs:
                        running[pool.submit(trial, queue[-1])] = queue[-1]
                        queue.pop()
                    done, _ = wait(running, return_when=FIRST_COMPLETED)
                    for fut in done:
                        spec = running.pop(fut)
                        try:
                            yield fut.result()
                        except BrokenProcessPool:
                            in_doubt.append(spec)
            except BrokenProcessPool:
                pass  # submit() on a broken pool; those in flight are handled below
            in_doubt.extend(running.values())
        for spec in in_doubt:
            yield _alone(spec, trial)
        in_doubt = []


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """End the pool now: cancel the queued trials and kill the workers, whose trials in flight are lost
    anyway (their rows are never written; ``--resume`` runs them). Shutting down without waiting left the
    workers to finish their trials, and a second Ctrl-C landing in the joins that followed (the pool's
    ``with``, then concurrent.futures' exit-time join of its manager thread) hung the run for good: the
    main thread waiting on one worker, the manager on another, each blocked on the pool's pipes (attack,
    session 29: 4 of 11 double Ctrl-Cs). ``_processes`` is the executor's own record of its workers
    (Python 3.14 adds ``terminate_workers`` for this)."""
    # a second Ctrl-C while the workers are stopped waits until they are (it cut the stop short, leaving the
    # pool's manager to join at exit: session 29), then takes effect
    with _ctrl_c_held():
        workers = list((getattr(pool, "_processes", None) or {}).values())
        # (read before the shutdown, which drops the executor's reference: read after it, this was None and the
        # manager was never joined; concurrent.futures' exit-time hook then raced it for its wake-up pipe, an
        # "OSError: Bad file descriptor" traceback under the resume line in 1 of 25 double Ctrl-Cs at load 5)
        manager = getattr(pool, "_executor_manager_thread", None)
        results = getattr(pool, "_result_queue", None)  # (dropped by the shutdown too)
        pool.shutdown(wait=False, cancel_futures=True)
        for worker in workers:
            try:
                worker.kill()
            except (OSError, ValueError, AttributeError):
                pass  # gone already, or closed
        for worker in workers:
            try:
                worker.join(5.0)
            except (OSError, ValueError, AssertionError):
                pass
        # and the pool's manager thread, which then closes its wake-up pipe: left running, concurrent.futures'
        # exit-time hook wrote to that pipe after the manager had gone, a BrokenPipeError traceback under the
        # resume line (session 29)
        if manager is not None:
            manager.join(MANAGER_JOIN_S)
            if manager.is_alive() and results is not None:
                _complete_a_torn_result(manager, results)


#: [s] how long the pool's stop waits for its manager thread before it looks for a torn result, and then
#: at most how long it feeds the result pipe
MANAGER_JOIN_S, UNBLOCK_S = 0.5, 5.0


def _complete_a_torn_result(manager: threading.Thread, results) -> None:
    """Unblock a pool's manager thread stuck reading a result a killed worker had half written.

    A worker killed in the middle of sending its result leaves the message's header and part of its body in
    the result pipe; the manager then waits for the rest for ever (this process holds the pipe's other end
    too, so no end of file comes), and Python's exit joins the manager: ``navlab bench`` printed its resume
    line and never ended (1 of 155 double Ctrl-Cs at load 5-7; faulthandler's stacks showed the manager in
    ``Connection._recv``, session 30). Zero bytes written into the pipe complete the message, which does not
    unpickle; the manager then takes the pool for broken and ends, as it would for a worker that died.
    """
    try:
        fd = results._writer.fileno()
        os.set_blocking(fd, False)
    except (AttributeError, OSError, ValueError):
        return
    filler = bytes(1 << 16)
    end = time.monotonic() + UNBLOCK_S
    while manager.is_alive() and time.monotonic() < end:
        try:
            os.write(fd, filler)
        except BlockingIOError:
            pass  # the pipe is full until the manager reads on
        except OSError:
            return
        manager.join(0.05)


@contextlib.contextmanager
def _ctrl_c_held():
    """Within it, a Ctrl-C is only noted; it is raised when the block ends (on the main thread; elsewhere
    signals are not delivered and nothing changes)."""
    if threading.current_thread() is not threading.main_thread() or signal.getsignal(signal.SIGINT) is None:
        yield  # (None: a handler set outside Python, which could not be put back)
        return
    noted = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: noted.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if noted:
            signal.raise_signal(signal.SIGINT)


def _alone(spec: Spec, trial: Callable[[Spec], Dict[str, Any]]) -> Dict[str, Any]:
    with stoppable_pool(1) as solo:  # (Ctrl-C: as for the pool, not a wait for the trial to end)
        try:
            return solo.submit(trial, spec).result()
        except BrokenProcessPool:
            return crash_row(spec, "the worker process running this trial died (crash or killed); "
                                   "it died again when the trial was rerun alone")


#: seconds to wait for a Dask scheduler before giving up
DASK_CONNECT_TIMEOUT = 5


def check_executor(name: str, scheduler: Optional[str] = None) -> None:
    """Fail in one line, before any trial runs, when ``name`` cannot run here:
    the Dask extra is missing, or its scheduler cannot be reached."""
    EXECUTORS.get(name)
    if name != "dask":
        if scheduler is not None:
            raise ExperimentError("--scheduler is for --executor dask only")
        return
    try:
        import distributed  # noqa: F401
    except ImportError:
        from ..extras import install_command

        raise ExperimentError(f"the dask executor needs Dask, which is not installed: {install_command('dask')}") \
            from None
    if scheduler is not None:
        _client(scheduler).close()


def _client(scheduler):
    """A Dask client, or one line within :data:`DASK_CONNECT_TIMEOUT` seconds.

    Dask's own timeout does not cover every way an address can fail: a port
    that answers in another protocol (SSH's banner was read as a 2.82 EiB
    message length) or that accepts and never answers (an HTTP server) hung or
    gave a baffling message. The connection is therefore made in a daemon
    thread and abandoned at the deadline: a daemon thread, because Python
    joins every other thread at exit (a ``ThreadPoolExecutor``'s too), and a
    connection that never ends kept the process alive after its error line
    for as long as the far end held the line.
    """
    import threading

    from distributed import Client

    if not isinstance(scheduler, str):  # a LocalCluster this process started
        return Client(scheduler, timeout=DASK_CONNECT_TIMEOUT)
    outcome = {}

    def connect():
        try:
            outcome["client"] = Client(scheduler, timeout=DASK_CONNECT_TIMEOUT)
        except BaseException as exc:  # noqa: BLE001 - handed to the caller below
            outcome["error"] = exc

    attempt = threading.Thread(target=connect, name="navlab-dask-connect", daemon=True)
    attempt.start()
    attempt.join(DASK_CONNECT_TIMEOUT + 1)
    if "client" in outcome:
        return outcome["client"]
    exc = outcome.get("error")
    if exc is None:  # still connecting: abandoned, and not waited for at exit
        raise ExperimentError(f"--scheduler {scheduler}: no Dask scheduler answered within "
                              f"{DASK_CONNECT_TIMEOUT} s (is it a Dask scheduler's address, tcp://HOST:8786?)")
    if isinstance(exc, MemoryError):  # another protocol's bytes read as a message length
        detail = "it answered, but not in Dask's protocol"
    else:
        detail = str(exc).splitlines()[0][:200] if str(exc) else type(exc).__name__
    raise ExperimentError(f"--scheduler {scheduler}: not a Dask scheduler, or not reachable ({detail})")


@EXECUTORS.register("dask")
def dask(specs: List[Spec], jobs: Optional[int] = None, scheduler: Optional[str] = None,
         trial: Callable[[Spec], Dict[str, Any]] = run_trial) -> Iterator[Dict[str, Any]]:
    """A Dask cluster: the scheduler at ``scheduler`` (``tcp://host:8786``), or
    a LocalCluster with ``jobs`` workers when none is given. Needs the
    ``dask`` extra, and navlab installed on every worker
    (:func:`check_executor` says so before anything runs)."""
    check_executor("dask")
    from distributed import LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        # (its workers' warnings, "Async instruction ... ended with CancelledError" for each trial a Ctrl-C
        # cancelled, came above the resume line: newcomer, session 30; errors still show)
        cluster = LocalCluster(n_workers=jobs or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR,
                               preload=["navlab.bench.dask_worker"])  # (its workers leave Ctrl-C to this process)
        scheduler = cluster
    client = _client(scheduler)
    stopped = False
    try:
        futures = client.map(trial, specs, pure=False)
        by_key = {f.key: s for f, s in zip(futures, specs)}
        for fut in as_completed(futures):
            try:
                yield fut.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker and the like: record and go on
                yield crash_row(by_key[fut.key], f"Dask could not run this trial: {type(exc).__name__}: {exc}")
    except BaseException:  # Ctrl-C, or the consumer stopped
        stopped = True
        raise
    finally:
        # Closing takes seconds: a second Ctrl-C waits for it (it broke the close with a CancelledError
        # traceback from distributed.client, newcomer, session 30), and after a stop the cancellations it
        # logs are not news
        with _ctrl_c_held(), (_quiet("distributed") if stopped else contextlib.nullcontext()):
            client.close()
            if cluster is not None:
                cluster.close()


@contextlib.contextmanager
def _quiet(logger: str):
    """``logger``'s records below CRITICAL dropped within the block."""
    log = logging.getLogger(logger)
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)
