"""An arena's tasks: ``station NAME (X, Y) [heading A]``, ``task A -> B`` and
``tasks N seed S [min distance D [UNIT]]``, checked against the arena and its map, drawn ones drawn
where the robot stands on the empty floor."""

from __future__ import annotations

import math
from typing import Any

from mazegen.dsl.located import fail, suggestion, where
from mazegen.spec import MAX_TASKS, METRES_PER_UNIT, Arena, Station, Task, task_point_problem

TASK_PROPERTIES = ("StationProperty", "TaskProperty", "DrawnTasks")
"""The arena properties that give tasks (several of each may be written)."""


def point_problem(arena: Arena, label: str, point: tuple[float, float]) -> str | None:
    """Why the robot cannot stand at ``point`` (``label`` names it) in ``arena``, or None."""
    problem = task_point_problem(label, point, arena.width, arena.height, arena.robot_radius)
    if problem is None and arena.base is not None:
        from mazegen.maps import point_on_walls  # numpy: only for an arena on a map

        problem = point_on_walls(arena.base, label, point, arena.robot_radius)
    return problem


def with_tasks(arena: Arena, props: list[Any]) -> Arena:
    """``arena`` with the stations and tasks ``props`` give (its ``station``, ``task`` and ``tasks``
    properties, in order), its start and goal the first task's; ``arena`` itself when there are none."""
    stations = _stations([p for p in props if type(p).__name__ == "StationProperty"], arena)
    listed = [p for p in props if type(p).__name__ == "TaskProperty"]
    drawn = [p for p in props if type(p).__name__ == "DrawnTasks"]
    if len(drawn) > 1:
        fail(drawn[1], f"duplicate 'tasks' in arena '{arena.name}' (first given at {where(drawn[0])})")
    tasks = _listed(listed, stations)
    used = {name for task in listed for name in (task.start, task.goal)}
    for prop in props:
        if type(prop).__name__ == "StationProperty" and prop.name not in used:
            fail(prop, f"station '{prop.name}' is in no task (add e.g. 'task {prop.name} -> B')")
    if drawn:
        tasks += _drawn(drawn[0], arena, len(tasks))
    if not tasks:
        return arena
    first = tasks[0]
    return Arena(
        arena.name,
        arena.width,
        arena.height,
        arena.unit,
        first.start,
        first.goal,
        arena.robot_radius,
        arena.grid,
        arena.base,
        arena.zones,
        tuple(stations.values()),
        tuple(tasks),
    )


def _stations(props: list[Any], arena: Arena) -> dict[str, Station]:
    stations: dict[str, Station] = {}
    first: dict[str, Any] = {}
    for prop in props:
        if prop.name in stations:
            fail(prop, f"duplicate station '{prop.name}' (first given at {where(first[prop.name])})")
        point = (prop.point.x, prop.point.y)
        problem = point_problem(arena, f"station '{prop.name}'", point)
        if problem is not None:
            fail(prop.point, problem)
        heading = prop.heading
        if heading is not None and not -360 <= heading <= 360:
            fail(prop, f"a heading is in degrees, -360..360, got {heading:g}")
        stations[prop.name] = Station(prop.name, point, None if heading is None else heading % 360.0)
        first[prop.name] = prop
    return stations


def _listed(props: list[Any], stations: dict[str, Station]) -> list[Task]:
    tasks: dict[str, Task] = {}
    first: dict[str, Any] = {}
    for prop in props:
        for name in (prop.start, prop.goal):
            if name not in stations:
                fail(
                    prop,
                    f"no station '{name}'{suggestion(name, stations)} (declare it: 'station {name} (X, Y)')",
                )
        if prop.start == prop.goal:
            fail(prop, f"task {prop.start} -> {prop.goal} starts where it ends")
        name = f"{prop.start} -> {prop.goal}"
        if name in tasks:
            fail(prop, f"duplicate task {name} (first given at {where(first[name])})")
        start, goal = stations[prop.start], stations[prop.goal]
        tasks[name] = Task(name, start.point, goal.point, start.heading, goal.heading)
        first[name] = prop
    if len(tasks) > MAX_TASKS:
        fail(props[MAX_TASKS], f"an arena has at most {MAX_TASKS} tasks")
    return list(tasks.values())


def _drawn(prop: Any, arena: Arena, listed: int) -> list[Task]:
    """The ``tasks N seed S [min distance D]`` of ``arena``, drawn on its empty floor (its map's walls
    only: elements come and go, and each task's solvability is measured on each floor)."""
    if not 1 <= prop.count <= MAX_TASKS - listed:
        fail(prop, f"tasks: give 1 to {MAX_TASKS - listed} tasks to draw, got {prop.count}")
    if prop.seed < 0 or prop.seed >= 2**63:
        fail(prop, f"tasks: the seed must be 0 to {2**63 - 1}, got {prop.seed}")
    distance = _distance(prop, arena)
    import numpy as np  # only for an arena whose tasks are drawn

    from mazegen.maps import base_on_grid, draw_tasks, standing_cells

    cell = arena.cell  # the navigation grid's cells (``Grid.from_arena``): a drawn point is a cell's centre
    rows, cols = (max(1, math.ceil(side / cell - 1e-9)) for side in (arena.height, arena.width))
    walls = np.zeros((rows, cols), bool) if arena.base is None else base_on_grid(arena.base, cell, rows, cols)
    free, standing = standing_cells(walls, cell, arena.width, arena.height, arena.robot_radius)
    try:
        pairs = draw_tasks(free, standing, cell, prop.count, prop.seed, distance)
    except ValueError as error:
        fail(prop, f"tasks: {error} (on the arena's grid of {cell:g} {arena.unit} cells)")
    return [Task(f"drawn {listed + k + 1}", start, goal) for k, (start, goal) in enumerate(pairs)]


def _distance(prop: Any, arena: Arena) -> float:
    """The minimum distance of ``tasks``, in the arena's unit."""
    if prop.distance is None:
        return 0.0
    distance = prop.distance
    if distance < 0:
        fail(prop, f"tasks: the min distance must not be negative, got {distance:g}")
    if prop.unit is None or prop.unit == arena.unit:
        return distance
    if prop.unit not in METRES_PER_UNIT or arena.unit not in METRES_PER_UNIT:
        fail(prop, f"tasks: a min distance in {prop.unit} cannot be converted to the arena's {arena.unit}")
    return distance * METRES_PER_UNIT[prop.unit] / METRES_PER_UNIT[arena.unit]
