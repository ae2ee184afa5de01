"""Levels: floors with a task and a robot, as fixed-shape arrays with what a learner wants to know of
each (its id, hash, difficulty, task) and, where it has one, the genome it was mapped from.

:class:`Levels` is what level sources give, what ``reset(options={"levels": ...})`` takes, what the
curriculum's sampler keeps, and what ``.npz`` files hold (:meth:`Levels.save`, :meth:`Levels.load`):
padded element parts with a mask (a part of no vertices is padding), start, goal, robot limits,
the level's path, step limits; a JAX user loads a batch and ``vmap``\\ s over its first axis.
"""

from __future__ import annotations

import hashlib
import io
import os
import zipfile
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from mazegen.errors import MazeError
from mazegen.fileio import write_atomic
from mazegen.runtime.simulation import LevelRows

FORMAT = "mazegen-levels"
VERSION = 1


@dataclass(frozen=True)
class Levels:
    """``n`` levels.

    Attributes:
        rows: The levels' arrays (:class:`mazegen.runtime.simulation.LevelRows`: parts, start, goal,
            robot limits, path, step limits; arena units).
        ids: ``str[n]`` each level's name: its scenario file (and task), or its spec and genome's hash.
        hashes: ``str[n]`` a digest of what the robot meets (parts, arena, start, goal, robot): two
            levels with one hash are the same level, whatever their ids.
        difficulty: ``float64[n]`` MazeGen's difficulty score of the floor's task (NaN when unknown).
        task: ``str[n]`` the task's name on a floor of several tasks, else ``""``.
        spec: The spec the genomes map through (its scenario's name), or ``""``.
        codons: ``int32[n, G]`` each level's structure genome, or None when not every level has one.
        genes: ``uint16[n, K, 5]`` its placement genes, or None.
    """

    rows: LevelRows
    ids: np.ndarray
    hashes: np.ndarray
    difficulty: np.ndarray
    task: np.ndarray
    spec: str = ""
    codons: np.ndarray | None = None
    genes: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.ids)

    @property
    def has_genomes(self) -> bool:
        """Whether every level carries the genome it was mapped from (a mutator needs them)."""
        return self.codons is not None and self.genes is not None

    def take(self, index: np.ndarray | list[int]) -> Levels:
        """Levels ``index``, in that order (repeats allowed)."""
        at = np.asarray(index, np.int64).reshape(-1)
        return Levels(
            self.rows.take(at),
            self.ids[at],
            self.hashes[at],
            self.difficulty[at],
            self.task[at],
            self.spec,
            None if self.codons is None else self.codons[at],
            None if self.genes is None else self.genes[at],
        )

    @classmethod
    def joined(cls, parts: list[Levels]) -> Levels:
        """``parts``' levels one after another; genomes kept when all share one spec and genome shape."""
        if len(parts) == 1:
            return parts[0]
        genomes = [(p.codons, p.genes) for p in parts if p.codons is not None and p.genes is not None]
        shapes = {(codons.shape[1:], genes.shape[1:]) for codons, genes in genomes}
        specs = {p.spec for p in parts}
        same = len(genomes) == len(parts) and len(specs) == 1 and len(shapes) == 1
        return cls(
            LevelRows.joined([p.rows for p in parts]),
            np.concatenate([p.ids for p in parts]),
            np.concatenate([p.hashes for p in parts]),
            np.concatenate([p.difficulty for p in parts]),
            np.concatenate([p.task for p in parts]),
            parts[0].spec if len(specs) == 1 else "",
            np.concatenate([codons for codons, _ in genomes]) if same else None,
            np.concatenate([genes for _, genes in genomes]) if same else None,
        )

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the levels to one ``.npz`` file (written whole or not at all); returns its path."""
        target = Path(path)
        arrays = {f"rows.{name}": array for name, array in self.rows.arrays.items()}
        arrays |= {"ids": self.ids, "hashes": self.hashes, "difficulty": self.difficulty, "task": self.task}
        arrays |= {"format": np.array(FORMAT), "version": np.array(VERSION), "spec": np.array(self.spec)}
        if self.codons is not None and self.genes is not None:
            arrays |= {"codons": self.codons, "genes": self.genes}

        buffer = io.BytesIO()
        np.savez_compressed(buffer, allow_pickle=False, **arrays)
        write_atomic(target, buffer.getvalue())
        return target

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Levels:
        """The levels of a file :meth:`save` wrote.

        Raises:
            MazeError: for a file that is not one, naming it.
        """
        where = Path(path)
        try:
            with np.load(where, allow_pickle=False) as data:
                if str(data.get("format", "")) != FORMAT or int(data["version"]) != VERSION:
                    raise MazeError(
                        f"not a MazeGen levels file (format {FORMAT} version {VERSION})", filename=str(where)
                    )
                rows = LevelRows(**{f.name: data[f"rows.{f.name}"] for f in fields(LevelRows)})
                return cls(
                    rows,
                    data["ids"],
                    data["hashes"],
                    data["difficulty"],
                    data["task"],
                    str(data["spec"]),
                    data.get("codons"),
                    data.get("genes"),
                )
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as error:
            raise MazeError(f"cannot read levels: {error}", filename=str(where)) from error


def level_hashes(rows: LevelRows) -> np.ndarray:
    """``str[n]``: each level's digest of what its robot meets: its real parts, arena, start, goal, limits."""
    found = []
    for k in range(len(rows)):
        digest = hashlib.sha256()
        real = rows.count[k] > 0
        for array in (
            rows.parts[k][real],
            rows.count[k][real],
            rows.size[k],
            rows.start[k],
            rows.goal[k],
            rows.limits[k],
        ):
            digest.update(np.ascontiguousarray(array, np.float64).tobytes())
        found.append(digest.hexdigest()[:16])
    return np.array(found, np.str_)
