"""The run directory: statistics, best scenarios, final populations, and checkpoints while it runs.

A run directory is written as it goes, so that a killed experiment can be resumed:

* at the start, ``experiment/`` (the build) and ``experiment.json``;
* while runs go, ``checkpoints/run-NN/`` (see :mod:`mazegen.runtime.checkpoint`);
* as each run finishes, ``run-NN/`` (its best scenarios and final population), whole
  or not at all;
* at the end, ``timing.csv`` and then ``stats.csv``, which marks the directory finished;
  then the checkpoints are deleted.

Every file but ``timing.csv`` (wall-clock seconds) depends only on the experiment,
not on the executor nor on interruptions.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import shutil
import tempfile
import zipfile
from collections.abc import Iterator
from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

try:
    import fcntl
except ImportError:  # Windows: run directories are not locked
    fcntl = None  # type: ignore[assignment]

from mazegen.errors import MazeError, option
from mazegen.fileio import FOLDER_MODE, make_folder, write_atomic
from mazegen.runtime.evolution import GenerationStats, RunResult
from mazegen.runtime.render import scenario_svg
from mazegen.runtime.scenario import dumps

TIMED = "seconds"
STATS_COLUMNS = ("run", *(f.name for f in fields(GenerationStats) if f.name != TIMED))
TIMING_COLUMNS = ("run", "generation", TIMED)


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "" if value != value else repr(value)  # NaN (no valid individual) → empty cell
    return str(value)


def _csv(columns: tuple[str, ...], rows: list[list[Any]]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    writer.writerows([_cell(value) for value in row] for row in rows)
    return buffer.getvalue()


def stats_csv(rows: list[tuple[int, GenerationStats]]) -> str:
    """``stats.csv`` text: one row per run and generation, without wall-clock times."""
    return _csv(
        STATS_COLUMNS, [[run, *(getattr(stats, name) for name in STATS_COLUMNS[1:])] for run, stats in rows]
    )


def timing_csv(rows: list[tuple[int, GenerationStats]]) -> str:
    """``timing.csv`` text: the wall-clock seconds of each run's generations."""
    return _csv(TIMING_COLUMNS, [[run, stats.generation, stats.seconds] for run, stats in rows])


def npz_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """An ``.npz`` archive with fixed timestamps, so equal arrays give equal bytes."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, array in arrays.items():
            member = io.BytesIO()
            np.lib.format.write_array(member, np.ascontiguousarray(array), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, member.getvalue())
    return buffer.getvalue()


def json_text(data: Any) -> str:
    """Deterministic, readable JSON text ending with a newline."""
    return json.dumps(data, indent=2, sort_keys=True) + "\n"


@contextlib.contextmanager
def staged_directory(target: Path, *, force: bool) -> Iterator[Path]:
    """Yield a temporary directory that replaces ``target`` only if the block succeeds.

    An interrupted or failed run leaves ``target`` as it was.
    """
    if target.exists() and any(target.iterdir()) and not force:
        raise MazeError(
            f"output directory already exists and is not empty (use {option('force')} to replace it, "
            f"or {option('out_dir')} to choose another)",
            filename=str(target),
        )
    make_folder(target.parent)
    stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    stage.chmod(FOLDER_MODE)
    try:
        yield stage
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    old = None
    if target.exists():
        old = target.parent / f"{stage.name}.old"
        target.rename(old)
    stage.rename(target)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def run_files(result: RunResult, documents: tuple[dict[str, Any], ...]) -> dict[str, bytes]:
    """The files of a run's folder: its best scenarios (JSON and SVG) and its final population.

    Workers prepare them (compressing a large population takes as long as a few generations),
    so the launcher, which writes every run, only writes bytes.
    """
    files: dict[str, bytes] = {}
    for rank, document in enumerate(documents, start=1):
        files[f"best-{rank:02d}.json"] = dumps(document).encode("utf-8")
        files[f"best-{rank:02d}.svg"] = scenario_svg(document).encode("utf-8")
    arrays = {"codons": result.codons, "placement": result.genes, "fitness": result.fitness}
    files["population.npz"] = npz_bytes(arrays)
    return files


class RunDirectory:
    """The files of one experiment's run directory (see the module docstring for its life).

    A directory being written is locked (an exclusive ``flock`` on the folder itself, where
    the system has it), so a second launch cannot resume or replace it meanwhile; the lock
    goes with the process, also when it is killed.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self._lock: int | None = None

    @classmethod
    def create(cls, path: Path, *, force: bool) -> RunDirectory:
        """A new, empty, locked run directory; an existing non-empty one is emptied only with ``force``.

        Raises:
            MazeError: for an existing directory without ``force``, a file in the way, or a
                directory another launch is writing.
        """
        if path.exists() and not path.is_dir():
            raise MazeError("output directory is a file", filename=str(path))
        make_folder(path)
        directory = cls(path)
        directory.lock()
        if any(path.iterdir()):
            if not force:
                directory.close()
                raise MazeError(
                    f"output directory already exists and is not empty (use {option('force')} to replace "
                    f"it, {option('out_dir')} to choose another, or {option('resume')} to continue an "
                    "interrupted run)",
                    filename=str(path),
                )
            for child in path.iterdir():  # the folder itself stays: it carries the lock
                if child.is_dir():
                    shutil.rmtree(child)
                else:
                    child.unlink()
        return directory

    @classmethod
    def unfinished(cls, path: Path) -> RunDirectory:
        """An interrupted run directory, locked, cleared of the temporary files a kill left behind.

        Raises:
            MazeError: for a folder that is not a run directory, a finished one, or one in use.
        """
        directory = cls(path)
        directory.check_unfinished()
        directory.lock()
        for leftover in sorted(path.rglob(".*"), reverse=True):  # temporary files and staged runs
            if leftover.is_dir():
                shutil.rmtree(leftover)
            else:
                leftover.unlink()
        (path / "checkpoints").mkdir(exist_ok=True)  # workers check that they can see it
        return directory

    def check_unfinished(self) -> None:
        """Raise a :class:`MazeError` unless this is a run directory that has not finished."""
        if not (self.path / "experiment.json").is_file() or not (self.build / "spec.json").is_file():
            raise MazeError("not a MazeGen run directory (no experiment.json)", filename=str(self.path))
        if self.finished:
            raise MazeError("this run directory is finished: nothing to resume", filename=str(self.path))

    def lock(self) -> None:
        """Take the directory's lock.

        Raises:
            MazeError: when another process holds it.
        """
        if fcntl is None:
            return
        handle = os.open(self.path, os.O_RDONLY)
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(handle)
            raise MazeError(
                "this run directory is in use by another mazegen process", filename=str(self.path)
            ) from None
        self._lock = handle

    def close(self) -> None:
        """Release the lock."""
        if self._lock is not None:
            os.close(self._lock)
            self._lock = None

    @property
    def build(self) -> Path:
        """The build that runs: ``experiment/``."""
        return self.path / "experiment"

    @property
    def finished(self) -> bool:
        """Whether every run is written (``stats.csv`` is written last)."""
        return (self.path / "stats.csv").is_file()

    def run_path(self, number: int) -> Path:
        """The folder of run ``number``'s results."""
        return self.path / f"run-{number:02d}"

    def checkpoints(self, number: int) -> Path:
        """The folder of run ``number``'s checkpoints."""
        return self.path / "checkpoints" / f"run-{number:02d}"

    def write_start(self, files: dict[str, str | bytes]) -> None:
        """Write the files known before any run (paths relative to the directory)."""
        for name, data in files.items():
            write_atomic(self.path / name, data)
        (self.path / "checkpoints").mkdir(exist_ok=True)

    def write_run(self, number: int, files: dict[str, bytes]) -> None:
        """Write run ``number``'s files (from :func:`run_files`), whole or not at all."""
        with staged_directory(self.run_path(number), force=True) as stage:
            for name, data in files.items():
                (stage / name).write_bytes(data)  # the stage is renamed whole: no file needs its own rename

    def finish(self, results: list[RunResult]) -> None:
        """Write the statistics of every run (run 1 first), which marks the directory finished."""
        rows = [(number, row) for number, result in enumerate(results, start=1) for row in result.stats]
        write_atomic(self.path / "timing.csv", timing_csv(rows))
        write_atomic(self.path / "stats.csv", stats_csv(rows))
        shutil.rmtree(self.path / "checkpoints", ignore_errors=True)
