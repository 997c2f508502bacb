"""Compile (or load from numba's cache) the kernels a query will use, before it is timed.

A fresh process pays numba's compile or cache-load time on its first call of
each kernel. That time is not planning time: :func:`warm_up` runs a tiny query
of the same planner and sampler so the timed query that follows starts warm.
"""

from __future__ import annotations

import functools
import time


@functools.lru_cache(maxsize=None)
def _warm(planner: str, sampler: str) -> None:
    from .planning import warm_query

    warm_query(planner, sampler)  # a tiny query of either kind, itself not warmed (no recursion)


def warm_up(planner: str = "rrt_star", sampler: str = "uniform") -> float:
    """Warm the kernels of ``planner`` with ``sampler``; return the seconds spent.

    The second and later calls in a process with the same names return at once
    (and report 0 s): the kernels are loaded.
    """
    t0 = time.perf_counter()
    _warm(planner, sampler)
    return time.perf_counter() - t0
