import os

os.environ.setdefault("MPLBACKEND", "Agg")

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


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


def pytest_collection_modifyitems(config, items):
    """The documented-commands test first: it is the longest file (every
    document's commands, mostly waiting on simulated clocks and ROS nodes), so
    under pytest-xdist it starts at once and the other files fill the other
    workers around it instead of leaving it to run alone at the end."""
    items.sort(key=lambda item: item.nodeid.split("::")[0] != "tests/test_documented_commands.py")


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: one worker per core, plus one for the documented-commands
    test, whose worker only waits on its commands' processes (they use the
    cores); without it the other files share one worker fewer than the cores."""
    return (os.cpu_count() or 1) + 1
