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
from mazegen.spec import Arena, Point, Spec, Station, Task, task_point_problem
from mazegen.text import printable, quoted

TASK = ("start", "goal", "stations", "tasks")
"""The fields of a document's ``arena`` that are its own tasks, not the spec's floor."""


def document_arena(spec: Spec, document: dict[str, Any], filename: str) -> Arena:
    """The spec's arena with the tasks of ``document``'s ``arena`` where it gives them: its ``tasks``
    (checked by the document rules), or its start and goal when they are not the spec's (one task).

    Raises:
        MazeError: for a start or goal that is no ``[x, y]`` point, or where the spec's robot
            cannot stand.
    """
    arena, given = spec.arena, document.get("arena")
    if not isinstance(given, dict):
        return arena
    if "tasks" in given:
        _named(given, "tasks", ("name",), filename)
        _named(given, "stations", ("name", "point"), filename)
        tasks = tuple(
            _task(arena, item, f"arena.tasks[{k}]", filename) for k, item in enumerate(given["tasks"])
        )
        stations = tuple(
            Station(item["name"], _pair(item["point"]), item.get("heading"))
            for item in given.get("stations", ())
        )
        if (tasks, stations) == (arena.tasks, arena.stations):
            return arena
        return dataclasses.replace(
            arena, start=tasks[0].start, goal=tasks[0].goal, stations=stations, tasks=tasks
        )
    task = _task(arena, {**given, "name": "start -> goal"}, "arena", filename)
    if (task.start, task.goal) == (arena.start, arena.goal):
        return arena
    return dataclasses.replace(arena, start=task.start, goal=task.goal, stations=(), tasks=())


def _named(given: dict[str, Any], key: str, fields: tuple[str, ...], filename: str) -> None:
    """Check that every entry of ``given[key]`` (a document's ``arena.tasks`` or ``arena.stations``,
    whose values the document rules checked) has ``fields``."""
    for k, item in enumerate(given.get(key, ())):
        for field in fields:
            if field not in item:
                raise MazeError(f"arena.{key}[{k}]: '{field}' is missing", filename=filename)


def _pair(value: Any) -> Point:
    return (float(value[0]), float(value[1]))


def _task(arena: Arena, given: dict[str, Any], where: str, filename: str) -> Task:
    """The task ``given`` (a document's ``arena`` or one of its ``tasks``, at ``where``), its start and
    goal the spec's where it gives none."""
    points = {}
    for label in ("start", "goal"):
        value = given.get(label, getattr(arena, label))
        if not (
            isinstance(value, (list, tuple))
            and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        ):
            raise MazeError(f"{where}: '{label}' must be an [x, y] point", filename=filename)
        point = _pair(value)
        problem = task_point_problem(label, point, arena.width, arena.height, arena.robot_radius)
        if problem is None and arena.base is not None:
            problem = point_on_walls(arena.base, label, point, arena.robot_radius)
        if problem is not None:
            raise MazeError(problem if where == "arena" else f"{where}: {problem}", filename=filename)
        points[label] = point
    if points["start"] == points["goal"]:
        raise MazeError(f"{where}: start and goal are the same point", filename=filename)
    headings = (given.get("start_heading"), given.get("goal_heading"))
    return Task(str(given["name"]), points["start"], points["goal"], *headings)


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
    goal of its ``own`` arena (or its own tasks), or None when they are the ``spec``'s."""
    if own.every_task == spec.every_task:
        return None
    if own.tasks or spec.tasks:
        return (
            f"{printable(filename)}: {done} on its own {len(own.every_task)} task(s), not the spec's "
            f"{len(spec.every_task)}"
        )
    return (
        f"{printable(filename)}: {done} with its own {_point('start', own.start)} and "
        f"{_point('goal', own.goal)}, not the spec's {_point('start', spec.start)} "
        f"and {_point('goal', spec.goal)}"
    )
