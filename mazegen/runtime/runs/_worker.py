"""One run of an experiment, wherever it executes: this process, a local worker process or a Dask worker.

A run is a pure function of the built experiment, its seed and its run number, so a
:class:`RunTask` carries the spec (plain dataclasses) and the build's grammar and fitness
texts (a few KB, which pickle anywhere) rather than a loaded problem, whose fitness module
is loaded again in the worker, once per process and text. What the run reports while it
goes, and whether it is asked to stop, goes through a :class:`Channel` that each executor
provides.
"""

from __future__ import annotations

import hashlib
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from pathlib import Path
from time import perf_counter
from types import ModuleType
from typing import Any, Protocol

import numpy as np

from mazegen.errors import MazeError, option
from mazegen.runtime.runs._checkpoint import (
    CheckpointPolicy,
    CheckpointShape,
    CheckpointStore,
    read_checkpoint,
)
from mazegen.runtime.documents import best_documents
from mazegen.runtime.engine import GenerationStats, RunResult, RunState, evolve
from mazegen.runtime.engine import Problem, compiled_bnf, load_fitness
from mazegen.runtime.runs._locks import writing_checkpoints
from mazegen.runtime.runs._results import run_files
from mazegen.runtime.threads import thread_count, threads
from mazegen.spec import Spec

RunKey = tuple[int, int]
"""(experiment index in the launch, run number from 1)."""


@dataclass(frozen=True)
class BuildFiles:
    """What a run needs of a build directory: the spec (overrides applied), the grammar's and the
    fitness module's texts."""

    spec: Spec
    grammar: str
    fitness: str

    @cached_property
    def digest(self) -> str:
        """Identifies the experiment: checkpoints of another one are refused."""
        hasher = hashlib.sha256()
        for text in (self.spec.to_json(), self.grammar, self.fitness):
            hasher.update(text.encode("utf-8") + b"\0")
        return hasher.hexdigest()[:16]


@dataclass(frozen=True)
class RunTask:
    """One run to execute.

    Attributes:
        key: Which experiment of the launch and which run.
        build: The experiment's build files.
        checkpoints: Absolute folder of the run's checkpoints, or ``None`` for none.
        policy: When to checkpoint.
        resume_from: A checkpoint to continue from, or ``None`` to start afresh.
        threads: numba threads for the run, or ``None`` to keep the process's setting.
        prepare_files: Prepare the run folder's files (see :func:`run_files`).
        keep_population: Send the final population back (else only statistics and documents:
            the population is in the files).
        waited: Seconds spent for the run before it started (its kernels compiled ahead), counted in
            the time of its generation 0.
    """

    key: RunKey
    build: BuildFiles
    checkpoints: str | None = None
    policy: CheckpointPolicy = field(default_factory=CheckpointPolicy)
    resume_from: str | None = None
    threads: int | None = None
    prepare_files: bool = False
    keep_population: bool = True
    waited: float = 0.0

    @property
    def run(self) -> int:
        """Run number, from 1."""
        return self.key[1]


@dataclass(frozen=True)
class FinishedRun:
    """A run that reached its last generation, with its best scenario documents and, if asked, its files."""

    key: RunKey
    result: RunResult
    documents: tuple[dict[str, Any], ...]
    files: dict[str, bytes] | None = None


@dataclass(frozen=True)
class InterruptedRun:
    """A run stopped on request: at ``generation`` (``None``: before starting), ``saved`` if checkpointed."""

    key: RunKey
    generation: int | None
    saved: bool


RunOutcome = FinishedRun | InterruptedRun


class Channel(Protocol):
    """How a run talks to the process that launched it."""

    def progress(self, key: RunKey, stats: GenerationStats, *, flush: bool) -> None:
        """Report one generation's statistics (``flush``: the run's last, to send at once)."""

    def stop_requested(self) -> bool:
        """Whether the launcher asks runs to stop (Ctrl-C) at the end of the current generation."""


class _Stopped(Exception):
    def __init__(self, generation: int, saved: bool) -> None:
        super().__init__(generation)
        self.generation, self.saved = generation, saved


def run_rng(seed: int, run: int) -> np.random.Generator:
    """The generator of run ``run`` (from 1): the ``run``-th child of ``SeedSequence(seed)``."""
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(run - 1,)))


def problem_of(build: BuildFiles) -> Problem:
    """The problem of a build; its grammar and fitness module are loaded once per process and text."""
    grammar = compiled_bnf(build.grammar, "grammar.bnf", build.spec.scenario.elements, build.spec.row_tokens)
    module = _fitness_module(build.fitness)
    return Problem.assemble(build.spec, grammar, module, Path(module.__file__ or ".").parent)


@lru_cache(maxsize=8)
def _fitness_module(text: str) -> ModuleType:
    with tempfile.TemporaryDirectory(prefix="mazegen-worker-") as folder:
        path = Path(folder) / "fitness.py"
        # Loading runs the module from the file, which can go after.
        path.write_text(text, encoding="utf-8")
        return load_fitness(path)


@contextmanager
def kernel_threads(count: int | None) -> Iterator[None]:
    """Run the block's kernels on ``count`` threads (default: as many as in use)."""
    with threads(thread_count() if count is None else count):
        yield


class _Checkpointer:
    """Saves the states a run's policy asks for, the last generation's always, and on a stop."""

    def __init__(self, task: RunTask, last: int) -> None:
        self._store = None
        if task.checkpoints is not None:
            self._store = CheckpointStore(directory=Path(task.checkpoints), experiment=task.build.digest)
        self._policy, self._last = task.policy, last
        self._saved_at = perf_counter()

    def after(self, state: RunState, *, stopping: bool) -> bool:
        """Save ``state`` if due; return whether it is saved."""
        if self._store is None:
            return False
        now = perf_counter()
        if (
            stopping
            or state.generation == self._last
            or self._policy.due(state.generation, now - self._saved_at)
        ):
            self._store.save(state)
            self._saved_at = now
            return True
        return False


@contextmanager
def _writing_checkpoints(task: RunTask) -> Iterator[None]:
    """Hold the run directory's checkpoints while the run may write there."""
    if task.checkpoints is None:
        yield
        return
    folder = Path(task.checkpoints).parent
    if not folder.is_dir():
        # The message holds the path: exceptions cross back to the launcher by pickling.
        raise MazeError(
            f"{folder.parent}: a worker cannot see the run directory; checkpoints need "
            f"a folder shared with the workers (or {option('checkpoint_every 0')})"
        )
    with writing_checkpoints(folder):
        yield


def run_task(task: RunTask, channel: Channel) -> RunOutcome:
    """Run (or continue) one run to its end, or to a requested stop.

    Raises:
        MazeError: for a checkpoint that cannot be read or a run directory the worker cannot see.
    """
    if channel.stop_requested():
        return InterruptedRun(task.key, None, False)
    with kernel_threads(task.threads), _writing_checkpoints(task):
        problem = problem_of(task.build)
        settings = problem.spec.evolution
        checkpointer = _Checkpointer(task, settings.generations)
        resume = None
        if task.resume_from is not None:
            shape = CheckpointShape.of(problem)
            resume = read_checkpoint(Path(task.resume_from), experiment=task.build.digest, shape=shape)

        def on_generation(state: RunState) -> None:
            last = state.generation == settings.generations
            channel.progress(task.key, state.stats[-1], flush=last)
            stopping = not last and channel.stop_requested()
            saved = checkpointer.after(state, stopping=stopping)
            if stopping:
                raise _Stopped(state.generation, saved)

        rng = run_rng(settings.seed, task.run)
        try:
            result = evolve(
                problem, settings, rng, resume=resume, on_generation=on_generation, waited=task.waited
            )
        except _Stopped as stopped:
            return InterruptedRun(task.key, stopped.generation, stopped.saved)
        origin = {"seed": settings.seed, "run": task.run, "generation": settings.generations}
        documents = best_documents(problem, result, count=settings.best, origin=origin)
    files = run_files(result, documents, problem.spec.arena.base) if task.prepare_files else None
    if not task.keep_population:
        result = RunResult(result.codons[:0], result.genes[:0], result.fitness[:0], result.stats)
    return FinishedRun(task.key, result, documents, files)
