"""Running experiments: the experiment, launching its runs on executors (local processes,
serial, Dask), the worker, checkpoints, run directories, resuming, progress and compile-ahead.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.runs.experiment import BUILD_FILES, Experiment, default_run_dir
    from mazegen.runtime.runs.launcher import (
        ExperimentResult,
        Job,
        RunsInterrupted,
        executor_for,
        launch,
        run_jobs,
    )
    from mazegen.runtime.runs.executors import Executor, LocalExecutor, SerialExecutor
    from mazegen.runtime.runs.results import RunDirectoryWriter
    from mazegen.runtime.runs.resumable import resumable_experiment
    from mazegen.runtime.runs.progress import Reporter, reporter_for
    from mazegen.runtime.runs.warmup import compile_kernels
    from mazegen.runtime.runs.command_line import main

__all__ = [
    "BUILD_FILES",
    "Executor",
    "Experiment",
    "ExperimentResult",
    "Job",
    "LocalExecutor",
    "Reporter",
    "RunDirectoryWriter",
    "RunsInterrupted",
    "SerialExecutor",
    "compile_kernels",
    "default_run_dir",
    "executor_for",
    "launch",
    "main",
    "reporter_for",
    "resumable_experiment",
    "run_jobs",
]

__getattr__ = lazy_names(
    __name__,
    {
        "experiment": ["BUILD_FILES", "Experiment", "default_run_dir"],
        "launcher": ["ExperimentResult", "Job", "RunsInterrupted", "executor_for", "launch", "run_jobs"],
        "executors": ["Executor", "LocalExecutor", "SerialExecutor"],
        "results": ["RunDirectoryWriter"],
        "resumable": ["resumable_experiment"],
        "progress": ["Reporter", "reporter_for"],
        "warmup": ["compile_kernels"],
        "command_line": ["main"],
    },
)
