"""Progress reporting of runs: a Rich bar per run and one over all of them, or nothing.

Evaluations per second are measured where the work is done: a run's bar divides its
evaluations by the seconds its generations took on its worker; the overall bar divides
every run's evaluations by the wall-clock time since the first bar appeared.
A run that must first compile the kernels says so (:func:`note_first_compile`).
"""

from __future__ import annotations

import sys
from collections.abc import Hashable
from time import monotonic
from typing import Protocol

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TaskID, TextColumn, TimeElapsedColumn

from mazegen.runtime import EVERY_RUN_KERNELS
from mazegen.runtime.compiling import RUN_SECONDS, compile_note
from mazegen.runtime.engine import GenerationStats

VISIBLE_RUNS = 16
"""A run's bar shows from its first generation; with more runs than this, it hides again when
the run ends (sweeps launch hundreds)."""


class Reporter(Protocol):
    """What a launch tells about its progress.

    A run is identified by any hashable ``key``; ``done`` generations of a resumed run
    are already complete when its bar appears.
    """

    def add_run(self, key: Hashable, label: str, generations: int, *, done: int = 0) -> None: ...
    def generation(self, key: Hashable, stats: GenerationStats) -> None: ...
    def finish_run(self, key: Hashable) -> None: ...
    def note(self, message: str) -> None: ...
    def close(self) -> None: ...


def reporter_for(*, quiet: bool) -> Reporter:
    """The reporter a command line asks for."""
    return QuietReporter() if quiet else RichReporter()


FIRST_COMPILE_NOTE = compile_note("run", RUN_SECONDS)


def note_first_compile(reporter: Reporter, *, kernels: tuple[str, ...] = EVERY_RUN_KERNELS) -> None:
    """Say why a first run's bars stand still for a while: its ``kernels`` (a run's by default, or
    another command's) are not compiled yet."""
    from mazegen.runtime import kernels_cached

    if not kernels_cached(kernels):
        reporter.note(FIRST_COMPILE_NOTE)


class QuietReporter:
    """Shows no progress (scripts, tests); notes still go to standard error."""

    def add_run(self, key: Hashable, label: str, generations: int, *, done: int = 0) -> None:
        """Ignore."""

    def generation(self, key: Hashable, stats: GenerationStats) -> None:
        """Ignore."""

    def finish_run(self, key: Hashable) -> None:
        """Ignore."""

    def note(self, message: str) -> None:
        """Print ``message`` on standard error."""
        print(message, file=sys.stderr)

    def close(self) -> None:
        """Ignore."""


def _shown(best: float) -> str:
    """A best fitness as a bar shows it: ``-`` while no individual is valid (NaN)."""
    return "-" if best != best else f"{best:g}"


class _Run:
    def __init__(self, task: TaskID) -> None:
        self.task, self.evaluations, self.seconds, self.finished = task, 0, 0.0, False


class RichReporter:
    """A bar per run (generations, best fitness, evaluations/s) under an overall bar, on standard error."""

    def __init__(self, console: Console | None = None) -> None:
        self._progress = Progress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("best {task.fields[best]}"),
            TextColumn("{task.fields[rate]} evaluations/s"),
            TimeElapsedColumn(),
            console=console or Console(stderr=True),
            transient=False,
        )
        self._runs: dict[Hashable, _Run] = {}
        self._overall: TaskID | None = None
        self._started = 0.0
        self._evaluations = 0
        self._best = float("nan")  # over every run's generations so far

    def add_run(self, key: Hashable, label: str, generations: int, *, done: int = 0) -> None:
        """Open the bar of a run (shown from its first generation)."""
        if self._overall is None:
            self._progress.start()
            self._started = monotonic()
            self._overall = self._progress.add_task("all runs", total=0, best="-", rate="-")
        self._progress.update(self._overall, total=(self._total() or 0) + generations + 1, advance=done)
        task = self._progress.add_task(
            label, total=generations + 1, completed=done, best="-", rate="-", visible=False
        )
        self._runs[key] = _Run(task)

    def _total(self) -> float | None:
        assert self._overall is not None
        return self._progress.tasks[self._overall].total

    def _few(self) -> bool:
        return len(self._runs) <= VISIBLE_RUNS

    def generation(self, key: Hashable, stats: GenerationStats) -> None:
        """Advance a run's bar and the overall bar by one generation."""
        run = self._runs.get(key)
        if run is None or run.finished or self._overall is None:
            return  # progress that arrives after its run's outcome
        run.evaluations += stats.evaluations
        run.seconds += stats.seconds
        self._evaluations += stats.evaluations
        rate = f"{run.evaluations / run.seconds:,.0f}" if run.seconds > 0 else "-"
        self._progress.update(run.task, advance=1, best=_shown(stats.best), rate=rate, visible=True)
        if stats.best > self._best or self._best != self._best:  # NaN: no valid individual yet
            self._best = stats.best
        elapsed = monotonic() - self._started
        overall = f"{self._evaluations / elapsed:,.0f}" if elapsed > 0 else "-"
        self._progress.update(self._overall, advance=1, best=_shown(self._best), rate=overall)

    def finish_run(self, key: Hashable) -> None:
        """Fill a run's bar (and the overall one by what it skipped); hide it when there are many."""
        run = self._runs[key]
        run.finished = True
        task = self._progress.tasks[run.task]
        missing = (task.total or 0) - task.completed
        self._progress.update(run.task, completed=task.total, visible=self._few())
        if self._overall is not None:
            self._progress.update(self._overall, advance=missing)

    def note(self, message: str) -> None:
        """Print ``message`` above the bars: wrapped to a terminal's width, one line in a pipe or file
        (whose width Rich takes as 80 columns)."""
        console = self._progress.console
        console.print(message, markup=False, highlight=False, soft_wrap=not console.is_terminal)

    def close(self) -> None:
        """Stop the live display."""
        if self._overall is not None:
            self._progress.stop()
