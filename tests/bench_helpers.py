"""Trial functions that misbehave on purpose (importable by worker processes)."""

import os

from navlab.bench.trial import execute, run_trial

CRASH_TRIAL = "-0001"  # suffix of the trial id that kills its worker
RAISE_TRIAL = "-0002"  # suffix of the trial id whose planner raises


def crashing_trial(spec):
    if spec["trial_id"].endswith(CRASH_TRIAL):
        os._exit(13)  # like a segfault in compiled code: no exception, no traceback
    return run_trial(spec)


def _raising_execute(spec):
    if spec["trial_id"].endswith(RAISE_TRIAL):
        raise RuntimeError("planner blew up")
    return execute(spec)


def raising_trial(spec):
    return run_trial(spec, runner=_raising_execute)
