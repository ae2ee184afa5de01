"""Checkpoints of a run: its whole state after a generation, written atomically, read back checked.

A checkpoint is a ZIP archive (``gen-000012.ckpt``) of three ``.npy`` arrays (codons,
placement genes, fitness) and ``state.json`` (generation, the bit generator's state,
the statistics so far, and the experiment it belongs to). ZIP keeps a CRC-32 of every
member, so a truncated or damaged file is recognised when read; each run keeps its
last :data:`KEEP` checkpoints, so a damaged newest one falls back to the one before.
The evaluation cache is not saved: it is rebuilt from the checkpoint's generation
(see :func:`mazegen.runtime.engine._evolution.primed_cache`).
"""

from __future__ import annotations

import io
import json
import zipfile
import zlib
from dataclasses import astuple, dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mazegen.errors import MazeError, option
from mazegen.fileio import write_atomic
from mazegen.runtime.documents import RunDirectory
from mazegen.runtime.engine import GenerationStats, RunState
from mazegen.runtime.engine import PLACEMENT_GENES

if TYPE_CHECKING:
    from mazegen.runtime.engine import Problem

FORMAT = "mazegen-checkpoint"
VERSION = 1
KEEP = 2
"""Checkpoints kept per run: the newest and the one before, in case the newest is damaged."""

AUTO_SECONDS = 30.0
"""Without ``every``, a run checkpoints after the first generation that ends this long after
its previous checkpoint (a run of a few seconds never writes more than its last)."""


class DamagedCheckpoint(MazeError):
    """A checkpoint that cannot be read back: truncated, corrupted, edited or from another experiment."""


class ForeignCheckpoint(DamagedCheckpoint):
    """A whole checkpoint of another experiment (or of the same one before its build was edited)."""


@dataclass(frozen=True)
class CheckpointShape:
    """What the checkpoints of one experiment hold, so that an edited one is refused as damaged.

    Attributes:
        population: Individuals (rows of every array).
        genome: Structure codons per individual, each in ``0..codon_max``.
        slots: Element slots (rows of placement genes per individual).
        codon_max: The largest codon.
        generations: The experiment's last generation.
    """

    population: int
    genome: int
    slots: int
    codon_max: int
    generations: int

    @classmethod
    def of(cls, problem: Problem) -> CheckpointShape:
        """The shape of ``problem``'s checkpoints."""
        settings = problem.spec.evolution
        return cls(
            settings.population, settings.genome, problem.slots, settings.codon_max, settings.generations
        )

    def check(self, state: RunState) -> None:
        """Raise :class:`ValueError` unless ``state`` could be one of this experiment's runs."""
        arrays = (
            ("codons", state.codons, np.int32, (self.population, self.genome)),
            ("placement", state.genes, np.uint16, (self.population, self.slots, PLACEMENT_GENES)),
            ("fitness", state.fitness, np.float64, (self.population,)),
        )
        for name, array, dtype, shape in arrays:
            if array.dtype != dtype or array.shape != shape:
                raise ValueError(
                    f"{name} is {array.dtype}{list(array.shape)}, not {np.dtype(dtype)}{list(shape)}"
                )
        if state.codons.size and not 0 <= state.codons.min() <= state.codons.max() <= self.codon_max:
            raise ValueError(f"codons outside 0..{self.codon_max}")
        if np.isnan(state.fitness).any() or (state.fitness == np.inf).any():
            raise ValueError("fitness neither finite nor -inf (invalid)")
        if not 0 <= state.generation <= self.generations:
            raise ValueError(f"generation {state.generation} outside 0..{self.generations}")
        # Raises for a state the run's generator (as evolve restores it) cannot take.
        np.random.default_rng().bit_generator.state = state.rng_state


@dataclass(frozen=True)
class CheckpointPolicy:
    """When a run writes a checkpoint besides its last generation.

    Attributes:
        every: Every this many generations; ``None`` for time-based checkpoints
            (:data:`AUTO_SECONDS`); 0 for none at all (not even the last generation).
    """

    every: int | None = None

    @property
    def enabled(self) -> bool:
        """Whether the run writes checkpoints at all."""
        return self.every != 0

    def due(self, generation: int, seconds_since_last: float) -> bool:
        """Whether generation ``generation`` (not the last) should be checkpointed."""
        if self.every is None:
            return seconds_since_last >= AUTO_SECONDS
        return self.every > 0 and generation % self.every == 0


def checkpoint_bytes(state: RunState, *, experiment: str) -> bytes:
    """The checkpoint archive of ``state`` (uncompressed: runs save often, and the files are transient).

    Args:
        state: The run's state after a generation.
        experiment: Digest of the experiment's ``spec.json``, checked when reading back.
    """
    record = {
        "format": FORMAT,
        "version": VERSION,
        "experiment": experiment,
        "generation": state.generation,
        "rng": state.rng_state,
        "stats": [list(astuple(row)) for row in state.stats],
    }
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_STORED) as archive:
        for name, array in (("codons", state.codons), ("placement", state.genes), ("fitness", state.fitness)):
            member = io.BytesIO()
            np.lib.format.write_array(member, np.ascontiguousarray(array), allow_pickle=False)
            archive.writestr(_entry(f"{name}.npy"), member.getvalue())
        archive.writestr(_entry("state.json"), json.dumps(record))
    return buffer.getvalue()


def _entry(name: str) -> zipfile.ZipInfo:
    return zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))


def read_checkpoint(path: Path, *, experiment: str, shape: CheckpointShape | None = None) -> RunState:
    """Read a checkpoint back, checking every member and that it belongs to ``experiment``.

    Args:
        path: The file.
        experiment: Digest of the experiment's build.
        shape: What its arrays, codons, fitness and generator state must be; a file edited with
            valid CRCs that breaks them is damaged too.

    Raises:
        DamagedCheckpoint: for a missing, truncated, corrupted, edited or foreign file.
    """
    try:
        with zipfile.ZipFile(path) as archive:
            # ZipFile.read checks each member's CRC-32.
            record = json.loads(archive.read("state.json"))
            arrays = {
                name: np.load(io.BytesIO(archive.read(f"{name}.npy")), allow_pickle=False)
                for name in ("codons", "placement", "fitness")
            }
        if not isinstance(record, dict):
            raise ValueError("state.json is not an object")
        if record.get("experiment") != experiment:
            raise ForeignCheckpoint("checkpoint of another experiment", filename=str(path))
        state = _state(record, arrays)
        if shape is not None:
            shape.check(state)
    except (OSError, EOFError, zipfile.BadZipFile, zlib.error, KeyError, ValueError, TypeError) as error:
        raise DamagedCheckpoint(f"damaged checkpoint ({error})", filename=str(path)) from None
    return state


def _state(record: dict[str, Any], arrays: dict[str, np.ndarray]) -> RunState:
    if record["format"] != FORMAT or record["version"] != VERSION:
        raise ValueError(f"not a {FORMAT} version {VERSION}")
    generation = int(record["generation"])
    stats = tuple(GenerationStats(*row) for row in record["stats"])
    if any(row.generation != number for number, row in enumerate(stats)) or not all(
        isinstance(value, (int, float)) for row in stats for value in astuple(row)
    ):
        raise ValueError("damaged statistics")
    codons, genes, fitness = arrays["codons"], arrays["placement"], arrays["fitness"]
    population = codons.shape[0] if codons.ndim else -1
    if len(stats) != generation + 1 or genes.shape[:1] != (population,) or fitness.shape != (population,):
        raise ValueError("inconsistent arrays and statistics")
    return RunState(generation, codons, genes, fitness, record["rng"], stats)


class CheckpointStore:
    """The checkpoints of one run, in their own folder."""

    def __init__(
        self, *, directory: Path, experiment: str, shape: CheckpointShape | None = None, keep: int = KEEP
    ) -> None:
        self.directory = directory
        self.experiment = experiment
        self.shape = shape
        self.keep = keep

    def paths(self) -> list[Path]:
        """The run's checkpoint files, newest generation first."""
        if not self.directory.is_dir():
            return []
        named = [(RunDirectory.checkpoint_generation(path.name), path) for path in self.directory.iterdir()]
        found = [(generation, path) for generation, path in named if generation is not None]
        return [path for _, path in sorted(found, reverse=True)]

    def save(self, state: RunState) -> Path:
        """Write ``state`` (temporary file, then rename) and drop checkpoints older than the kept ones."""
        path = self.directory / RunDirectory.checkpoint_name(state.generation)
        write_atomic(path, checkpoint_bytes(state, experiment=self.experiment))
        for old in self.paths()[self.keep :]:
            old.unlink(missing_ok=True)
        return path

    def latest(self) -> tuple[tuple[Path, int] | None, list[str]]:
        """The newest checkpoint that reads back whole, and a warning for each newer damaged one.

        Returns:
            Its path and generation (``None`` when the run has none), and the warnings.

        Raises:
            MazeError: when the run has checkpoints and none of them is usable.
        """
        warnings: list[str] = []
        foreign = True
        for path in self.paths():
            try:
                state = read_checkpoint(path, experiment=self.experiment, shape=self.shape)
            except DamagedCheckpoint as error:
                if not path.exists():
                    continue  # dropped by a run that was still finishing its generation
                warnings.append(f"{error}; using the one before")
                foreign = foreign and isinstance(error, ForeignCheckpoint)
                continue
            return (path, state.generation), warnings
        if warnings and foreign:
            raise MazeError(
                "checkpoints of another build: were the files of experiment/ edited since the run started? "
                f"(restore them to resume, or start again with {option('run force')})",
                filename=str(self.directory),
            )
        if warnings:
            raise MazeError(
                f"no usable checkpoint ({len(warnings)} damaged); delete this folder to run that run again",
                filename=str(self.directory),
            )
        return None, warnings
