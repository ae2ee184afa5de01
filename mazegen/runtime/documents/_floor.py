"""A scenario file read with the spec it was made under, when known: what ``export`` and ``drive`` read.

Drawings, JSON and Gazebo worlds need only the document (its elements' world polygons), unless
the floor is built on a map: the document names the map, the spec holds its walls (:meth:`Floor.base`).
Occupancy maps need the engine's own grid, which the spec defines: the spec comes from
``--spec`` or is found beside the scenario (``spec.json`` of a suite directory,
``experiment/spec.json`` of a run directory: see :mod:`~mazegen.runtime.documents._folders`).
A hand-written document is completed from it.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.documents._folders import RunDirectory, SuiteDirectory
from mazegen.runtime.documents._scenario import (
    check_complete,
    completed_document,
    has_parts,
    population_from_document,
    read_document,
)
from mazegen.runtime.documents._task import arena_differences, task_note, task_spec
from mazegen.runtime.engine import Population, read_build_spec
from mazegen.runtime.geometry import ElementTable, Grid, grid_of, point_grid_of
from mazegen.runtime.navigation import free_cells
from mazegen.spec import Arena, BaseMap, Spec
from mazegen.text import quoted

EXPORT_METRES_PER_UNIT = {"mm": 0.001, "cm": 0.01, "m": 1.0, "px": 0.01}
"""Metres per arena unit in exports: ``px`` has no physical size, so exports take 1 px = 1 cm
(:data:`mazegen.spec.METRES_PER_UNIT` sizes a pixel from the robot instead)."""

MAX_CELLS_PER_SIDE = 4096
"""Largest grid side a grid export accepts: beyond it maps are too large to search."""

_UNSAFE = re.compile(r"[\s\x00-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")
"""Whitespace, control characters, lone surrogates and the two non-characters XML forbids."""


def safe_name(text: str) -> str:
    """``text`` with each character :data:`_UNSAFE` matches replaced by ``_``.

    Safe in file names, XML text and comments, YAML and the tab-separated lines of
    MovingAI's ``.scen``, whatever name the user's file has.
    """
    return _UNSAFE.sub("_", text)


class Scale(Protocol):
    """What :meth:`Floor.metres_per_unit` reads of an export's options
    (:class:`~mazegen.runtime.exporters._floor.ExportOptions`)."""

    @property
    def scale(self) -> float | None:
        """Metres per arena unit, or None for the unit's own."""


@dataclass(frozen=True)
class Floor:
    """One scenario document, whole, with its spec when known.

    Attributes:
        document: The scenario document, every element with its ``parts``.
        spec: The spec the scenario was made under, with the start and goal the document gives
            (:func:`~mazegen.runtime.documents._task.task_spec`), or None when unknown.
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
    def name(self) -> str:
        """Stem every exported file is named after (``best-01``), made safe (:func:`safe_name`)."""
        return safe_name(self.source.stem)

    @property
    def where(self) -> str:
        """The scenario file, for messages."""
        return str(self.source)

    @property
    def arena(self) -> dict[str, Any]:
        """The document's ``arena`` object."""
        return self.document["arena"]

    def metres_per_unit(self, options: Scale) -> float:
        """Metres per arena unit: ``options.scale``, else the arena unit's (:data:`EXPORT_METRES_PER_UNIT`).

        Raises:
            MazeError: For a unit of unknown size and no scale.
        """
        if options.scale is not None:
            return options.scale
        unit = self.arena.get("unit")
        if unit not in EXPORT_METRES_PER_UNIT:
            raise MazeError(
                f"arena unit {unit!r} has no known size in metres: give --scale", filename=self.where
            )
        return EXPORT_METRES_PER_UNIT[unit]

    def needs_spec(self, what: str) -> Spec:
        """The spec, or a one-line error saying that ``what`` needs it (and, for a floor on a map, that
        the map's walls are the spec's)."""
        if self.spec is None:
            found = "scenarios in a run or suite directory find it there"
            needed = f"{what} needs the spec the scenario was made under"
            if "map" in self.arena:
                source = quoted(str(self.arena["map"].get("source")))
                needed = f"the floor is built on map {source}: {what} needs its spec"
            raise MazeError(
                f"{needed}: " + (self.unlike_spec or f"give --spec SPEC.maze ({found})"),
                filename=self.where,
            )
        return self.spec

    def base(self, what: str) -> BaseMap | None:
        """The map the floor is built on, None for a floor on none.

        Raises:
            MazeError: For a floor on a map whose spec is unknown: the document names its map, the
                spec holds its cells, and ``what`` (``a Gazebo world``) is not made without its walls.
        """
        if "map" not in self.arena:
            return None
        return self.needs_spec(what).arena.base

    def task_note(self, done: str) -> str | None:
        """The note that the floor is ``done`` (``driven``) on its own start and goal, or None when
        they are its spec's (:func:`~mazegen.runtime.documents._task.task_note`)."""
        if self.spec is None or self.spec_arena is None:
            return None
        return task_note(self.where, self.spec.arena, self.spec_arena, done)

    @cached_property
    def population(self) -> Population:
        """The scenario as the engine sees it: a one-individual population built from the spec."""
        spec = self.needs_spec("this export")
        table = ElementTable.from_types(spec.scenario_elements)
        return population_from_document(spec, table, self.document, self.where)

    def occupancy(self, cell: float | None = None) -> tuple[np.ndarray, Grid]:
        """``bool[rows, cols]``: the cells the elements occupy on a grid of ``cell``, by default the
        engine's (row 0 at y = 0).

        The engine's configuration space for a point robot: no disc dilation, and blocked
        only where elements or the base map's walls touch, or for a partial edge cell whose centre
        lies outside the arena.

        Raises:
            MazeError: For a cell that gives too large a grid.
        """
        grid = point_grid_of(self._arena_of_cell(cell, "an occupancy map"))
        return ~free_cells(self.population, grid, 0), grid

    def configuration_space(self, cell: float | None) -> tuple[np.ndarray, Grid]:
        """``bool[rows, cols]`` free cells for the robot's centre, on a grid of ``cell`` (row 0 at y = 0).

        Raises:
            MazeError: For a cell that gives too large a grid.
        """
        grid = grid_of(self._arena_of_cell(cell, "a grid map"))
        return free_cells(self.population, grid, 0), grid

    def _arena_of_cell(self, cell: float | None, what: str) -> Arena:
        """The spec's arena with its grid of ``cell`` arena units (None: the spec's own grid)."""
        arena = self.needs_spec(what).arena
        if cell is None:
            return arena
        sides = [math.ceil(side / cell - 1e-9) for side in (arena.width, arena.height)]
        if max(sides) > MAX_CELLS_PER_SIDE:
            raise MazeError(
                f"--cell {cell:g} gives a {sides[0]} x {sides[1]} grid; "
                f"at most {MAX_CELLS_PER_SIDE} cells a side: choose a larger cell"
            )
        return replace(arena, grid=cell)


def load_floor(path: Path, spec: Spec | None = None) -> Floor:
    """Read a scenario file, with its spec when given or found beside it (:func:`floor_of`).

    Raises:
        MazeError: For an unreadable file, and as :func:`floor_of` does.
    """
    return floor_of(read_document(path), path, spec)


def floor_of(document: dict[str, Any], path: Path, spec: Spec | None = None) -> Floor:
    """A checked scenario document as a floor, with its spec when given or found beside ``path``.

    A document without every element's ``parts`` or without a ``path`` (hand-written,
    or written before paths were recorded) is completed from the spec when there is one.
    A document's own start and goal are kept: the floor's spec has them.

    Raises:
        MazeError: For a document that is not a scenario or is damaged, a spec given whose arena
            differs from the document's otherwise than in its start and goal (saying what differs),
            or parts missing with no spec.
    """
    filename, explicit = str(path), spec is not None
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
