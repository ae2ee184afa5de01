"""ROS and ROS 2 occupancy maps: a PGM image and the YAML that ``map_server`` loads.

The image is the engine's own occupancy grid (the cells the elements and the base map's walls
touch, see :meth:`~mazegen.runtime.documents._floor.Floor.occupancy`), one pixel per cell, framed by one
occupied cell on each side for the arena's edge, which the engine never lets the robot cross. Pixels
are 0 (occupied) or 254 (free); 205 (unknown) is never written, and the YAML's
thresholds read it back as unknown, not free. Lengths are metres whatever the
arena's unit. The map frame is the arena's, its lower-left corner at (0, 0); or, for a floor built
on a map, that map's own frame, so the export lies where the user's map lies. A floor of several
tasks also gets ``NAME.tasks.yaml``: each task's start and goal poses in that frame.
"""

from __future__ import annotations

import json

import numpy as np

from mazegen.runtime.documents import Floor, safe_name
from mazegen.runtime.exporters._floor import ExportOptions, arena_corner, floor_tasks, task_pose, yaml_number

OCCUPIED = 0
FREE = 254
OCCUPIED_THRESH = 0.65
FREE_THRESH = 0.196
"""Below 50/255 = 0.19608, the occupancy an unknown (205) pixel reads as."""


def map_image(occupied: np.ndarray) -> bytes:
    """Binary PGM (P5) of a grid whose row 0 is at y = 0, framed by occupied cells.

    Args:
        occupied: ``bool[rows, cols]``, row 0 the lowest.

    Returns:
        The image bytes: ``cols + 2`` by ``rows + 2`` pixels, top row first.
    """
    framed = np.pad(occupied, 1, constant_values=True)[::-1]
    pixels = np.where(framed, OCCUPIED, FREE).astype(np.uint8)
    height, width = pixels.shape
    return f"P5\n{width} {height}\n255\n".encode("ascii") + pixels.tobytes()


def ros_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.pgm`` and ``NAME.yaml`` of a scenario, on a grid of ``options.cell`` (default the engine's).

    Raises:
        MazeError: When the scenario's spec is unknown or its unit has no size in metres.
    """
    occupied, grid = floor.occupancy(options.cell)
    metres = floor.metres_per_unit(options)
    resolution = grid.cell * metres
    corner = arena_corner(floor, metres)
    image = f"{floor.name}.pgm"
    arena = floor.arena
    start, goal = (
        [yaml_number(v * metres + at) for v, at in zip(arena[key], corner)] for key in ("start", "goal")
    )
    source = json.dumps(safe_name(floor.source.name))
    lines = [f"# MazeGen scenario {json.dumps(floor.document.get('scenario'))}, {source}:"]
    if "map" in arena:
        lines.append(
            f"# built on map {json.dumps(safe_name(str(arena['map']['source'])))}: its walls and the elements"
        )
    lines += [
        f"# {grid.cols} x {grid.rows} cells of {yaml_number(resolution)} m, framed by one occupied cell",
        f"# start [{', '.join(start)}], goal [{', '.join(goal)}], "
        f"robot radius {yaml_number(arena.get('robot_radius', 0.0) * metres)} (metres, map frame)",
        f"image: {json.dumps(image)}",
        "mode: trinary",
        f"resolution: {yaml_number(resolution)}",
        # The frame's cell lies below and left of the arena's corner.
        f"origin: [{yaml_number(corner[0] - resolution)}, {yaml_number(corner[1] - resolution)}, 0.0]",
        "negate: 0",
        f"occupied_thresh: {OCCUPIED_THRESH}",
        f"free_thresh: {FREE_THRESH}",
    ]
    files = {image: map_image(occupied), f"{floor.name}.yaml": ("\n".join(lines) + "\n").encode("utf-8")}
    if floor_tasks(floor):
        files[f"{floor.name}.tasks.yaml"] = tasks_yaml(floor, metres, corner, source)
    return files


def tasks_yaml(floor: Floor, metres: float, corner: tuple[float, float], source: str) -> bytes:
    """The tasks of a floor of several, beside its map: each one's name, start and goal poses in the
    map frame (metres, yaw in radians, null for no heading), the optimal length of MazeGen's path
    and the narrowest gap on it (metres, null where the task has no path)."""
    measured = {task.get("name"): task.get("metrics") or {} for task in floor.document.get("tasks", ())}
    lines = [
        f"# Tasks of MazeGen scenario {json.dumps(floor.document.get('scenario'))}, {source}: poses in",
        "# the map frame (metres, yaw in radians; null: any heading); MazeGen's optimal path length and",
        "# the narrowest gap on it (metres; null: no path)",
        "tasks:",
    ]
    for task in floor_tasks(floor):
        metrics = measured.get(task["name"], {})
        lines.append(f"  - name: {json.dumps(str(task['name']))}")
        for end in ("start", "goal"):
            x, y, yaw = task_pose(task, end, metres, corner)
            lines.append(
                f"    {end}: {{x: {yaml_number(x)}, y: {yaml_number(y)}, yaw: {_or_null(yaw, 1.0)}}}"
            )
        lines.append(f"    optimal_length: {_or_null(metrics.get('path_length'), metres)}")
        lines.append(f"    narrowest: {_or_null(metrics.get('narrowest'), metres)}")
    return ("\n".join(lines) + "\n").encode("utf-8")


def _or_null(value: float | None, times: float) -> str:
    return "null" if value is None else yaml_number(value * times)
