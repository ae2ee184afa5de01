"""Running experiments: the experiment, launching its runs on executors (local processes,
serial, Dask), the worker, checkpoints, run directories, resuming, progress and compile-ahead.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.runs._command_line import closing_lines, main, NO_SCENARIO, summary_lines
    from mazegen.runtime.runs._executors import Executor, LocalExecutor, SerialExecutor
    from mazegen.runtime.runs._experiment import BUILD_FILES, default_run_dir, Experiment, with_overrides
    from mazegen.runtime.runs._launcher import executor_for, ExperimentResult, Job, launch, run_jobs, RunsInterrupted
    from mazegen.runtime.runs._locks import folder_in_use
    from mazegen.runtime.runs._progress import FIRST_COMPILE_NOTE, Reporter, reporter_for
    from mazegen.runtime.runs._results import json_text, RunDirectoryWriter, staged_directory
    from mazegen.runtime.runs._resumable import resumable_experiment
    from mazegen.runtime.runs._warmup import compile_drive_kernels, compile_kernels

__all__ = [
    "BUILD_FILES",
    "Executor",
    "Experiment",
    "ExperimentResult",
    "FIRST_COMPILE_NOTE",
    "Job",
    "LocalExecutor",
    "NO_SCENARIO",
    "Reporter",
    "RunDirectoryWriter",
    "RunsInterrupted",
    "SerialExecutor",
    "closing_lines",
    "compile_drive_kernels",
    "compile_kernels",
    "default_run_dir",
    "executor_for",
    "folder_in_use",
    "json_text",
    "launch",
    "main",
    "reporter_for",
    "resumable_experiment",
    "run_jobs",
    "staged_directory",
    "summary_lines",
    "with_overrides",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_command_line": ["closing_lines", "main", "NO_SCENARIO", "summary_lines"],
        "_executors": ["Executor", "LocalExecutor", "SerialExecutor"],
        "_experiment": ["BUILD_FILES", "default_run_dir", "Experiment", "with_overrides"],
        "_launcher": ["executor_for", "ExperimentResult", "Job", "launch", "run_jobs", "RunsInterrupted"],
        "_locks": ["folder_in_use"],
        "_progress": ["FIRST_COMPILE_NOTE", "Reporter", "reporter_for"],
        "_results": ["json_text", "RunDirectoryWriter", "staged_directory"],
        "_resumable": ["resumable_experiment"],
        "_warmup": ["compile_drive_kernels", "compile_kernels"],
    },
)
