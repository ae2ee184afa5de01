"""Scoring scenario documents under a spec, for ``mazegen score``: fitness, terms, solvability, metrics,
and how controllers drive them.

The spec is built and its fitness module loaded once, then any number of documents are
scored with it. A document is scored on its own task: the start and goal its ``arena``
gives, else the spec's (a floor drawn by hand for another start is not judged on the
spec's).
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mazegen.errors import MazeError
from mazegen.runtime.documents.driving import Drive, Floors
from mazegen.runtime.documents.scenario import population_from_document, read_document
from mazegen.runtime.engine.problem import Problem
from mazegen.runtime.navigation.measures import survey_of
from mazegen.spec import Arena, Point, Spec, task_point_problem


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
        drives: How each controller asked for drove it, in their order.
    """

    file: str
    fitness: float
    elements: int
    terms: dict[str, float]
    measured: dict[str, bool | float | None]
    start: Point
    goal: Point
    drives: tuple[Drive, ...] = ()

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
            **(
                {"drive": {drive.controller: drive.measures() for drive in self.drives}}
                if self.drives
                else {}
            ),
        }


def _finite(value: float) -> float | None:
    return value + 0.0 if math.isfinite(value) else None  # + 0.0 turns -0.0 into 0.0


def _point(text: str, point: Point) -> str:
    return f"{text} ({point[0]:g}, {point[1]:g})"


def document_arena(spec: Spec, document: dict[str, Any], filename: str) -> Arena:
    """The spec's arena with the start and goal of ``document``'s ``arena`` where it gives them.

    Raises:
        MazeError: for a start or goal that is no ``[x, y]`` point, or where the spec's robot
            cannot stand.
    """
    arena, given = spec.arena, document.get("arena")
    if not isinstance(given, dict):
        return arena
    points = {}
    for label in ("start", "goal"):
        value = given.get(label, getattr(arena, label))
        if not (
            isinstance(value, (list, tuple))
            and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        ):
            raise MazeError(f"arena: '{label}' must be an [x, y] point", filename=filename)
        point = (float(value[0]), float(value[1]))
        problem = task_point_problem(label, point, arena.width, arena.height, arena.robot_radius)
        if problem is not None:
            raise MazeError(problem, filename=filename)
        points[label] = point
    if points["start"] == points["goal"]:
        raise MazeError("arena: start and goal are the same point", filename=filename)
    return dataclasses.replace(arena, start=points["start"], goal=points["goal"])


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
        arena = document_arena(self.spec, document, filename)
        if (arena.start, arena.goal) != (self.spec.arena.start, self.spec.arena.goal):
            note(
                f"{filename}: scored with its own {_point('start', arena.start)} and "
                f"{_point('goal', arena.goal)}, not the spec's {_point('start', self.spec.arena.start)} "
                f"and {_point('goal', self.spec.arena.goal)}"
            )
        task = dataclasses.replace(self.spec, arena=arena)
        population = population_from_document(task, self.problem.table, document, filename)
        fitness, terms = self.problem.score(population)
        drives = (
            Floors.of_population(task, [filename], population).drive(controllers)[0] if controllers else []
        )
        return Scored(
            file=filename,
            fitness=float(fitness[0]),
            elements=int(population.n_elements[0]),
            terms={key: float(values[0]) for key, values in terms.items()},
            measured=survey_of(population).summary(0),
            start=arena.start,
            goal=arena.goal,
            drives=tuple(drives),
        )
