"""Progress reporting of runs: a Rich bar per run, or nothing."""

from __future__ import annotations

from typing import Protocol

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TaskID, TextColumn, TimeElapsedColumn

from mazegen.runtime.evolution import GenerationStats


class Reporter(Protocol):
    """What an experiment tells about its progress."""

    def start_run(self, run: int, runs: int, generations: int) -> None: ...
    def generation(self, stats: GenerationStats) -> None: ...
    def close(self) -> None: ...


def reporter_for(*, quiet: bool) -> Reporter:
    """The reporter a command line asks for."""
    return QuietReporter() if quiet else RichReporter()


class QuietReporter:
    """Reports nothing (scripts, tests)."""

    def start_run(self, run: int, runs: int, generations: int) -> None:
        """Ignore."""

    def generation(self, stats: GenerationStats) -> None:
        """Ignore."""

    def close(self) -> None:
        """Ignore."""


class RichReporter:
    """One progress bar per run on standard error, with the best fitness so far."""

    def __init__(self, console: Console | None = None) -> None:
        self._progress = Progress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("best {task.fields[best]}"),
            TimeElapsedColumn(),
            console=console or Console(stderr=True),
            transient=False,
        )
        self._task: TaskID | None = None

    def start_run(self, run: int, runs: int, generations: int) -> None:
        """Open the bar of run ``run`` (1-based)."""
        if self._task is None:
            self._progress.start()
        self._task = self._progress.add_task(f"run {run}/{runs}", total=generations + 1, best="-")

    def generation(self, stats: GenerationStats) -> None:
        """Advance by one generation."""
        best = "-" if stats.best != stats.best else f"{stats.best:g}"
        if self._task is not None:
            self._progress.update(self._task, advance=1, best=best)

    def close(self) -> None:
        """Stop the live display."""
        if self._task is not None:
            self._progress.stop()
