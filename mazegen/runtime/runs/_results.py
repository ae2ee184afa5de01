"""Writing the run directory: statistics, best scenarios, final populations, and checkpoints while it runs.

Where each file goes is :class:`~mazegen.runtime.documents._folders.RunDirectory`'s to say. A run
directory is written as it goes, so that a killed experiment can be resumed:

* at the start, ``experiment/`` (the build), ``experiment.json`` and ``checkpoints/``, staged
  beside and renamed into place at once: a kill leaves the whole start or nothing;
* while runs go, ``checkpoints/run-NN/`` (see :mod:`mazegen.runtime.runs._checkpoint`);
* as each run finishes, ``run-NN/`` (its best scenarios and final population), whole
  or not at all;
* at the end, ``timing.csv``, then ``stats.csv``, then the catalog marks the experiment
  finished, then the checkpoints are deleted, which marks the directory finished (a
  directory killed before that is resumed from each run's last checkpoint and ends again);
* a new directory whose runs fail before any progress (no checkpoint, no finished run)
  is deleted (the catalog marks the experiment ``failed``).

Every file but ``timing.csv`` (wall-clock seconds) depends only on the experiment,
not on the executor nor on interruptions.
"""

from __future__ import annotations

import contextlib
import csv
import glob
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

from mazegen.errors import MazeError, option
from mazegen.fileio import FOLDER_MODE, disk_errors, make_folder, write_atomic
from mazegen.runtime.engine import GenerationStats, RunResult
from mazegen.runtime.documents import RunDirectory
from mazegen.runtime.documents import dumps
from mazegen.runtime.reports import scenario_svg
from mazegen.runtime.runs._locks import lock_folder
from mazegen.spec import BaseMap

TIMED = "seconds"
STAGED_START = "start-"
"""Infix of the folder a run directory's start is staged in, beside it (``.NAME.start-XXXX``)."""
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
def staged_directory(target: Path, *, force: bool, kind: str = "") -> Iterator[Path]:
    """Yield a temporary directory beside ``target`` that replaces it only if the block succeeds.

    An interrupted or failed block leaves ``target`` as it was; an error naming a file of the
    temporary directory names it as it would be in ``target``. ``kind`` marks the temporary
    directory's name (``.NAME.KIND…``).

    Raises:
        MazeError: for a non-empty ``target`` without ``force``, or a disk that cannot be written.
    """
    if target.exists() and not target.is_dir():
        raise MazeError("output directory is a file", filename=str(target))
    if target.exists() and any(target.iterdir()) and not force:
        raise MazeError(
            f"output directory already exists and is not empty (use {option('force')} to replace it, "
            f"or {option('out_dir')} to choose another)",
            filename=str(target),
        )
    stage = _stage(target, kind)
    try:
        yield stage
        _swap(stage, target)
    except MazeError as error:
        shutil.rmtree(stage, ignore_errors=True)
        if error.filename is not None and Path(error.filename).is_relative_to(stage):
            error.filename = str(target / Path(error.filename).relative_to(stage))
        raise
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise


def _stage(target: Path, kind: str) -> Path:
    """A new private folder beside ``target`` (``.NAME.KIND…``), to be renamed to ``target``."""
    make_folder(target.parent)
    with disk_errors(target, "create the folder"):
        stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.{kind}", dir=target.parent))
        stage.chmod(FOLDER_MODE)
    return stage


def _swap(stage: Path, target: Path) -> None:
    """Rename ``stage`` to ``target``; an existing ``target`` is moved aside first, then deleted."""
    old = target.parent / f"{stage.name}.old"
    with disk_errors(target):
        if target.exists():
            target.rename(old)
        try:
            stage.rename(target)
        except OSError:
            if old.exists():
                old.rename(target)  # nothing already written is lost
            raise
    shutil.rmtree(old, ignore_errors=True)


def run_files(
    result: RunResult, documents: tuple[dict[str, Any], ...], base: BaseMap | None
) -> dict[str, bytes]:
    """The files of a run's folder: its best scenarios (JSON and SVG, on ``base``, the map the arena
    is built on) and its final population.

    Workers prepare them (compressing a large population takes as long as a few generations),
    so the launcher, which writes every run, only writes bytes.
    """
    files: dict[str, bytes] = {}
    for rank, document in enumerate(documents, start=1):
        name = RunDirectory.best_name(rank, ".json")
        files[name] = dumps(document, name).encode("utf-8")
        files[RunDirectory.best_name(rank, ".svg")] = scenario_svg(document, base=base).encode("utf-8")
    arrays = {"codons": result.codons, "placement": result.genes, "fitness": result.fitness}
    files[RunDirectory.POPULATION] = npz_bytes(arrays)
    return files


class RunDirectoryWriter(RunDirectory):
    """One experiment's run directory as a launch writes it (see the module docstring for its life).

    A directory being written is locked (see :mod:`~mazegen.runtime.runs._locks`), so a second
    launch cannot resume or replace it meanwhile, nor a launch while the workers of a launcher
    killed outright are still on their way out.
    """

    def __init__(self, path: Path) -> None:
        super().__init__(path)
        self._lock: int | None = None

    @classmethod
    def create(cls, path: Path, *, force: bool, files: dict[str, str | bytes]) -> RunDirectoryWriter:
        """A new run directory holding ``files`` (paths relative to it), locked.

        The start is staged in a folder beside ``path`` and renamed to it at once, so a kill
        leaves either no run directory or one whose start is whole; a folder staged by a
        killed launch is deleted here. An existing non-empty directory is replaced only
        with ``force``.

        Raises:
            MazeError: for an existing directory without ``force``, a file in the way, a
                directory another launch is writing, or a disk that cannot be written.
        """
        if path.exists() and not path.is_dir():
            raise MazeError("output directory is a file", filename=str(path))
        existing = cls(path)
        if path.is_dir():
            existing.lock()
            if any(path.iterdir()) and not force:
                existing.close()
                raise MazeError(
                    f"output directory already exists and is not empty (use {option('force')} to replace "
                    f"it, {option('out_dir')} to choose another, or {option('resume')} to continue an "
                    "interrupted run)",
                    filename=str(path),
                )
        directory: RunDirectoryWriter | None = None
        try:
            _delete_abandoned_starts(path)
            with staged_directory(path, force=True, kind=STAGED_START) as stage:
                directory = cls(stage)
                directory.lock()
                for name, data in files.items():
                    write_atomic(stage / name, data)
                with disk_errors(RunDirectory(path).all_checkpoints):
                    directory.all_checkpoints.mkdir()
        except BaseException:
            if directory is not None:
                directory.close()
            raise
        finally:
            existing.close()
        directory.path = path  # the same folder, and lock, under its final name
        return directory

    @classmethod
    def unfinished(cls, path: Path) -> RunDirectoryWriter:
        """An interrupted run directory, locked, cleared of the temporary files a kill left behind.

        Raises:
            MazeError: for a folder that is not a run directory, a finished one, or one in use.
        """
        directory = cls(path)
        directory.check_unfinished()
        directory.lock()
        with disk_errors(path):
            for leftover in sorted(path.rglob(".*"), reverse=True):  # temporary files and staged runs
                if leftover.is_dir():
                    shutil.rmtree(leftover)
                else:
                    leftover.unlink()
            directory.all_checkpoints.mkdir(exist_ok=True)  # workers check that they can see it
        return directory

    def check_unfinished(self) -> None:
        """Raise a :class:`MazeError` unless this is a run directory that has not finished.

        A finished one is first rid of checkpoints whose deletion a kill interrupted.
        """
        if not self.record.is_file() or not self.spec.is_file():
            raise MazeError("not a MazeGen run directory (no experiment.json)", filename=str(self.path))
        if self.finished:
            shutil.rmtree(self.dropped_checkpoints, ignore_errors=True)
            raise MazeError("this run directory is finished: nothing to resume", filename=str(self.path))

    def lock(self) -> None:
        """Take the directory's lock, once no worker writes its checkpoints.

        Raises:
            MazeError: when another process holds either.
        """
        self._lock = lock_folder(self.path, "run directory")

    def close(self) -> None:
        """Release the lock."""
        if self._lock is not None:
            os.close(self._lock)
            self._lock = None

    def discard(self) -> None:
        """Delete the whole directory (a new one that failed before any run made progress)."""
        shutil.rmtree(self.path, ignore_errors=True)

    def write_run(self, number: int, files: dict[str, bytes]) -> None:
        """Write run ``number``'s files (from :func:`run_files`), whole or not at all."""
        with staged_directory(self.run_path(number), force=True) as stage:
            for name, data in files.items():
                with disk_errors(stage / name):
                    (stage / name).write_bytes(data)  # the stage is renamed whole: no file needs its own

    def finish(self, results: list[RunResult]) -> None:
        """Write the statistics of every run (run 1 first); :meth:`drop_checkpoints` then ends it."""
        rows = [(number, row) for number, result in enumerate(results, start=1) for row in result.stats]
        write_atomic(self.timing, timing_csv(rows))
        write_atomic(self.stats, stats_csv(rows))

    def drop_checkpoints(self) -> None:
        """Delete the checkpoints, which marks the directory finished: one rename, then the deletion
        of the renamed folder (a kill in between leaves it hidden, deleted by the next resume)."""
        checkpoints, dropped = self.all_checkpoints, self.dropped_checkpoints
        if checkpoints.exists():
            with disk_errors(checkpoints):
                checkpoints.rename(dropped)
        shutil.rmtree(dropped, ignore_errors=True)


def _delete_abandoned_starts(path: Path) -> None:
    """Delete the folders a killed launch staged for ``path``: those no process holds locked."""
    for stage in path.parent.glob(f".{glob.escape(path.name)}.{STAGED_START}*"):
        abandoned = RunDirectoryWriter(stage)
        try:
            abandoned.lock()
        except MazeError:
            continue  # another launch is starting there now
        shutil.rmtree(stage, ignore_errors=True)
        abandoned.close()
