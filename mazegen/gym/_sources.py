"""Where an environment's levels come from: saved scenarios, a spec's fresh floors, a fixed set, or a
sampler of the user's.

A level source is anything with ``sample(rng, n) -> Levels``: the environment calls it with its own
generator for every level it plays, at ``reset`` and at every automatic reset, and never draws a
level from anywhere else. :func:`level_source` turns what a user passes as ``levels=`` into one.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

import numpy as np

from mazegen.errors import MazeError
from mazegen.gym._levels import Levels, level_hashes
from mazegen.runtime.engine import Population, Problem, random_codons, random_genes
from mazegen.runtime.navigation import survey_of, task_views
from mazegen.runtime.simulation import level_rows
from mazegen.spec import Robot, Spec

TRAINING_SPEC = Path(__file__).with_name("training.maze")
"""The bundled spec an environment given no levels draws fresh floors from."""


@runtime_checkable
class LevelSource(Protocol):
    """What an environment draws its levels from."""

    def sample(self, rng: np.random.Generator, n: int) -> Levels:
        """``n`` levels, drawn with ``rng``."""
        ...


class LevelPool:
    """A fixed set of levels, drawn uniformly with replacement."""

    def __init__(self, levels: Levels) -> None:
        if not len(levels):
            raise MazeError("no levels to draw from")
        self.levels = levels

    def sample(self, rng: np.random.Generator, n: int) -> Levels:
        """``n`` of the levels, each drawn uniformly."""
        return self.levels.take(self.draw(rng, n))

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """The indices of the levels :meth:`sample` gives for the same generator state."""
        size = len(self.levels)  # uniform floats scaled: a third of what Generator.integers costs a call
        return np.minimum((rng.random(n) * size).astype(np.int64), size - 1)


class _Sampler:
    """A user's function ``sampler(rng, n) -> Levels`` as a source, its answers checked."""

    def __init__(self, sampler: Callable[[np.random.Generator, int], Levels]) -> None:
        self.sampler = sampler

    def sample(self, rng: np.random.Generator, n: int) -> Levels:
        levels = self.sampler(rng, n)
        if not isinstance(levels, Levels) or len(levels) != n:
            got = f"{len(levels)} levels" if isinstance(levels, Levels) else type(levels).__name__
            raise MazeError(f"a level sampler asked for {n} levels returned {got}")
        return levels


class SpecLevels:
    """Fresh floors of a spec: random genomes mapped through its grammar; a floor that is invalid, that
    the spec's reject terms refuse or that has no path from start to goal is drawn again. On a floor of
    several tasks each level plays one task, drawn uniformly.

    Args:
        spec: A spec, or the path of a ``.maze`` file.
        robot: The robot of every level (default the spec's).
        batch: Genomes drawn at a time; levels not yet handed out wait for the next call with the same
            generator (a call with another one draws afresh, so that a seed gives the same levels).
    """

    def __init__(
        self, spec: Spec | str | os.PathLike[str], *, robot: Robot | None = None, batch: int = 256
    ) -> None:
        from mazegen.dsl.loader import load_spec
        from mazegen.generator.build import build

        self.spec = spec if isinstance(spec, Spec) else load_spec(Path(spec))
        with tempfile.TemporaryDirectory(prefix="mazegen-levels-") as temp:
            build(self.spec, Path(temp))
            self.problem = Problem.from_build_dir(Path(temp))
        self.robot = robot or self.spec.robot_or_default
        self.batch = batch
        self._waiting: Levels | None = None  # drawn with generator _waiting_for, not yet handed out
        self._waiting_for: np.random.Generator | None = None

    def sample(self, rng: np.random.Generator, n: int) -> Levels:
        """``n`` fresh valid, solvable floors."""
        settings, drawn = self.spec.evolution, 0
        found = self._waiting if self._waiting_for is rng else None  # a new generator: a fresh draw
        while found is None or len(found) < n:
            size = max(self.batch, n - (0 if found is None else len(found)))
            codons = random_codons(rng, size, settings.genome, settings.codon_max)
            genes = random_genes(rng, size, self.problem.slots)
            fresh = self.levels_of(codons, genes, rng)
            found = fresh if found is None else Levels.joined([found, fresh])
            drawn += size
            if not len(found) and drawn >= 64 * max(n, self.batch):
                raise MazeError(
                    f"spec {self.spec.scenario.name}: no valid floor with a path in {drawn} random genomes"
                )
        self._waiting = found.take(np.arange(n, len(found))) if len(found) > n else None
        self._waiting_for = rng
        return found.take(np.arange(n))

    def levels_of(self, codons: np.ndarray, genes: np.ndarray, rng: np.random.Generator) -> Levels:
        """The levels of the genomes that map to valid floors with a path (the others left out), a task
        drawn for each with ``rng`` on a floor of several."""
        tasks = self.spec.arena.tasks
        chosen = rng.integers(0, len(tasks), size=len(codons)) if tasks else np.zeros(len(codons), np.int64)
        return self.decoded(codons, genes, chosen)[1]

    def decoded(self, codons: np.ndarray, genes: np.ndarray, tasks: np.ndarray) -> tuple[np.ndarray, Levels]:
        """The genomes that map to valid floors with a path (their rows) and their levels, genome ``k``
        playing task ``tasks[k]``."""
        _, population = self.problem.decode(codons, genes)
        refused = np.logical_or.reduce(list(self.problem.rejections(population).values()))
        solvable = survey_of(population).navigation.solvable  # the survey the levels' difficulty reads
        keep = np.flatnonzero(population.valid & ~refused & solvable)
        name = self.spec.scenario.name
        levels = population_levels(population, self.robot, keep, tasks[keep], name)
        ids = np.array([f"{name}:{digest}" for digest in levels.hashes], np.str_)
        genomes = np.ascontiguousarray(codons[keep], np.int32), np.ascontiguousarray(genes[keep])
        return keep, Levels(levels.rows, ids, levels.hashes, levels.difficulty, levels.task, name, *genomes)


def population_levels(
    population: Population, robot: Robot, rows: np.ndarray, tasks: np.ndarray, spec: str
) -> Levels:
    """The levels of floors ``rows`` of ``population``, floor ``rows[k]`` playing its arena's task
    ``tasks[k]`` (0 for an arena of one task), named by their hashes."""
    views, named = task_views(population), population.arena.tasks
    parts, order = [], []
    for t, view in enumerate(views):
        at = np.flatnonzero(tasks == t)
        if not at.size:
            continue
        task = named[t] if named else None
        starts = None if task is None else task.start_poses(at.size)
        rows_t = level_rows(view, robot, rows[at], starts)
        hashes = level_hashes(rows_t)
        parts.append(
            Levels(
                rows_t,
                hashes,
                hashes,
                survey_of(view).difficulty[rows[at]],
                np.full(at.size, "" if task is None else task.name, np.str_),
                spec,
            )
        )
        order.append(at)
    if not parts:
        return _no_levels(robot, population)
    joined = Levels.joined(parts)
    return joined.take(np.argsort(np.concatenate(order), kind="stable"))


def _no_levels(robot: Robot, population: Population) -> Levels:
    rows = level_rows(population, robot, np.zeros(0, np.int64))
    empty = np.zeros(0, np.str_)
    return Levels(rows, empty, empty, np.zeros(0), empty)


def file_levels(
    sources: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    *,
    spec: Spec | str | os.PathLike[str] | None = None,
    robot: Robot | None = None,
) -> Levels:
    """Every task of every floor of ``sources`` (scenario files, run and suite directories, folders of
    scenario files, any mix) as a level, each on its own start and goal, driven by ``robot`` (default
    its spec's); a task without a path from start to goal is left out. A level is named by its file
    (and ``#task``), and keeps its genome when every file of its spec carries one (``origin``).

    Raises:
        MazeError: for a file that cannot be read or checked, naming it; when no level is left.
    """
    from mazegen.dsl.loader import load_spec
    from mazegen.runtime.documents import floor_batches, load_floor, scenario_files

    given = spec if isinstance(spec, Spec) or spec is None else load_spec(Path(spec))
    items = [sources] if isinstance(sources, str | os.PathLike) else list(sources)
    floors = [
        load_floor(path, given) for item in items for path, _ in scenario_files(Path(item), any_folder=True)
    ]
    ordered, batches = floor_batches(floors)
    found, at = [], 0
    for batch in batches:
        documents = [floor.document for floor in ordered[at : at + len(batch.files)]]
        at += len(batch.files)
        population, arena = batch.population, batch.spec.arena
        tasks = max(1, len(arena.tasks))
        pairs = [(i, t) for i in range(population.size) for t in range(tasks)]
        solvable = [survey_of(view).navigation.solvable for view in task_views(population)]
        pairs = [(i, t) for i, t in pairs if solvable[t][i]]
        rows, chosen = np.array([i for i, _ in pairs], np.int64), np.array([t for _, t in pairs], np.int64)
        name = batch.spec.scenario.name
        levels = population_levels(population, robot or batch.robot, rows, chosen, name)
        task_of = [f"#{arena.tasks[t].name}" if arena.tasks else "" for t in chosen]
        ids = np.array([f"{batch.files[i]}{suffix}" for i, suffix in zip(rows, task_of)], np.str_)
        codons, genes = _genomes([documents[i] for i in rows])
        found.append(
            Levels(levels.rows, ids, levels.hashes, levels.difficulty, levels.task, name, codons, genes)
        )
    joined = Levels.joined(found) if found else None
    if joined is None or not len(joined):
        raise MazeError(f"no level with a path from start to goal in {', '.join(map(str, items))}")
    return joined


def _genomes(documents: list[dict[str, Any]]) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The documents' genomes (``origin.codons``, ``origin.placement``) when every one has one of one
    shape, else ``(None, None)``."""
    try:
        codons = np.array([doc["origin"]["codons"] for doc in documents], np.int32)
        genes = np.array([doc["origin"]["placement"] for doc in documents], np.uint16)
    except (KeyError, TypeError, ValueError):
        return None, None
    return (codons, genes) if codons.ndim == 2 and genes.ndim == 3 and len(documents) else (None, None)


def level_source(levels: Any, *, robot: Robot | None = None) -> LevelSource:
    """What an environment draws from, given ``levels``: None (fresh floors of the bundled training
    spec), a ``.maze`` spec or a :class:`~mazegen.spec.Spec` (its fresh floors), a ``.npz`` of
    :class:`Levels`, scenario files and folders (:func:`file_levels`), a :class:`Levels` (drawn
    uniformly), a source (anything with ``sample(rng, n)``) or a function ``(rng, n) -> Levels``.
    ``robot`` drives the levels of a spec or of scenario files; levels already made carry their own.

    Raises:
        MazeError: for anything else, or a ``robot`` given with levels already made.
    """
    if levels is None:
        return SpecLevels(TRAINING_SPEC, robot=robot)
    if isinstance(levels, Spec):
        return SpecLevels(levels, robot=robot)
    path = Path(levels) if isinstance(levels, str | os.PathLike) else None
    made = isinstance(levels, Levels | LevelSource) or (path is not None and path.suffix == ".npz")
    made = made or (path is None and callable(levels))
    if robot is not None and made:
        raise MazeError(
            "robot= drives the levels of a spec or scenario files: levels already made carry theirs"
        )
    if isinstance(levels, Levels):
        return LevelPool(levels)
    if isinstance(levels, LevelSource):
        return levels
    if path is not None:
        if path.suffix == ".maze":
            return SpecLevels(path, robot=robot)
        if path.suffix == ".npz":
            return LevelPool(Levels.load(path))
    if isinstance(levels, str | os.PathLike) or (
        isinstance(levels, Sequence) and all(isinstance(item, str | os.PathLike) for item in levels)
    ):
        return LevelPool(file_levels(levels, robot=robot))
    if callable(levels):
        return _Sampler(levels)
    raise MazeError(
        f"levels must be a spec, files, Levels, a source or a sampler, got {type(levels).__name__}"
    )
