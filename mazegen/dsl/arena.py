"""The ``arena`` block: its size or the map it is built on, its start and goal, robot radius and grid."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from textx import get_location

from mazegen.dsl.bounds import MAX_LENGTH, at_most
from mazegen.dsl.located import fail, single_properties
from mazegen.dsl.zones import convert_zones
from mazegen.errors import MazeError
from mazegen.spec import METRES_PER_UNIT, Arena, BaseMap, task_point_problem
from mazegen.text import quoted

MAX_GRID_CELLS = 1024
"""The most cells a side of the navigation grid may have."""


def convert_arena(decl: Any) -> Arena:
    """Check one ``arena`` block and convert it (reading its map, when it names one)."""
    what = f"arena '{decl.name}'"
    zone_props = [p for p in decl.properties if type(p).__name__ == "ZoneProperty"]
    props = single_properties([p for p in decl.properties if p not in zone_props], what)
    if "UnknownCells" in props and "ArenaMap" not in props:
        fail(
            props["UnknownCells"], "'unknown' says what a map's unknown cells are, and this arena has no map"
        )
    if "ArenaMap" in props and "ArenaSize" in props:
        fail(props["ArenaSize"], "an arena built on a map takes its size from the map: remove 'size'")
    if "ArenaSize" not in props and "ArenaMap" not in props:
        fail(decl, f"{what} has no size (add e.g. 'size 1400 x 1050 cm', or 'map \"hall.yaml\"')")
    for key, example in (("StartProperty", "start (60, 60)"), ("GoalProperty", "goal (1340, 990)")):
        if key not in props:
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
    points = {}
    for key, label in (("StartProperty", "start"), ("GoalProperty", "goal")):
        point = props[key].point
        problem = task_point_problem(label, (point.x, point.y), width, height, radius)
        if problem is None and base is not None:
            from mazegen.maps import point_on_walls  # numpy: only for an arena on a map

            problem = point_on_walls(base, label, (point.x, point.y), radius)
        if problem is not None:
            fail(point, problem)
        points[label] = (point.x, point.y)
    if points["start"] == points["goal"]:
        fail(props["GoalProperty"], "start and goal are the same point")
    grid = props["GridProperty"].cell if "GridProperty" in props else None
    if grid is not None and not 0 < grid <= min(width, height) / 4:
        fail(
            props["GridProperty"],
            f"grid cell must be positive and at most a quarter of the arena's shorter side, got {grid:g}",
        )
    if grid is not None and max(width, height) / grid > MAX_GRID_CELLS:
        fail(props["GridProperty"], f"grid cell {grid:g} makes more than {MAX_GRID_CELLS} cells on a side")
    zones = convert_zones(zone_props, width, height)
    return Arena(decl.name, width, height, unit, points["start"], points["goal"], radius, grid, base, zones)


def _base(prop: Any, unknown: Any) -> BaseMap:
    """The map ``map "FILE" [UNIT]`` names, relative to the file that declares the arena."""
    unit = prop.unit or "m"
    if unit not in METRES_PER_UNIT:
        fail(prop, f"a map's cells are in metres: give its arena in mm, cm or m (map {quoted(prop.file)} cm)")
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
