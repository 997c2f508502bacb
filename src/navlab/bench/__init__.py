"""Benchmark harness: experiments as data, trials on any executor, rows on
disk as they finish, statistics and a report (``navlab bench``)."""

from .experiment import Cell, Component, Experiment, ExperimentError, load_experiment, trial_seed
from .runner import BenchRun, run_experiment, write_report
from .suites import SUITES

__all__ = ["BenchRun", "Cell", "Component", "Experiment", "ExperimentError", "SUITES", "load_experiment",
           "run_experiment", "trial_seed", "write_report"]
