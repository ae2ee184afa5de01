"""Where MazeGen's folders keep their files, and which scenario files a folder stands for.

The layouts of a run directory (``mazegen run``) and of a suite directory (``mazegen suite``) are
spelled here alone: every module that writes or reads one asks :class:`RunDirectory` or
:class:`SuiteDirectory` for a file's path, and :func:`scenario_files` walks a folder for the
scenario files in it.
"""

from __future__ import annotations

import re
from pathlib import Path

from mazegen.errors import MazeError
from mazegen.fileio import found_files

_RUN, _BEST, _SCENARIO = "run-", "best-", "scenario-"
_CHECKPOINT = re.compile(r"gen-(\d+)\.ckpt")


class _Place:
    """A fixed place in a folder: ``RunDirectory(path).stats`` is ``path / "stats.csv"``."""

    def __init__(self, *parts: str) -> None:
        self.parts = parts

    def __get__(self, folder: RunDirectory | SuiteDirectory, owner: type) -> Path:
        return folder.path.joinpath(*self.parts)


class RunDirectory:
    """Where each file of a run directory is (not whether it is there yet).

    ``experiment.json`` and ``experiment/`` (the build that runs) from the start;
    ``checkpoints/run-NN/gen-GGGGGG.ckpt`` while runs go; ``run-NN/`` as each run finishes
    (``best-KK.json`` and ``best-KK.svg``, ``population.npz``); ``timing.csv`` and ``stats.csv``
    at the end. :mod:`mazegen.runtime.runs._results` writes it in that order.
    """

    POPULATION = "population.npz"
    """A finished run's final population, in its folder."""
    RECORD_FORMAT = "mazegen-run"
    """The ``format`` of ``experiment.json``."""

    record = _Place("experiment.json")
    """``experiment.json``: the experiment's settings, seeds and versions."""
    build = _Place("experiment")
    """``experiment/``: the build that runs."""
    spec = _Place("experiment", "spec.json")
    """``experiment/spec.json``: the spec that runs, its overrides applied."""
    stats = _Place("stats.csv")
    """``stats.csv``: every run's statistics per generation, written at the end."""
    timing = _Place("timing.csv")
    """``timing.csv``: the wall-clock seconds of every run's generations."""
    all_checkpoints = _Place("checkpoints")
    """``checkpoints/``: a folder per run, there until the directory is finished."""
    dropped_checkpoints = _Place(".checkpoints-dropped")
    """Where the checkpoints go, in one rename, when the directory ends."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def run_path(self, number: int) -> Path:
        """The folder of run ``number``'s results."""
        return self.path / f"{_RUN}{number:02d}"

    def checkpoints(self, number: int) -> Path:
        """The folder of run ``number``'s checkpoints."""
        return self.all_checkpoints / f"{_RUN}{number:02d}"

    def population(self, number: int) -> Path:
        """Run ``number``'s final population."""
        return self.run_path(number) / self.POPULATION

    @property
    def pictures(self) -> Path:
        """Every best scenario's drawing, as messages name them all: ``run-NN/best-KK.svg``."""
        return self.path / f"{_RUN}NN" / f"{_BEST}KK.svg"

    @staticmethod
    def best_name(rank: int, suffix: str) -> str:
        """The name of a run's ``rank``-th best scenario in its folder: ``best-01.json`` for ``.json``."""
        return f"{_BEST}{rank:02d}{suffix}"

    def best_files(self) -> list[Path]:
        """Every ``run-*/best-*.json``, in run and rank order (regular files only: see
        :func:`~mazegen.fileio.found_files`)."""
        return found_files(self.path, f"{_RUN}*/{_BEST}*.json")

    @staticmethod
    def best_rank(path: Path) -> tuple[int, int] | None:
        """Run number and rank of a best scenario's file, or None for a name MazeGen does not write."""
        number, rank = path.parent.name.removeprefix(_RUN), path.stem.removeprefix(_BEST)
        return (int(number), int(rank)) if number.isdigit() and rank.isdigit() else None

    @staticmethod
    def checkpoint_name(generation: int) -> str:
        """The file of a run's checkpoint after ``generation``: ``gen-000012.ckpt``."""
        return f"gen-{generation:06d}.ckpt"

    @staticmethod
    def checkpoint_generation(name: str) -> int | None:
        """The generation of a checkpoint's file name, or None for another file."""
        found = _CHECKPOINT.fullmatch(name)
        return None if found is None else int(found[1])

    @property
    def finished(self) -> bool:
        """Whether the directory's ending is done: ``stats.csv`` written, then the checkpoints deleted.

        A directory killed in between is not finished: resuming it goes on from each run's
        last checkpoint (its last generation) and ends it again, identically.
        """
        return self.stats.is_file() and not self.all_checkpoints.exists()

    @property
    def started_anything(self) -> bool:
        """Whether a run has saved a checkpoint or finished: what a resume would continue from."""
        saved = self.all_checkpoints.glob(f"{_RUN}*/gen-*.ckpt")
        return any(self.path.glob(f"{_RUN}*")) or any(saved)


class SuiteDirectory:
    """Where each file of a suite directory is: ``spec.json``, ``archive.json`` and its heatmap
    ``archive.png``, and ``scenario-NN.json`` with its drawing ``scenario-NN.svg``."""

    spec = _Place("spec.json")
    """``spec.json``: the spec the suite was made under."""
    archive = _Place("archive.json")
    """``archive.json``: the suite's settings and the archive's filled cells."""
    heatmap = _Place("archive.png")
    """``archive.png``: the archive's cells, those chosen marked."""

    def __init__(self, path: Path) -> None:
        self.path = path

    @staticmethod
    def scenario_name(number: int, suffix: str) -> str:
        """The name of the suite's ``number``-th scenario: ``scenario-01.json`` for ``.json``."""
        return f"{_SCENARIO}{number:02d}{suffix}"

    def scenario_files(self) -> list[Path]:
        """Every ``scenario-*.json``, in name order (regular files only)."""
        return found_files(self.path, f"{_SCENARIO}*.json")

    @staticmethod
    def number(path: Path) -> str:
        """What follows ``scenario-`` in a scenario's file name (``05``)."""
        return path.stem.removeprefix(_SCENARIO)


def scenario_files(source: Path, *, any_folder: bool = False) -> list[tuple[Path, Path]]:
    """The scenario files ``source`` stands for, each with its folder relative to ``source``.

    A file is itself; a run directory gives its ``run-NN/best-KK.json``, a suite directory its
    ``scenario-NN.json``. Any other folder is refused, or with ``any_folder`` gives every scenario
    file below it (hidden ones, JSON files of another format such as ``experiment.json``, and
    entries that are not regular files, left out).

    Raises:
        MazeError: For a folder that is neither a run nor a suite directory (with ``any_folder``:
            one without a scenario file).
    """
    if not source.is_dir():
        return [(source, Path())]
    found = RunDirectory(source).best_files() or SuiteDirectory(source).scenario_files()
    if not found and not any_folder:
        raise MazeError(
            "not a run or suite directory (it has no run-NN/best-KK.json nor scenario-NN.json)",
            filename=str(source),
        )
    if not found:
        found = [
            path
            for path in found_files(source, "**/*.json")
            if not any(part.startswith(".") for part in path.relative_to(source).parts)
            and _may_be_scenario(path)
        ]
    if not found:
        raise MazeError("no scenario files in this folder", filename=str(source))
    return [(path, path.parent.relative_to(source)) for path in found]


def _may_be_scenario(path: Path) -> bool:
    """False for JSON files of another format; a file that cannot be read stays, to be reported."""
    from mazegen.runtime.documents._scenario import (
        FORMAT,  # NumPy: not for the catalog, which reads the layout
    )
    from mazegen.runtime.documents._scenario_rules import read_json

    try:
        document = read_json(path)  # bounded: a huge or deep file in the folder is refused, not loaded
    except MazeError:
        return True
    return not isinstance(document, dict) or document.get("format") == FORMAT
