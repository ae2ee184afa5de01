"""Scenario documents (JSON format ``mazegen-scenario`` version 1): writing and reading back.

See ``docs/scenario-format.md`` (and its schema, ``docs/scenario.schema.json``). A
document lists each element's type, position, size and rotation, plus its world
polygons for consumers that do not know the element types, and the robot's path
when there is one. Reading a document back (for ``mazegen score``) uses only the
types and parameters; the polygons are recomputed.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.fitness_terms import reads_survey
from mazegen.maps import base_digest
from mazegen.runtime.documents._scenario_rules import check_document, read_json
from mazegen.runtime.engine import PLACEMENT_GENES, SX, SY, THETA, Population, X, Y
from mazegen.runtime.geometry import ElementTable, world_vertices
from mazegen.runtime.navigation import corner_paths_of, survey_of, task_views
from mazegen.spec import BaseMap, Spec, Station, Task, Zone

FORMAT = "mazegen-scenario"
VERSION = 1
DIGITS = 4


def _round(value: float) -> float:
    return round(float(value), DIGITS)


def arena_document(spec: Spec) -> dict[str, Any]:
    """The ``arena`` object of a document: the spec's floor, start, goal and robot."""
    a = spec.arena
    return {
        "name": a.name,
        "width": a.width,
        "height": a.height,
        "unit": a.unit,
        "start": list(a.start),
        "goal": list(a.goal),
        "robot_radius": a.robot_radius,
        **({} if a.base is None else {"map": map_document(a.base)}),
        **({} if not a.zones else {"zones": [zone_document(zone) for zone in a.zones]}),
        **({} if not a.stations else {"stations": [station_document(station) for station in a.stations]}),
        **({} if not a.tasks else {"tasks": [task_document(task) for task in a.tasks]}),
    }


def _heading(degrees: float | None) -> float | None:
    return None if degrees is None else _round(degrees) % 360.0


def station_document(station: Station) -> dict[str, Any]:
    """One of a document's ``arena.stations``: its name, point and heading (degrees, or null)."""
    return {"name": station.name, "point": list(station.point), "heading": _heading(station.heading)}


def task_document(task: Task) -> dict[str, Any]:
    """One of a document's ``arena.tasks``: its name, start and goal, and their headings (or null)."""
    return {
        "name": task.name,
        "start": list(task.start),
        "goal": list(task.goal),
        "start_heading": _heading(task.start_heading),
        "goal_heading": _heading(task.goal_heading),
    }


def zone_document(zone: Zone) -> dict[str, Any]:
    """One of a document's ``arena.zones``: its name, rule, outline and the types its rule names."""
    return {
        "name": zone.name,
        "rule": zone.rule,
        "outline": [[_round(x), _round(y)] for x, y in zone.outline],
        "types": list(zone.types),
    }


def map_document(base: BaseMap) -> dict[str, Any]:
    """The ``map`` of a document's ``arena``: which map the floor is built on. Its cells are the spec's
    (a run's ``spec.json``), not repeated in every document; ``cells`` tells one map's from another's."""
    return {
        "source": base.source,
        "resolution": base.resolution,
        "rows": base.rows,
        "cols": base.cols,
        "origin": list(base.origin),
        "unknown": base.unknown,
        "cells": base_digest(base),
    }


def row_fields(spec: Spec, population: Population, index: int) -> list[dict[str, Any] | None]:
    """The ``row`` of each element of individual ``index``: the row it is a member of (by name), that
    row's number among the floor's rows (from 0, in element order) and its place in the row (from 0);
    None for an element placed alone."""
    count = int(population.n_elements[index])
    if population.membership is None:
        return [None] * count
    fields: list[dict[str, Any] | None] = []
    rows = -1
    for row, member, _ in population.membership[index, :count].tolist():
        rows += row >= 0 and member == 0
        fields.append(
            None if row < 0 else {"name": spec.scenario.rows[row].name, "index": rows, "member": member}
        )
    return fields


def element_documents(
    spec: Spec, population: Population, index: int, rows: list[dict[str, Any] | None] | None = None
) -> list[dict[str, Any]]:
    """The elements of individual ``index`` as JSON-ready dicts; ``rows``: each element's ``row``
    (default: the population's, :func:`row_fields`)."""
    types = spec.scenario_elements
    count = int(population.n_elements[index])
    ids, params = population.element_ids[index, :count], population.params[index, :count]
    table = population.table
    # One rounding and one conversion for every vertex of the scenario.
    world = np.round(world_vertices(table, ids, params), DIGITS).tolist()
    n_parts, n_vertices = table.n_parts.tolist(), table.n_vertices.tolist()
    rows = row_fields(spec, population, index) if rows is None else rows
    out = []
    for e, p, parts, row in zip(ids.tolist(), params.tolist(), world, rows):
        kind = types[e]
        item: dict[str, Any] = {
            "type": kind.name,
            "class": kind.semantic_class,
            "colour": kind.colour,
            "height": kind.height,
            "x": _round(p[X]),
            "y": _round(p[Y]),
            # Rounded first: 359.99996 degrees must not round up to 360.
            "rotation": _round(math.degrees(p[THETA])) % 360.0,
        }
        if kind.uniform:
            item["size"] = _round(p[SX])
        else:
            item["width"], item["depth"] = _round(p[SX]), _round(p[SY])
        if row is not None:
            item["row"] = row
        item["parts"] = [parts[k][: n_vertices[e][k]] for k in range(n_parts[e])]
        out.append(item)
    return out


def robot_path(population: Population, index: int) -> list[list[float]] | None:
    """The corners of individual ``index``'s path from start to goal (its first task's, for a floor of
    several), or None when it has none.

    The path is the engine's own (:func:`~mazegen.runtime.navigation._paths.paths_of` on the
    arena's grid), rounded to :data:`DIGITS` decimals, without repeated corners.
    """
    corners = corner_paths_of(population)[index]
    if corners is None:
        return None
    points = np.round(corners, DIGITS).tolist()
    return [point for k, point in enumerate(points) if k == 0 or point != points[k - 1]]


def _metrics(population: Population, index: int) -> dict[str, Any]:
    return {
        key: value if not isinstance(value, float) else _round(value)
        for key, value in survey_of(population).summary(index).items()
    }


def task_sections(population: Population, index: int) -> dict[str, Any]:
    """``{"tasks": [...]}``: each task's name, metrics and path, for a floor of several tasks (``{}`` for
    a floor of one, whose ``metrics`` and ``path`` are its task's)."""
    if not population.arena.tasks:
        return {}
    return {
        "tasks": [
            {"name": task.name, "metrics": _metrics(view, index), "path": robot_path(view, index)}
            for task, view in zip(population.arena.tasks, task_views(population))
        ]
    }


def scenario_key(population: Population, index: int) -> bytes:
    """What tells scenarios apart: element types and placements to :data:`DIGITS` decimals."""
    count = int(population.n_elements[index])
    ids = population.element_ids[index, :count].astype(np.int32)
    return ids.tobytes() + np.round(population.params[index, :count], DIGITS).tobytes()


def scenario_document(
    spec: Spec,
    population: Population,
    index: int,
    *,
    phenotype: str | None,
    fitness: float,
    terms: dict[str, float],
    origin: dict[str, Any],
) -> dict[str, Any]:
    """A whole scenario document for individual ``index`` of ``population``."""
    return {
        "format": FORMAT,
        "version": VERSION,
        "scenario": spec.name,
        "arena": arena_document(spec),
        "elements": element_documents(spec, population, index),
        "phenotype": phenotype,
        "fitness": fitness if math.isfinite(fitness) else None,
        "terms": {key: float(value) + 0.0 for key, value in terms.items()},  # + 0.0 turns -0.0 into 0.0
        "metrics": _metrics(population, index),
        "path": robot_path(population, index),
        **task_sections(population, index),
        "valid": bool(math.isfinite(fitness)),
        "origin": origin,
    }


def dumps(document: dict[str, Any], filename: str) -> str:
    """Deterministic JSON text of a document, to be written as ``filename``: every scenario file is
    made here, so none holds what its readers refuse.

    Raises:
        MazeError: naming ``filename`` and the field, for a NaN or an infinity (JSON has neither).
    """
    try:
        return json.dumps(document, indent=1, sort_keys=False, allow_nan=False) + "\n"
    except ValueError:
        found = _non_finite(document, "")
        if found is None:  # not a number's fault (a circular reference): a bug, not the user's
            raise
        field, value = found
        raise MazeError(
            f"{field} is {value}: a scenario file holds finite numbers only", filename=filename
        ) from None


def _non_finite(value: Any, where: str) -> tuple[str, float] | None:
    """The JSON path (``drive.dwa.time``) and value of the first non-finite number in ``value``, or None."""
    if isinstance(value, float):
        return None if math.isfinite(value) else (where, value)
    if isinstance(value, dict):
        items = [(f"{where}.{key}" if where else str(key), item) for key, item in value.items()]
    elif isinstance(value, (list, tuple)):
        items = [(f"{where}[{index}]", item) for index, item in enumerate(value)]
    else:
        return None
    for path, item in items:
        found = _non_finite(item, path)
        if found is not None:
            return found
    return None


def _require(item: dict[str, Any], keys: tuple[str, ...], where: str, filename: str) -> None:
    """Check that ``item`` (a checked object, at JSON path ``where``) has every one of ``keys``."""
    for key in keys:
        if key not in item:
            raise MazeError(f"{where}: '{key}' is missing", filename=filename)


def has_parts(document: dict[str, Any]) -> bool:
    """Whether every element of a document (read with :func:`read_document`) carries its world parts."""
    return all("parts" in element for element in document["elements"])


def check_complete(document: dict[str, Any], filename: str) -> None:
    """Check that a document (read with :func:`read_document`) has what consumers of a whole one read.

    The arena's size, start and goal, and each element's type, position and world parts.

    Raises:
        MazeError: Naming the file and the JSON path of what is missing.
    """
    if "arena" not in document:
        raise MazeError("'arena' is missing", filename=filename)
    _require(document["arena"], ("width", "height", "start", "goal"), "arena", filename)
    for index, item in enumerate(document["elements"]):
        _require(item, ("type", "x", "y", "parts"), f"elements[{index}]", filename)


def read_document(path: Path) -> dict[str, Any]:
    """Read a scenario file, every field it has checked (:func:`checked_document`).

    Raises:
        MazeError: Naming the file, and the line or the JSON path of what is wrong.
    """
    return checked_document(read_json(path), str(path))


def checked_document(document: Any, filename: str) -> dict[str, Any]:
    """``document`` if it is a scenario document of this version, every field it has checked
    (:mod:`~mazegen.runtime.documents._scenario_rules`).

    Raises:
        MazeError: Naming ``filename`` and the JSON path of what is wrong.
    """
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise MazeError(f'not a scenario file (expected "format": "{FORMAT}")', filename=filename)
    if document.get("version") != VERSION:
        raise MazeError(
            f"unsupported scenario version {document.get('version')!r} (this MazeGen reads {VERSION})",
            filename=filename,
        )
    if not isinstance(document.get("elements"), list):
        raise MazeError("'elements' must be a list", filename=filename)
    check_document(document, filename)
    return document


def population_from_document(
    spec: Spec, table: ElementTable, document: dict[str, Any], filename: str
) -> Population:
    """A one-individual :class:`Population` from a scenario document, checked against ``spec``."""
    return population_from_documents(spec, table, [(filename, document)])


def population_from_documents(
    spec: Spec, table: ElementTable, documents: list[tuple[str, dict[str, Any]]]
) -> Population:
    """A :class:`Population` of scenario documents, one individual each in their order, on ``spec``'s
    arena, each checked against ``spec``; ``documents`` are ``(filename, document)`` pairs."""
    slots = max([len(document["elements"]) for _, document in documents] + [1])
    ids = np.full((len(documents), slots), -1, dtype=np.int32)
    params = np.zeros((len(documents), slots, PLACEMENT_GENES), dtype=np.float64)
    for index, (filename, document) in enumerate(documents):
        _place_elements(spec, document["elements"], ids[index], params[index], filename)
    count = np.array([len(document["elements"]) for _, document in documents], dtype=np.int32)
    valid = np.ones(len(documents), dtype=np.bool_)
    return Population(ids, count, lambda: params, valid, table, spec.arena, reads_survey(spec))


def _place_elements(
    spec: Spec, elements: list[dict[str, Any]], ids: np.ndarray, params: np.ndarray, filename: str
) -> None:
    """Write a document's ``elements`` into one individual's element ids and placement rows."""
    names = list(spec.scenario.elements)
    for slot, item in enumerate(elements):
        where = f"elements[{slot}]"
        if item.get("type") not in names:
            raise MazeError(
                f"{where}.type: {item.get('type')!r} is not an element of scenario '{spec.name}' "
                f"({', '.join(names)})",
                filename=filename,
            )
        kind = spec.element(item["type"])
        ids[slot] = names.index(kind.name)
        sizes = ("size",) if kind.uniform else ("width", "depth")
        _require(item, ("x", "y", *sizes), where, filename)
        sx, sy = (item[sizes[0]], item[sizes[-1]])
        params[slot] = (item["x"], item["y"], sx, sy, math.radians(item.get("rotation", 0.0)))


def completed_document(spec: Spec, document: dict[str, Any], filename: str) -> dict[str, Any]:
    """A document with the spec's arena, every element's parts, the metrics and the path recomputed.

    For hand-written floors, which give only each element's type and placement (and the ``row`` of a
    row's members, which is kept).
    """
    population = population_from_document(
        spec, ElementTable.from_types(spec.scenario_elements), document, filename
    )
    return {
        "format": FORMAT,
        "version": VERSION,
        "scenario": spec.name,
        "phenotype": None,
        "fitness": None,
        "terms": {},
        "valid": True,
        "origin": {},
        **{key: value for key, value in document.items() if key != "tasks"},
        "arena": arena_document(spec),
        "elements": element_documents(
            spec, population, 0, [item.get("row") for item in document["elements"]]
        ),
        "metrics": _metrics(population, 0),
        "path": robot_path(population, 0),
        **task_sections(population, 0),
    }
