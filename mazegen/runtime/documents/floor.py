"""A scenario file read with the spec it was made under, when known: what ``export`` and ``drive`` read.

The spec comes from ``--spec`` or is found beside the scenario (``spec.json`` of a suite
directory, ``experiment/spec.json`` of a run directory: see
:mod:`~mazegen.runtime.documents.folders`). A hand-written document is completed from it.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

from mazegen.errors import MazeError
from mazegen.runtime.documents.folders import RunDirectory, SuiteDirectory
from mazegen.runtime.documents.scenario import (
    check_complete,
    completed_document,
    has_parts,
    population_from_document,
    read_document,
)
from mazegen.runtime.documents.task import arena_differences, task_note, task_spec
from mazegen.runtime.engine.population import Population
from mazegen.runtime.engine.problem import read_build_spec
from mazegen.runtime.geometry.elements import ElementTable
from mazegen.spec import Arena, Spec


@dataclass(frozen=True)
class Floor:
    """One scenario document, whole, with its spec when known.

    Attributes:
        document: The scenario document, every element with its ``parts``.
        spec: The spec the scenario was made under, with the start and goal the document gives
            (:func:`~mazegen.runtime.documents.task.task_spec`), or None when unknown.
        source: The scenario file.
        spec_arena: The arena of the spec as written, whose start and goal may not be the floor's.
        unlike_spec: Why the spec found beside the scenario is not its spec, if it is not.
    """

    document: dict[str, Any]
    spec: Spec | None
    source: Path
    spec_arena: Arena | None = None
    unlike_spec: str | None = None

    @property
    def where(self) -> str:
        """The scenario file, for messages."""
        return str(self.source)

    @property
    def arena(self) -> dict[str, Any]:
        """The document's ``arena`` object."""
        return self.document["arena"]

    def needs_spec(self, what: str) -> Spec:
        """The spec, or a one-line error saying that ``what`` needs it."""
        if self.spec is None:
            found = "scenarios in a run or suite directory find it there"
            raise MazeError(
                f"{what} needs the spec the scenario was made under: "
                + (self.unlike_spec or f"give --spec SPEC.maze ({found})"),
                filename=self.where,
            )
        return self.spec

    def task_note(self, done: str) -> str | None:
        """The note that the floor is ``done`` (``driven``) on its own start and goal, or None when
        they are its spec's (:func:`~mazegen.runtime.documents.task.task_note`)."""
        if self.spec is None or self.spec_arena is None:
            return None
        return task_note(self.where, self.spec.arena, self.spec_arena, done)

    @cached_property
    def population(self) -> Population:
        """The scenario as the engine sees it: a one-individual population built from the spec."""
        spec = self.needs_spec("this export")
        table = ElementTable.from_types(spec.scenario_elements)
        return population_from_document(spec, table, self.document, self.where)


def load_floor(path: Path, spec: Spec | None = None) -> Floor:
    """Read a scenario file, with its spec when given or found beside it.

    A document without every element's ``parts`` or without a ``path`` (hand-written,
    or written before paths were recorded) is completed from the spec when there is one.
    A document's own start and goal are kept: the floor's spec has them.

    Raises:
        MazeError: For an unreadable file, a document that is not a scenario or is
            damaged, a spec given whose arena differs from the document's otherwise than
            in its start and goal (saying what differs), or parts missing with no spec.
    """
    filename, explicit = str(path), spec is not None
    document = read_document(path)
    spec = spec if explicit else _found_spec(path, document)
    spec_arena, unlike_spec = None, None
    if spec is not None:
        differences = arena_differences(spec, document.get("arena", {}))
        if differences:
            unlike_spec = (
                f"the arena of spec '{spec.name}' differs from the scenario's: {'; '.join(differences)}"
            )
            if explicit:
                raise MazeError(unlike_spec, filename=filename)
            spec = None
        else:
            spec_arena, spec = spec.arena, task_spec(spec, document, filename)
    if spec is not None and not (has_parts(document) and "arena" in document and "path" in document):
        document = completed_document(spec, document, filename)
    if not has_parts(document):
        raise MazeError(
            unlike_spec or "the scenario's elements have no 'parts': give --spec SPEC.maze to compute them",
            filename=filename,
        )
    check_complete(document, filename)
    return Floor(document, spec, path, spec_arena, unlike_spec)


def _found_spec(path: Path, document: dict[str, Any]) -> Spec | None:
    """The spec of the suite or run directory holding ``path``, if it is the document's."""
    for spec_file in (SuiteDirectory(path.parent).spec, RunDirectory(path.parent.parent).spec):
        if spec_file.is_file():
            spec = read_build_spec(spec_file.parent)
            return spec if spec.name == document.get("scenario") else None
    return None
