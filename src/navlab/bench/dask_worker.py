"""Dask's preload for the workers of a LocalCluster that ``navlab bench --executor dask`` starts itself.

A terminal's Ctrl-C goes to the whole process group, the cluster's worker processes too: each printed a
``KeyboardInterrupt`` traceback from its asyncio loop above the resume line (newcomer, session 30). The run's
own process handles the Ctrl-C and closes the cluster, which stops the workers; so they ignore it.
"""

import signal


def dask_setup(worker) -> None:
    """Run by Dask in each worker process as it starts (on its main thread, where handlers are set)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
