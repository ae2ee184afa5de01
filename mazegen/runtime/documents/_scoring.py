"""Scoring scenario documents under a spec, for ``mazegen score``: fitness, terms, solvability, metrics,
and how controllers drive them.

The spec is built and its fitness module loaded once, then any number of documents are
scored with it. A document is scored on its own task: the start and goal its ``arena``
gives, else the spec's (see :mod:`~mazegen.runtime.documents._task`).
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mazegen.runtime.documents._driving import Drive, Floors
from mazegen.runtime.documents._scenario import population_from_document, read_document
from mazegen.runtime.documents._task import task_note, task_spec
from mazegen.runtime.engine import Problem
from mazegen.runtime.navigation import survey_of, task_views
from mazegen.spec import Point, Spec


@dataclass(frozen=True)
class Scored:
    """What a scenario file scores under a spec.

    Attributes:
        file: The file, as given.
        fitness: The fitness; ``-inf`` when a ``reject`` term rejects the scenario.
        elements: Its number of elements.
        terms: Each scored term's value.
        measured: Solvability, occupied fraction and the difficulty metrics (None where unsolvable).
        start: The start it was scored with.
        goal: The goal it was scored with.
        drives: How each controller asked for drove it, in their order (task by task, on a floor of
            several tasks).
        tasks: Each task's name and measures, on a floor of several tasks (``measured`` is theirs
            together: solvable where every task is, each metric their mean).
    """

    file: str
    fitness: float
    elements: int
    terms: dict[str, float]
    measured: dict[str, bool | float | None]
    start: Point
    goal: Point
    drives: tuple[Drive, ...] = ()
    tasks: tuple[tuple[str, dict[str, bool | float | None]], ...] = ()

    @property
    def valid(self) -> bool:
        """Whether no ``reject`` term rejects it."""
        return math.isfinite(self.fitness)

    def record(self) -> dict[str, Any]:
        """A JSON-ready object: file, fitness (null when invalid), every term and metric, solvable."""
        return {
            "file": self.file,
            "fitness": self.fitness if self.valid else None,
            "valid": self.valid,
            "solvable": self.measured["solvable"],
            "elements": self.elements,
            "start": list(self.start),
            "goal": list(self.goal),
            "terms": {key: _finite(value) for key, value in self.terms.items()},
            "metrics": self.measured,
            **_drive_section([drive for drive in self.drives if drive.task is None]),
            **(
                {
                    "tasks": [
                        {
                            "name": name,
                            "metrics": measured,
                            **_drive_section([drive for drive in self.drives if drive.task == name]),
                        }
                        for name, measured in self.tasks
                    ]
                }
                if self.tasks
                else {}
            ),
        }


def _drive_section(drives: list[Drive]) -> dict[str, Any]:
    return {"drive": {drive.controller: drive.measures() for drive in drives}} if drives else {}


def _finite(value: float) -> float | None:
    return value + 0.0 if math.isfinite(value) else None  # + 0.0 turns -0.0 into 0.0


class Scorer:
    """Scores scenario files under one built spec."""

    def __init__(self, spec: Spec, problem: Problem) -> None:
        self.spec, self.problem = spec, problem

    @classmethod
    @contextmanager
    def built(cls, spec: Spec) -> Iterator[Scorer]:
        """A scorer of ``spec``, built in a temporary folder that goes when the block ends."""
        from mazegen.generator.build import build

        with tempfile.TemporaryDirectory(prefix="mazegen-score-") as temp:
            build(spec, Path(temp))
            yield cls(spec, Problem.from_build_dir(Path(temp)))

    def score(self, path: Path, *, note: Callable[[str], None], controllers: Sequence[str] = ()) -> Scored:
        """Score the scenario file ``path`` and drive it with each of ``controllers``; ``note`` hears when
        its task is not the spec's.

        Raises:
            MazeError: naming the file, for one that cannot be read or scored.
        """
        filename = str(path)
        document = read_document(path)
        task = task_spec(self.spec, document, filename)
        own = task_note(filename, task.arena, self.spec.arena, "scored")
        if own is not None:
            note(own)
        population = population_from_document(task, self.problem.table, document, filename)
        fitness, terms = self.problem.score(population)
        drives = Floors(task, (filename,), population).drive(controllers)[0] if controllers else []
        return Scored(
            file=filename,
            fitness=float(fitness[0]),
            elements=int(population.n_elements[0]),
            terms={key: float(values[0]) for key, values in terms.items()},
            measured=survey_of(population).summary(0),
            start=task.arena.start,
            goal=task.arena.goal,
            drives=tuple(drives),
            tasks=tuple(
                (one.name, survey_of(view).summary(0))
                for one, view in zip(task.arena.tasks, task_views(population))
            ),
        )
