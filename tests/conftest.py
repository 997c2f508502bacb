import os
import sys

os.environ.setdefault("MPLBACKEND", "Agg")

# Python's bytecode cache, for this run and every process it starts. This machine's environment sets
# PYTHONDONTWRITEBYTECODE=1 (as many container images do; CI runs with it too): then each of the suite's several
# hundred Python processes (navlab commands, bench workers, ROS nodes) compiled navlab's sources anew, and
# each pytest-xdist worker rewrote every test module's asserts again (12.8 s of CPU to collect, 5.7 s
# with the cache). Set here, before the workers start, they and everything they start inherit it.
if os.environ.pop("PYTHONDONTWRITEBYTECODE", None) is not None:
    sys.dont_write_bytecode = False

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# Property tests (tests/fuzz). The default profile is what CI runs: derandomized
# (the same examples every run, so a failure is reproducible and the suite cannot
# turn red at random), a bounded number of examples, no per-example deadline
# (the first call compiles numba kernels). `--hypothesis-profile=long` searches
# ten times more, with fresh random examples each run, for local bug hunting.
_COMMON = dict(deadline=None, print_blob=True,
               suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much])
settings.register_profile("default", max_examples=40, derandomize=True, database=None, **_COMMON)
settings.register_profile("ci", parent=settings.get_profile("default"))
settings.register_profile("long", max_examples=400, derandomize=False, **_COMMON)
settings.load_profile(os.environ.get("NAVLAB_HYPOTHESIS_PROFILE", "default"))


def _compile_each_kernel_once_across_workers():
    """On a cold numba cache, a kernel that two pytest-xdist workers need at
    about the same time was compiled by both (Hybrid A*'s search, the tree's
    grow: 20-25 s of CPU each, on 2 cores). Here a cached dispatcher's compile
    takes a file lock named after its function first: the second worker waits
    for the first, then finds the kernel in the cache and loads it. Numba's own
    in-process compiler lock is taken before the file lock, so threads of one
    worker cannot cross each other; across workers the locks follow the
    (acyclic) call graph, a caller's before its callees', and cannot cross
    either. ``NAVLAB_TEST_COMPILE_LOCKS=0`` turns it off."""
    if os.environ.get("NAVLAB_TEST_COMPILE_LOCKS", "1") == "0":
        return
    import fcntl
    import hashlib
    import tempfile

    from numba.core import sigutils
    from numba.core.caching import NullCache
    from numba.core.compiler_lock import global_compiler_lock
    from numba.core.dispatcher import Dispatcher

    folder = os.path.join(tempfile.gettempdir(), f"navlab-test-compile-locks-{os.getuid()}")
    os.makedirs(folder, exist_ok=True)
    compile_here = Dispatcher.compile

    def compile_once(self, sig):
        with global_compiler_lock:
            args, _ = sigutils.normalize_signature(sig)
            if tuple(args) in self.overloads or isinstance(self._cache, (NullCache, type(None))):
                return compile_here(self, sig)  # loaded already, or nothing another process could share
            func = self.py_func
            name = hashlib.sha1(f"{func.__module__}.{func.__qualname__}:{func.__code__.co_filename}".encode())
            with open(os.path.join(folder, name.hexdigest()), "a") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes, or the process dies
                return compile_here(self, sig)

    Dispatcher.compile = compile_once


_compile_each_kernel_once_across_workers()


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


def pytest_collection_modifyitems(config, items):
    """The documented-commands test first in a plain run. Under pytest-xdist
    (``--dist loadfile``) xdist hands out files by test count, the most first,
    and this order only breaks ties: the documented-commands test (ten tests,
    a third of the suite's CPU) starts partway through the run, once the other
    files have compiled most kernels. Deliberately: started first on a fresh
    clone (``--no-loadscope-reorder``, session 26), its commands compiled the
    same kernels again, each in its own process, beside the workers (the
    compile lock above is only in pytest's processes): 1 160 -> 1 340 s of CPU
    and 567 -> 653 s for the suite."""
    items.sort(key=lambda item: item.nodeid.split("::")[0] != "tests/test_documented_commands.py")


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one worker per core, plus one for the documented-commands
    test, whose worker only waits on its commands' processes (they use the
    cores); without it the other files share one worker fewer than the cores."""
    return (os.cpu_count() or 1) + 1
