"""A scenario document's task under its spec: the start and goal its ``arena`` gives, and what else of
its arena differs from the spec's.

A floor is scored and driven on its own start and goal (a floor drawn by hand for another start is
not judged on the spec's), with a note saying so. Any other difference of the arena (its size,
unit or robot) means the document was made under another spec: the commands refuse it, saying what
differs.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from mazegen.errors import MazeError
from mazegen.maps import point_on_walls
from mazegen.runtime.documents._scenario import arena_document
from mazegen.spec import Arena, Point, Spec, task_point_problem
from mazegen.text import printable, quoted

TASK = ("start", "goal")
"""The fields of a document's ``arena`` that are its own task, not the spec's floor."""


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
    for label in TASK:
        value = given.get(label, getattr(arena, label))
        if not (
            isinstance(value, (list, tuple))
            and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        ):
            raise MazeError(f"arena: '{label}' must be an [x, y] point", filename=filename)
        point = (float(value[0]), float(value[1]))
        problem = task_point_problem(label, point, arena.width, arena.height, arena.robot_radius)
        if problem is None and arena.base is not None:
            problem = point_on_walls(arena.base, label, point, arena.robot_radius)
        if problem is not None:
            raise MazeError(problem, filename=filename)
        points[label] = point
    if points["start"] == points["goal"]:
        raise MazeError("arena: start and goal are the same point", filename=filename)
    return dataclasses.replace(arena, start=points["start"], goal=points["goal"])


def task_spec(spec: Spec, document: dict[str, Any], filename: str) -> Spec:
    """``spec`` with the arena of :func:`document_arena`: the spec a floor is scored and driven under."""
    return dataclasses.replace(spec, arena=document_arena(spec, document, filename))


def _shown(value: Any) -> str:
    if isinstance(value, dict):  # a map: its file and cells
        return f"{quoted(str(value.get('source')))} (cells {value.get('cells')})"
    if value is None:
        return "none"
    if isinstance(value, list):  # zones: their names
        return ", ".join(quoted(str(zone.get("name"))) for zone in value if isinstance(zone, dict)) or "none"
    return quoted(value) if isinstance(value, str) else f"{value:g}"


def arena_differences(spec: Spec, recorded: dict[str, Any]) -> list[str]:
    """What the fields ``recorded`` (a document's ``arena``) gives say otherwise than ``spec``, start and
    goal aside: ``width 1400 in the spec, 1500 in the scenario``, one entry per field."""
    expected = arena_document(spec)
    for key in ("map", "zones"):
        if (key in expected or key in recorded) and set(recorded) - set(TASK):
            # A floor on a map or with zones is not one on another map or zones, or on none; an arena of
            # a start and goal alone (a floor drawn by hand) says nothing of the floor.
            expected.setdefault(key, None)
            recorded = {**recorded, key: recorded.get(key)}
    return [
        f"{key} {_shown(expected[key])} in the spec, {_shown(recorded[key])} in the scenario"
        for key in expected
        if key not in TASK and key in recorded and recorded[key] != expected[key]
    ]


def _point(text: str, point: Point) -> str:
    return f"{text} ({point[0]:g}, {point[1]:g})"


def task_note(filename: str, own: Arena, spec: Arena, done: str) -> str | None:
    """The note that the floor of ``filename`` is ``done`` (``scored``, ``driven``) on the start and
    goal of its ``own`` arena, or None when they are the ``spec``'s."""
    if (own.start, own.goal) == (spec.start, spec.goal):
        return None
    return (
        f"{printable(filename)}: {done} with its own {_point('start', own.start)} and "
        f"{_point('goal', own.goal)}, not the spec's {_point('start', spec.start)} "
        f"and {_point('goal', spec.goal)}"
    )
