"""Launching experiments: their runs on an executor, their run directories and the catalog kept up to date.

The launcher is the only writer of run directories' final files and of the catalog:
workers send back each finished run, and the launcher writes it at once, so a kill
loses no finished run. A first Ctrl-C (or SIGTERM) asks every run to stop after its
current generation and save a checkpoint; a second one aborts.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Iterator
from contextlib import ExitStack, contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mazegen.errors import MazeError, option
from mazegen.fileio import make_folder
from mazegen.runtime import run_kernels
from mazegen.runtime.catalog import Catalog, default_catalog
from mazegen.runtime.runs._checkpoint import CheckpointPolicy, CheckpointShape, CheckpointStore
from mazegen.runtime.engine import RunResult
from mazegen.runtime.runs._executors import EXECUTORS, Executor, LocalExecutor, SerialExecutor, available_cores
from mazegen.runtime.runs._progress import QuietReporter, Reporter, note_first_compile
from mazegen.runtime.runs._results import RunDirectoryWriter
from mazegen.runtime.runs._worker import FinishedRun, RunOutcome, RunTask
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.runs._experiment import Experiment

POLL_SECONDS = 0.1
"""Longest wait for progress before looking for finished runs."""

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@dataclass(frozen=True)
class Job:
    """One experiment to launch.

    Attributes:
        experiment: What to run.
        run_dir: Where to write it, or ``None`` to keep the results in memory only.
        resume: Continue the interrupted run directory ``run_dir``.
        force: Replace an existing ``run_dir``.
        sweep: The settings of the sweep cell it is, for the catalog.
        compile_seconds: Seconds spent compiling its kernels before the launch (``mazegen run`` compiles
            them ahead), counted in the time of run 1's generation 0, as if run 1 had compiled them.
    """

    experiment: Experiment
    run_dir: Path | None = None
    resume: bool = False
    force: bool = False
    sweep: dict[str, Any] | None = None
    compile_seconds: float = 0.0


@dataclass(frozen=True)
class ExperimentResult:
    """What an experiment produced: each run's result and best scenario documents."""

    runs: tuple[RunResult, ...]
    best: tuple[tuple[dict[str, Any], ...], ...]
    run_dir: Path | None


class RunsInterrupted(KeyboardInterrupt):
    """A launch stopped by Ctrl-C; ``run_dirs`` are left to resume (their runs checkpointed)."""

    def __init__(self, run_dirs: list[Path]) -> None:
        super().__init__(", ".join(map(str, run_dirs)))
        self.run_dirs = run_dirs


class _Launched:
    """One job while its runs go: what came back, and where it is written."""

    def __init__(
        self,
        index: int,
        job: Job,
        *,
        label: str,
        catalog: Catalog | None,
        executor: str,
        policy: CheckpointPolicy,
        reporter: Reporter,
        keep_population: bool,
    ) -> None:
        self.job, self.catalog, self.keep_population = job, catalog, keep_population
        settings = job.experiment.problem.spec.evolution
        self.runs = settings.runs
        self.results: dict[int, RunResult] = {}
        self.documents: dict[int, tuple[dict[str, Any], ...]] = {}
        self.directory: RunDirectoryWriter | None = None
        self.experiment_id: int | None = None
        self.tasks: list[RunTask] = []
        if job.run_dir is not None:
            if job.resume:
                self.directory = RunDirectoryWriter.unfinished(job.run_dir)
            else:
                files = job.experiment.start_files()
                self.directory = RunDirectoryWriter.create(job.run_dir, force=job.force, files=files)
        try:
            self._prepare(index, label, executor, policy, reporter)
        except BaseException as error:
            if isinstance(error, Exception):
                self.failed()
            self.close()
            raise

    def _prepare(
        self, index: int, label: str, executor: str, policy: CheckpointPolicy, reporter: Reporter
    ) -> None:
        """Find each run's checkpoint, record the experiment."""
        job, settings = self.job, self.job.experiment.problem.spec.evolution
        build = job.experiment.build_files()
        for run in range(1, self.runs + 1):
            resume_from, done, folder = None, 0, None
            if self.directory is not None:
                store = CheckpointStore(
                    directory=self.directory.checkpoints(run),
                    experiment=build.digest,
                    shape=CheckpointShape.of(job.experiment.problem),
                )
                found, warnings = store.latest()
                for warning in warnings:
                    reporter.note(warning)
                if found is not None:
                    resume_from, done = str(found[0].resolve()), found[1] + 1
                folder = str(store.directory.resolve()) if policy.enabled else None
            task = RunTask(
                (index, run),
                build,
                checkpoints=folder,
                policy=policy,
                resume_from=resume_from,
                prepare_files=self.directory is not None,
                keep_population=self.keep_population,
                waited=job.compile_seconds if run == 1 else 0.0,
            )
            self.tasks.append(task)
            reporter.add_run((index, run), f"{label}run {run}/{self.runs}", settings.generations, done=done)
        if self.catalog is not None and self.directory is not None:
            self.experiment_id = self.catalog.start_experiment(
                run_dir=self.directory.path,
                record=job.experiment.record(),
                sweep=job.sweep,
                executor=executor,
                resumed=job.resume,
            )

    @property
    def complete(self) -> bool:
        return len(self.results) == self.runs

    def _recorded(self) -> tuple[Catalog, int] | None:
        if self.catalog is None or self.experiment_id is None:
            return None
        return self.catalog, self.experiment_id

    def take(self, outcome: RunOutcome) -> None:
        """Write a finished run (and the whole experiment after its last run), or note a stopped one."""
        run, recorded = outcome.key[1], self._recorded()
        if not isinstance(outcome, FinishedRun):
            if recorded is not None:
                recorded[0].run_stopped(recorded[1], run, outcome.generation)
            return
        if self.directory is not None:
            assert outcome.files is not None, "tasks of a run directory prepare their files"
            self.directory.write_run(run, outcome.files)
            if recorded is not None:
                run_path = self.directory.run_path(run)
                recorded[0].record_run(recorded[1], run, outcome.result, outcome.documents, run_path)
        self.results[run] = outcome.result
        self.documents[run] = outcome.documents
        if self.complete:
            # In this order, so that a kill anywhere leaves a directory that resume ends.
            if self.directory is not None:
                self.directory.finish([self.results[number] for number in range(1, self.runs + 1)])
            if recorded is not None:
                recorded[0].finish_experiment(recorded[1], status="finished")
            if self.directory is not None:
                self.directory.drop_checkpoints()

    def close(self) -> None:
        """Release the run directory."""
        if self.directory is not None:
            self.directory.close()

    def stopped(self) -> None:
        """Record the experiment as interrupted."""
        recorded = self._recorded()
        if recorded is not None:
            recorded[0].finish_experiment(recorded[1], status="interrupted")

    def failed(self) -> None:
        """Record the experiment as failed (an error, not a stop); a new directory without any
        progress to resume is deleted, so that the next try needs no ``--force``."""
        recorded = self._recorded()
        if recorded is not None:
            with suppress(MazeError):  # the error being raised says more than a catalog that cannot say it
                recorded[0].finish_experiment(recorded[1], status="failed")
        if self.directory is not None and not self.job.resume and not self.directory.started_anything:
            self.directory.discard()

    def result(self) -> ExperimentResult:
        numbers = range(1, self.runs + 1)
        return ExperimentResult(
            tuple(self.results[n] for n in numbers),
            tuple(self.documents[n] for n in numbers),
            self.job.run_dir,
        )


@contextmanager
def _stop_on_signals(executor: Executor, reporter: Reporter) -> Iterator[None]:
    """Turn the first Ctrl-C or SIGTERM into a stop request; the next one acts as usual."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {number: signal.getsignal(number) for number in STOP_SIGNALS}

    def stop(number: int, frame: Any) -> None:
        for restored, handler in previous.items():
            signal.signal(restored, handler)
        reporter.note(
            "stopping: each run saves a checkpoint after its current generation (Ctrl-C again to abort)"
        )
        executor.request_stop()

    for number in STOP_SIGNALS:
        signal.signal(number, stop)
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def launch(
    jobs: list[Job],
    *,
    executor: Executor,
    reporter: Reporter | None = None,
    catalog: Catalog | None = None,
    policy: CheckpointPolicy | None = None,
    keep_populations: bool = True,
) -> list[ExperimentResult]:
    """Run every run of ``jobs`` on ``executor``, writing run directories and the catalog as runs finish.

    Args:
        jobs: The experiments, with where to write them.
        executor: Where runs execute.
        reporter: Progress display.
        catalog: The catalog to record experiments with a run directory in.
        policy: When runs checkpoint (the default: every 30 s, and the last generation).
        keep_populations: Send each run's final population back to the results; without, the
            results hold statistics and documents only (the populations are in the run directories).

    Raises:
        RunsInterrupted: after a Ctrl-C, once every run has stopped.
        MazeError: for a user's mistake (an existing directory, a damaged checkpoint…).
    """
    reporter = reporter or QuietReporter()
    policy = policy or CheckpointPolicy()
    if not executor.name.startswith("dask"):  # a cluster's workers have caches of their own
        kernels = {kernel for job in jobs for kernel in run_kernels(job.experiment.problem.spec)}
        note_first_compile(reporter, kernels=tuple(sorted(kernels)))
    launched: list[_Launched] = []
    try:
        for index, job in enumerate(jobs):
            label = f"{printable(job.run_dir.name)} " if len(jobs) > 1 and job.run_dir is not None else ""
            launched.append(
                _Launched(
                    index,
                    job,
                    label=label,
                    catalog=catalog,
                    executor=executor.name,
                    policy=policy,
                    reporter=reporter,
                    keep_population=keep_populations,
                )
            )
        with _stop_on_signals(executor, reporter):
            _collect(launched, executor, reporter)
    except BaseException as error:
        for item in launched:
            if item.complete:
                continue
            if isinstance(error, Exception):
                item.failed()
            else:
                item.stopped()
        raise
    finally:
        for item in launched:
            item.close()
    unfinished = [item for item in launched if not item.complete]
    for item in unfinished:
        item.stopped()
    if unfinished:
        raise RunsInterrupted([item.job.run_dir for item in unfinished if item.job.run_dir is not None])
    return [item.result() for item in launched]


def _collect(launched: list[_Launched], executor: Executor, reporter: Reporter) -> None:
    """Submit every run, then take their outcomes as they come; on any error, stop the others first."""

    def take(outcome: RunOutcome) -> None:
        launched[outcome.key[0]].take(outcome)
        if isinstance(outcome, FinishedRun):
            reporter.finish_run(outcome.key)

    try:
        for item in launched:
            for task in item.tasks:
                executor.submit(task)
        while executor.pending:
            for outcome in executor.poll(POLL_SECONDS, reporter.generation):
                take(outcome)
    except BaseException:
        executor.request_stop()
        _drain(executor, take)
        raise


def _drain(executor: Executor, take: Any) -> None:
    """Collect the outcomes of runs told to stop, keeping those that finished; later errors are dropped
    (the first one is being raised)."""
    while executor.pending:
        try:
            for outcome in executor.poll(POLL_SECONDS, lambda key, stats: None):
                take(outcome)
        except Exception:
            continue


def run_jobs(
    jobs: list[Job],
    *,
    executor: str | Executor = "serial",
    workers: int | None = None,
    scheduler: str | None = None,
    catalog: bool | str | os.PathLike[str] = True,
    checkpoint_every: int | None = None,
    reporter: Reporter | None = None,
    keep_populations: bool = True,
) -> list[ExperimentResult]:
    """Launch ``jobs`` the way the API, the commands and generated builds ask for it.

    Args:
        jobs: The experiments.
        executor: An executor, or ``serial``, ``local`` or ``dask`` (see :func:`executor_for`).
        workers: Local worker processes (default: the cores).
        scheduler: The Dask scheduler's address.
        catalog: A catalog file, ``True`` for ``catalog.sqlite`` beside the first run directory,
            or ``False`` for none; jobs without a run directory are never catalogued.
        checkpoint_every: Checkpoint every this many generations (0: never; default: every 30 s).
        reporter: Progress display.
        keep_populations: See :func:`launch`.
    """
    runs = sum(job.experiment.problem.spec.evolution.runs for job in jobs)
    with ExitStack() as owned:
        if not isinstance(executor, Executor):  # first: a wrong executor option touches no file
            executor = owned.enter_context(
                executor_for(executor, runs=runs, workers=workers, scheduler=scheduler)
            )
        opened = _open_catalog(jobs, catalog)
        if opened is not None:
            owned.callback(opened.close)
        return launch(
            jobs,
            executor=executor,
            reporter=reporter,
            catalog=opened,
            policy=CheckpointPolicy(every=checkpoint_every),
            keep_populations=keep_populations,
        )


def _open_catalog(jobs: list[Job], catalog: bool | str | os.PathLike[str]) -> Catalog | None:
    directories = [job.run_dir for job in jobs if job.run_dir is not None]
    if not directories or catalog is False:
        return None
    if not isinstance(catalog, bool):
        return Catalog.open(Path(catalog), create=True)  # a folder the user named must exist already
    default = default_catalog(directories[0])
    make_folder(default.parent)
    return Catalog.open(default, create=True)


def executor_for(
    kind: str, *, runs: int, workers: int | None = None, scheduler: str | None = None
) -> Executor:
    """The executor a command line or API call asks for.

    Args:
        kind: ``local`` (worker processes), ``serial`` (this process) or ``dask``.
        runs: Runs to execute: local uses no more workers than runs, and none for one run.
        workers: Local worker processes (default: the cores).
        scheduler: The Dask scheduler's address (``tcp://HOST:PORT``), for ``dask`` only.

    Raises:
        MazeError: for an unknown executor, a scheduler without ``dask`` or the reverse,
            or a Dask cluster that cannot be reached.
    """
    if kind not in EXECUTORS:
        raise MazeError(f"unknown executor '{kind}' (choose {', '.join(EXECUTORS)})")
    if (kind == "dask") != (scheduler is not None):
        dask, scheduler = option("executor dask"), option("scheduler")
        raise MazeError(f"{scheduler} goes with {dask}, and {dask} needs {scheduler}")
    if kind == "dask":
        from mazegen.runtime.runs._dask_executor import DaskExecutor  # the optional 'dask' extra

        return DaskExecutor(scheduler=str(scheduler))
    count = min(workers or available_cores(), runs)
    if workers is not None and workers < 1:
        raise MazeError(f"{option('workers')} must be at least 1, got {workers}")
    return SerialExecutor() if kind == "serial" or count <= 1 else LocalExecutor(workers=count)
