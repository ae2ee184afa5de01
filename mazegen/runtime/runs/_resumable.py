"""What ``resume`` checks before it continues a run directory, in the directory's own words.

A run directory's build is loaded from a temporary copy (loading ``fitness.py`` where it
is would leave a bytecode cache there); every error names the directory's own file, never
the copy, which is gone when the message is read.
"""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from mazegen.errors import MazeError, option
from mazegen.fileio import json_value
from mazegen.runtime.runs._experiment import BUILD_FILES, Experiment
from mazegen.runtime.runs._results import RunDirectoryWriter

NEEDED = tuple(name for name in BUILD_FILES if name != "experiment.py")
"""The build files a resume loads (``experiment.py`` only runs a build by hand)."""

RESTORE = f"restore it to resume, or start again with {option('run force')}"


def resumable_experiment(run_dir: Path, *, copy_to: Path) -> Experiment:
    """The experiment of the interrupted run directory ``run_dir``, loaded from a copy of its build.

    Args:
        run_dir: The run directory.
        copy_to: A folder that does not exist yet, for the copy.

    Raises:
        MazeError: for a folder that is not a run directory, a finished one, or one whose files
            are missing, damaged or disagree with each other.
    """
    directory = RunDirectoryWriter(run_dir)
    directory.check_unfinished()
    for name in NEEDED:
        if not (directory.build / name).is_file():
            raise MazeError(
                f"missing from this run directory ({RESTORE})", filename=str(directory.build / name)
            )
    checkpoints = directory.all_checkpoints
    if checkpoints.exists() and not checkpoints.is_dir():
        raise MazeError("not a folder (move it away to resume)", filename=str(checkpoints))
    with _named_as_in(directory.build, copy_to):
        experiment = Experiment.from_build_dir(shutil.copytree(directory.build, copy_to))
    _check_record(directory.record, experiment)
    return experiment


@contextmanager
def _named_as_in(build: Path, copy: Path) -> Iterator[None]:
    """Errors of the block that name a file of ``copy`` name the same file of ``build``."""
    try:
        yield
    except MazeError as error:
        if error.filename is not None:
            error.filename = error.filename.replace(str(copy), str(build), 1)
        error.message = error.message.replace(str(copy), str(build))
        raise


def _check_record(path: Path, experiment: Experiment) -> None:
    """Raise a :class:`MazeError` unless ``experiment.json`` records ``experiment``'s settings."""
    expected = experiment.record()
    try:
        written = json_value(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        raise MazeError(f"damaged experiment.json ({error}; {RESTORE})", filename=str(path)) from None
    versions = "versions"  # a resume may run on newer software
    if not isinstance(written, dict) or {k: v for k, v in written.items() if k != versions} != {
        k: v for k, v in expected.items() if k != versions
    }:
        raise MazeError(
            f"damaged experiment.json: it does not record the experiment of experiment/spec.json ({RESTORE})",
            filename=str(path),
        )
