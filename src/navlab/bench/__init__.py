"""Benchmark harness: experiments as data, trials on any executor, rows on
disk as they finish, statistics and a report (``navlab bench``).

The public names load on first use (PEP 562, :func:`navlab.lazy_attributes`),
so ``navlab bench --help``, which reads only the suites' descriptions, does not
import the statistics (scipy.stats: about a second)."""

from .. import lazy_attributes

#: public name -> the module (relative to navlab.bench) that defines it
_LAZY = {"BenchRun": "runner", "run_experiment": "runner", "write_report": "runner", "Cell": "experiment",
         "Component": "experiment", "Experiment": "experiment", "ExperimentError": "experiment",
         "load_experiment": "experiment", "trial_seed": "experiment", "SUITES": "suites"}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = lazy_attributes(__name__, _LAZY)
