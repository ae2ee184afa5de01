"""IR-SIM worlds: one YAML per scenario that ``irsim.make(path)`` loads.

The world holds one differential-drive robot, a disc of the arena's robot radius (the box of its
``footprint``, when the robot block gives one) at the start,
heading toward the goal, with the driven robot's limits (the spec's robot block, else
:func:`mazegen.spec.robot_for` the arena) and its 2D lidar; and one static obstacle per convex
part of every element (a ``rectangle`` when the part is one, else a ``polygon``), for a floor built
on a map a ``rectangle`` per rectangle of the map's merged blocked cells, plus four walls
just outside the arena, since IR-SIM's world size bounds nothing. Lengths are metres, as in the
ROS and Gazebo exports; the frame is the arena's. The file names no other file (no
``obstacle_map`` image, whose path IR-SIM resolves from the current directory), so it loads the
same from any folder.
"""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

from mazegen.errors import MazeError, MazeNote
from mazegen.maps import wall_boxes
from mazegen.runtime.documents import Floor, safe_name
from mazegen.runtime.exporters._floor import ExportOptions, map_note, rectangle_of, task_comments, yaml_number
from mazegen.runtime.exporters._gazebo import WALL_THICKNESS
from mazegen.spec import Arena, BaseMap, Robot, robot_for

FULL_TURN = 2 * math.pi - 1e-12
"""A field of view this wide is a full turn (as the simulator's lidar takes it)."""


def _flow(values: Sequence[float]) -> str:
    """``[1.5, 0.0, 2.0]``: a YAML flow sequence of numbers."""
    return "[" + ", ".join(yaml_number(float(v)) for v in values) + "]"


def floor_robot(floor: Floor) -> Robot:
    """The robot the scenario is driven with: the spec's robot block, else the arena's defaults.

    Raises:
        MazeError: When the document's arena has no robot radius (IR-SIM's robot is a disc).
    """
    arena = floor.arena
    radius = float(arena.get("robot_radius", 0.0))
    if not radius > 0:
        raise MazeError(
            "an IR-SIM robot needs the arena's robot radius, which is not given", filename=floor.where
        )
    if floor.spec is not None:
        return floor.spec.robot_or_default
    start, goal = (tuple(float(v) for v in arena[key]) for key in ("start", "goal"))
    return robot_for(
        Arena(
            str(arena.get("name", "arena")),
            float(arena["width"]),
            float(arena["height"]),
            str(arena.get("unit")),
            (start[0], start[1]),
            (goal[0], goal[1]),
            radius,
        )
    )


def _start_pose(arena: dict[str, Any]) -> tuple[float, float, float]:
    """``(x, y, theta)`` at the arena's start, heading toward the goal (arena units)."""
    (sx, sy), (gx, gy) = arena["start"], arena["goal"]
    return float(sx), float(sy), math.atan2(float(gy) - float(sy), float(gx) - float(sx))


def _beams(beams: int, fov: float) -> str:
    """IR-SIM lidar keys that cast the beams of MazeGen's simulator, in the same directions.

    IR-SIM spreads ``number`` beams from edge to edge of ``angle_range``, as MazeGen does for a
    field of view under a full turn; a full turn MazeGen starts behind the robot and does not
    repeat, so its range is one spacing short and the sensor is turned back by half a spacing.
    """
    if fov < FULL_TURN:
        return f"angle_range: {yaml_number(fov)}, number: {beams}"
    spacing = 2 * math.pi / beams
    return (
        f"angle_range: {yaml_number(2 * math.pi - spacing)}, number: {beams}, "
        f"offset: {_flow((0.0, 0.0, -spacing / 2))}"
    )


def _shape(robot: Robot, radius_m: float, metres: float) -> str:
    """The robot's IR-SIM shape: the box of its footprint, centred on it, else the arena's disc."""
    if robot.footprint is None:
        return f"{{name: circle, radius: {yaml_number(radius_m)}}}"
    length, width = (side * metres for side in robot.footprint)
    return f"{{name: rectangle, length: {yaml_number(length)}, width: {yaml_number(width)}}}"


def _robot(floor: Floor, metres: float) -> list[str]:
    robot = floor_robot(floor)
    arena = floor.arena
    x, y, heading = _start_pose(arena)
    gx, gy = (float(v) * metres for v in arena["goal"])
    lidar = (
        f"{{type: lidar2d, range_min: 0.0, range_max: {yaml_number(robot.lidar_range * metres)}, "
        f"{_beams(robot.beams, robot.fov)}}}"
        if robot.lidar_range > 0 and robot.beams > 0
        else ""
    )
    return [
        "robot:",
        "  - name: robot",
        "    kinematics: {name: diff}",
        f"    shape: {_shape(robot, float(arena['robot_radius']) * metres, metres)}",
        f"    state: {_flow((x * metres, y * metres, heading))}",
        f"    goal: {_flow((gx, gy, heading))}",
        f"    goal_threshold: {yaml_number(robot.goal_tolerance * metres)}",
        f"    vel_min: {_flow((robot.min_speed * metres, -robot.max_turn))}",
        f"    vel_max: {_flow((robot.max_speed * metres, robot.max_turn))}",
        f"    acce: {_flow((robot.accel * metres, robot.turn_accel))}",
        f"    sensors: [{lidar}]",
    ]


def _rectangle(name: str, centre: Sequence[float], length: float, width: float, yaw: float) -> list[str]:
    return [
        f"  - name: {json.dumps(name)}",
        f"    shape: {{name: rectangle, length: {yaml_number(length)}, width: {yaml_number(width)}}}",
        f"    state: {_flow((centre[0], centre[1], yaw))}",
    ]


def _parts(floor: Floor, metres: float) -> Iterator[list[str]]:
    """Each convex part of each element, in the document's order: ``element_01_hwall_part_0``."""
    elements = floor.document["elements"]
    digits = max(2, len(str(len(elements))))
    for index, element in enumerate(elements, start=1):
        kind = safe_name(str(element.get("type", "element")))
        for k, part in enumerate(element["parts"]):
            name = f"element_{index:0{digits}d}_{kind}_part_{k}"
            corners = np.asarray(part, dtype=np.float64) * metres
            rectangle = rectangle_of(corners)
            if rectangle is not None:
                yield _rectangle(name, *rectangle)
            else:
                vertices = ", ".join(_flow(point) for point in corners)
                yield [
                    f"  - name: {json.dumps(name)}",
                    f"    shape: {{name: polygon, vertices: [{vertices}]}}",
                    "    state: [0.0, 0.0, 0.0]",  # IR-SIM's default state is [1, 1, 0]
                ]


def _map_walls(base: BaseMap | None, metres: float) -> Iterator[list[str]]:
    """The walls of the map the floor is built on, if any: a rectangle per rectangle of its merged
    blocked cells, ``map_wall_K``."""
    for k, (x0, y0, x1, y1) in enumerate(wall_boxes(base) if base is not None else ()):
        centre = ((x0 + x1) / 2 * metres, (y0 + y1) / 2 * metres)
        yield _rectangle(f"map_wall_{k}", centre, (x1 - x0) * metres, (y1 - y0) * metres, 0.0)


def _walls(width: float, height: float) -> Iterator[list[str]]:
    """Four walls, their inner faces on the arena's edges."""
    t = WALL_THICKNESS
    yield _rectangle("wall_south", (width / 2, -t / 2), width + 2 * t, t, 0.0)
    yield _rectangle("wall_north", (width / 2, height + t / 2), width + 2 * t, t, 0.0)
    yield _rectangle("wall_west", (-t / 2, height / 2), t, height, 0.0)
    yield _rectangle("wall_east", (width + t / 2, height / 2), t, height, 0.0)


def irsim_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.yaml``: the scenario as an IR-SIM world.

    Raises:
        MazeError: When the arena's unit has no size in metres and no ``--scale`` is given, the
            arena has no robot radius, or the floor is built on a map and its spec is unknown.
    """
    metres = floor.metres_per_unit(options)
    base = floor.base("an IR-SIM world")
    arena = floor.arena
    width, height = float(arena["width"]) * metres, float(arena["height"]) * metres
    robot = floor_robot(floor)
    if robot.contact == "continue":
        warnings.warn(
            "IR-SIM's world stops a robot at its first contact (collision_mode stop); this spec's robot "
            "drives on after a touch (contact continue), which the IR-SIM world does not carry",
            MazeNote,
            stacklevel=2,
        )
    step = robot.step
    note = map_note(floor, metres)
    t = WALL_THICKNESS
    lines = [
        f"# IR-SIM world of MazeGen scenario {json.dumps(floor.document.get('scenario'))}, "
        f"{json.dumps(safe_name(floor.source.name))}:",
        f"# metres (1 arena unit = {metres:g} m), radians; the arena's lower-left corner at (0, 0)",
        *([f"# {note}"] if note else []),
        *(f"# {line}" for line in task_comments(floor, metres, (0.0, 0.0))),
        "world:",
        f"  width: {yaml_number(width + 2 * t)}",
        f"  height: {yaml_number(height + 2 * t)}",
        f"  offset: {_flow((-t, -t))}",
        f"  step_time: {yaml_number(step)}",
        "  collision_mode: stop",
        *_robot(floor, metres),
        "obstacle:",
    ]
    for obstacle in (*_parts(floor, metres), *_map_walls(base, metres), *_walls(width, height)):
        lines.extend(obstacle)
    return {f"{floor.name}.yaml": ("\n".join(lines) + "\n").encode("utf-8")}
