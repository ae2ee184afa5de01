"""The ``arena`` block: its size or the map it is built on, its start and goal, robot radius and grid."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from textx import get_location

from mazegen.dsl.bounds import MAX_LENGTH, at_most
from mazegen.dsl.located import fail, single_properties
from mazegen.dsl.tasks import TASK_PROPERTIES, point_problem, with_tasks
from mazegen.dsl.zones import convert_zones
from mazegen.errors import MazeError
from mazegen.spec import METRES_PER_UNIT, Arena, BaseMap
from mazegen.text import quoted

_END = {"StartProperty": "start", "GoalProperty": "goal"}

MAX_GRID_CELLS = 1024
"""The most cells a side of the navigation grid may have."""


def convert_arena(decl: Any) -> Arena:
    """Check one ``arena`` block and convert it (reading its map, when it names one)."""
    what = f"arena '{decl.name}'"
    zone_props = [p for p in decl.properties if type(p).__name__ == "ZoneProperty"]
    task_props = [p for p in decl.properties if type(p).__name__ in TASK_PROPERTIES]
    props = single_properties([p for p in decl.properties if p not in zone_props + task_props], what)
    if "UnknownCells" in props and "ArenaMap" not in props:
        fail(
            props["UnknownCells"], "'unknown' says what a map's unknown cells are, and this arena has no map"
        )
    if "ArenaMap" in props and "ArenaSize" in props:
        fail(props["ArenaSize"], "an arena built on a map takes its size from the map: remove 'size'")
    if "ArenaSize" not in props and "ArenaMap" not in props:
        fail(decl, f"{what} has no size (add e.g. 'size 1400 x 1050 cm', or 'map \"hall.yaml\"')")
    ends = [props[key] for key in ("StartProperty", "GoalProperty") if key in props]
    tasks = [p for p in task_props if type(p).__name__ != "StationProperty"]
    if tasks and ends:
        fail(
            ends[0],
            f"an arena with tasks takes its starts and goals from them: make this "
            f"{_END[type(ends[0]).__name__]} a station and name it in a task ('station dock (X, Y)', "
            "'task dock -> B')",
        )
    if task_props and not tasks:
        fail(
            task_props[0],
            f"station '{task_props[0].name}' is in no task (add e.g. 'task {task_props[0].name} -> B')",
        )
    for key, example in (("StartProperty", "start (60, 60)"), ("GoalProperty", "goal (1340, 990)")):
        if key not in props and not tasks:
            fail(decl, f"{what} has no {example.split()[0]} (add e.g. '{example}')")
    base = _base(props["ArenaMap"], props.get("UnknownCells")) if "ArenaMap" in props else None
    if base is not None:
        width, height, unit = base.cols * base.resolution, base.rows * base.resolution, props["ArenaMap"].unit
        unit = unit or "m"
    else:
        size = props["ArenaSize"]
        width, height, unit = size.width, size.height, size.unit or "cm"
        if width <= 0 or height <= 0:
            fail(size, f"arena size must be positive, got {width:g} x {height:g}")
    if max(width, height) > MAX_LENGTH:
        fail(
            props.get("ArenaSize") or props["ArenaMap"],
            f"arena size must be at most {MAX_LENGTH}, got {width:.15g} x {height:.15g}",
        )
    radius = props["RobotProperty"].radius if "RobotProperty" in props else 0.0
    if radius < 0:
        fail(props["RobotProperty"], f"robot radius must not be negative, got {radius:g}")
    if "RobotProperty" in props:
        at_most(props["RobotProperty"], radius, MAX_LENGTH, "robot radius")
    grid = props["GridProperty"].cell if "GridProperty" in props else None
    if grid is not None and not 0 < grid <= min(width, height) / 4:
        fail(
            props["GridProperty"],
            f"grid cell must be positive and at most a quarter of the arena's shorter side, got {grid:g}",
        )
    if grid is not None and max(width, height) / grid > MAX_GRID_CELLS:
        fail(props["GridProperty"], f"grid cell {grid:g} makes more than {MAX_GRID_CELLS} cells on a side")
    zones = convert_zones(zone_props, width, height)
    arena = Arena(decl.name, width, height, unit, (0.0, 0.0), (0.0, 0.0), radius, grid, base, zones)
    if tasks:
        return with_tasks(arena, task_props)
    for key, label in (("StartProperty", "start"), ("GoalProperty", "goal")):
        point = props[key].point
        problem = point_problem(arena, label, (point.x, point.y))
        if problem is not None:
            fail(point, problem)
    start, goal = ((props[key].point.x, props[key].point.y) for key in ("StartProperty", "GoalProperty"))
    if start == goal:
        fail(props["GoalProperty"], "start and goal are the same point")
    return dataclasses.replace(arena, start=start, goal=goal)


def _base(prop: Any, unknown: Any) -> BaseMap:
    """The map ``map "FILE" [UNIT]`` names, relative to the file that declares the arena."""
    unit = prop.unit or "m"
    if unit not in METRES_PER_UNIT:
        fail(prop, f"a map's cells are in metres: give its arena in mm, cm or m (map {quoted(prop.file)} cm)")
    if "\0" in prop.file:  # no file name holds one; the operating system refuses it
        fail(prop, f"no map file {quoted(prop.file)}: a file name holds no NUL character")
    spec_file = get_location(prop)["filename"]
    path = ((Path(spec_file).parent if spec_file else Path.cwd()) / prop.file).resolve()
    if not path.is_file():
        fail(prop, f"no map file {quoted(prop.file)} (looked for {path})")
    if path.suffix.lower() not in (".yaml", ".yml"):
        fail(prop, f"map {quoted(prop.file)}: give a ROS map_server map's .yaml (its image beside it)")
    from mazegen.maps import read_base_map  # numpy and the image readers: only for an arena on a map

    try:
        base = read_base_map(
            path,
            source=prop.file,
            units_per_metre=1.0 / METRES_PER_UNIT[unit],
            unknown=unknown.cells if unknown is not None else "blocked",
        )
    except MazeError as error:
        where = (
            f"{Path(error.filename).name}{f':{error.line}' if error.line else ''}: " if error.filename else ""
        )
        fail(prop, f"map {quoted(prop.file)}: {where}{error.message}")
    if max(base.rows, base.cols) * base.resolution > MAX_LENGTH:
        fail(prop, f"map {quoted(prop.file)} is larger than {MAX_LENGTH} arena units")
    return base
