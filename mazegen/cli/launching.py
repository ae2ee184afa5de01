"""What the commands that launch runs share: executor, checkpoint and catalog options, and Ctrl-C."""

from __future__ import annotations

import functools
import tempfile
from collections.abc import Callable
from pathlib import Path
from time import monotonic
from typing import TYPE_CHECKING, Any, TypeVar

import click

from mazegen.cli.bounds import CHECKPOINT_EVERY, WORKERS, BoundedOption, within
from mazegen.errors import MazeError
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.engine import Problem
    from mazegen.runtime.runs import Reporter
    from mazegen.spec import Spec

F = TypeVar("F", bound=Callable[..., Any])

INTERRUPTED_STATUS = 130
"""Exit status after Ctrl-C, as shells report a process stopped by SIGINT."""


def launch_options(command: F) -> F:
    """Add the options of where runs execute, when they checkpoint, their catalog, and ``-q``."""
    options = [
        click.option(
            "--executor",
            type=click.Choice(["local", "serial", "dask"]),
            default="local",
            show_default=True,
            help="Where runs execute: local worker processes, this process, or a Dask cluster.",
        ),
        click.option(
            "--workers",
            type=within(*WORKERS),
            cls=BoundedOption,
            help="Local worker processes (default: the cores).",
        ),
        click.option(
            "--scheduler", metavar="tcp://HOST:PORT", help="The Dask scheduler (with --executor dask)."
        ),
        click.option(
            "--checkpoint-every",
            type=within(*CHECKPOINT_EVERY),
            cls=BoundedOption,
            metavar="K",
            help="Checkpoint every K generations (0: never; default: every 30 s and the last generation).",
        ),
        click.option(
            "--catalog",
            type=click.Path(path_type=Path),
            help="The results catalog (default: catalog.sqlite beside the run directory).",
        ),
        click.option("-q", "--quiet", is_flag=True, help="No progress bars."),
    ]
    for option in reversed(options):
        command = option(command)
    return command


def launch_settings(options: dict[str, Any]) -> dict[str, Any]:
    """The keyword arguments of :func:`mazegen.api.run` that :func:`launch_options` collected.

    Raises:
        MazeError: for ``--workers`` without local worker processes to count.
    """
    if options["workers"] is not None and options["executor"] != "local":
        raise MazeError(f"--workers goes with --executor local, not {options['executor']}")
    return {
        "executor": options["executor"],
        "workers": options["workers"],
        "scheduler": options["scheduler"],
        "checkpoint_every": options["checkpoint_every"],
        "catalog": True if options["catalog"] is None else options["catalog"],
    }


def compile_first(source: Spec | Path | Problem, executor: str, reporter: Reporter) -> float:
    """Before the first runs of this version, say so and compile the kernels on two cores at once.

    ``source`` is the spec, a build directory or the problem loaded from one. Here rather than
    in the API: a helper process imports the program's main module, which this command's is safe
    for and a script's may not be. A Dask cluster's workers compile for themselves.

    Returns:
        The seconds it took (0 when nothing was compiled), for the runs to count.
    """
    from mazegen.runtime import kernels_cached, run_kernels
    from mazegen.runtime.engine import Problem, read_build_spec

    if executor == "dask":
        return 0.0
    spec = source.spec if isinstance(source, Problem) else source
    if kernels_cached(run_kernels(read_build_spec(spec) if isinstance(spec, Path) else spec)):
        return 0.0
    from mazegen.runtime.runs import FIRST_COMPILE_NOTE, compile_kernels

    started = monotonic()
    reporter.note(FIRST_COMPILE_NOTE)
    if isinstance(source, Problem):
        compile_kernels(source)
    elif isinstance(source, Path):
        compile_kernels(Problem.from_build_dir(source))
    else:
        from mazegen.generator.build import build

        with tempfile.TemporaryDirectory(prefix="mazegen-compile-") as temp:
            build(source, Path(temp))
            compile_kernels(Problem.from_build_dir(Path(temp)))
    return monotonic() - started


def reports_interruption(command: F) -> F:
    """Wrap a command so that Ctrl-C ends it with one line saying how to continue, and status 130."""
    from mazegen.runtime.runs import RunsInterrupted

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return command(*args, **kwargs)
        except RunsInterrupted as stopped:
            resume = "; ".join(f"mazegen resume {printable(str(path))}" for path in stopped.run_dirs)
            click.echo(f"interrupted: runs saved checkpoints; continue with: {resume}", err=True)
            raise SystemExit(INTERRUPTED_STATUS) from None

    return wrapper  # type: ignore[return-value]
