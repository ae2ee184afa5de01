"""Occupancy maps as MazeGen imports them: a ROS map_server map, a grid of cells (``.npy``, ``.txt``), or a
world of BARN's (``barn-train.json``), each read into an :class:`OccupancyMap`.

A cell is free only where map_server would call it free (occupancy 0); occupied, unknown and partly
occupied cells are all obstacles, since a robot may not plan through what the map does not know.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.maps._files import (
    read_cell_array,
    read_cell_text,
    read_image,
    read_map_yaml,
    read_pgm,
)
from mazegen.spec import Point

RESOLUTION_BOUNDS = (0.01, 1000.0)
"""Metres per cell a map may have: a document's four decimals of a metre still place a finer cell's
edges within it (see :mod:`~mazegen.runtime.documents._import`)."""

BARN_CELL = 0.15
"""Metres per cell of BARN's grids (its ``conventions``)."""
BARN_MARGIN = 10
"""Free cells added before BARN's first column and after its last: its robots start 1 m before the grid
(BARN's C-space counts the cells off the map as free)."""
BARN_ORIGIN = (-4.5, round(5.1 - BARN_MARGIN * BARN_CELL, 9))
"""Gazebo's (x, y) of the arena's lower-left corner: cell (row, col) is centred at
x = -4.425 + 0.15 row, y = 5.175 + 0.15 col (world_writer.py)."""

MODES = ("trinary", "scale", "raw")


@dataclass(frozen=True)
class OccupancyMap:
    """A map read: which cells are obstacles, and where it lies in the frame of its source.

    Attributes:
        name: What to name the scenario after (the file's stem, ``barn_world_N``).
        occupied: ``bool[rows, cols]``, row 0 the lowest (y up), column 0 at the left (x right).
        resolution: Metres per cell.
        origin: The source frame's (x, y) of the lower-left corner of cell (0, 0), metres.
        frame: The source frame, for messages and notes (``map``, ``Gazebo``).
        task: The source's own start and goal in its frame, when it has one (BARN's).
        unknown: ``bool[rows, cols]``: the cells of ``occupied`` the source marks unknown rather than
            occupied (map_server's), or ``None`` when it knows every cell.
    """

    name: str
    occupied: np.ndarray
    resolution: float
    origin: Point
    frame: str
    task: tuple[Point, Point] | None = None
    unknown: np.ndarray | None = None


def scenario_name(stem: str) -> str:
    """``stem`` as a name the language takes: other characters than letters, digits and ``_`` become ``_``,
    and ``map_`` comes first unless it starts with a letter (``scenario-01`` -> ``scenario_01``)."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", stem)
    return name if name[:1].isalpha() else f"map_{name}"


def checked_resolution(value: Any, what: str, filename: str | None = None) -> float:
    """``value`` as metres per cell within :data:`RESOLUTION_BOUNDS`, or a one-line error naming ``what``."""
    low, high = RESOLUTION_BOUNDS
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise MazeError(
            f"{what} must be from {low:g} to {high:g} metres per cell, got {value}", filename=filename
        )
    return float(value)


def read_occupancy_map(
    path: Path, *, resolution: float | None = None, world: int | None = None
) -> OccupancyMap:
    """The map of ``path``: by its suffix, a map_server YAML, a ``.npy`` or ``.txt`` grid, or BARN's JSON.

    Args:
        path: The map.
        resolution: Metres per cell of a ``.npy`` or ``.txt`` grid (default 1).
        world: The world of a BARN file.

    Raises:
        MazeError: For an unknown suffix, an option the format does not take, or a file that cannot be read.
    """
    suffix = path.suffix.lower()
    if suffix not in (".yaml", ".yml", ".npy", ".txt", ".json"):
        raise MazeError(
            f"unknown map format {suffix or path.name!r}: give a map_server .yaml, a .npy or .txt grid, "
            "or BARN's .json",
            filename=str(path),
        )
    if resolution is not None and suffix not in (".npy", ".txt"):
        raise MazeError("--resolution is for .npy and .txt grids: this map gives its own", filename=str(path))
    if world is not None and suffix != ".json":
        raise MazeError("--world is for BARN's .json", filename=str(path))
    if suffix == ".json":
        return _barn_world(path, world)
    if suffix in (".yaml", ".yml"):
        return _map_server_map(path)
    cells = read_cell_array(path) if suffix == ".npy" else read_cell_text(path)
    cell = 1.0 if resolution is None else resolution
    return OccupancyMap(scenario_name(path.stem), cells[::-1].copy(), cell, (0.0, 0.0), "grid")


def _required(values: dict[str, Any], key: str, path: Path) -> Any:
    if key not in values:
        raise MazeError(f"the map has no '{key}'", filename=str(path))
    return values[key]


def _threshold(values: dict[str, Any], key: str, path: Path) -> float:
    value = _required(values, key, path)
    if isinstance(value, bool) or not isinstance(value, float) or not 0 <= value <= 1:
        raise MazeError(f"'{key}' must be a number from 0 to 1, got {value}", filename=str(path))
    return value


def _map_server_map(path: Path) -> OccupancyMap:
    """A ROS map_server map: its YAML read with nav2's semantics, its image beside it."""
    values = read_map_yaml(path)
    image = _required(values, "image", path)
    resolution = checked_resolution(_required(values, "resolution", path), "'resolution'", str(path))
    origin = _required(values, "origin", path)
    if not (isinstance(origin, list) and len(origin) == 3 and all(math.isfinite(v) for v in origin)):
        raise MazeError("'origin' must be [x, y, yaw]", filename=str(path))
    if origin[2] != 0:
        raise MazeError(
            f"origin yaw {origin[2]:g} is not 0: MazeGen's arenas are not rotated (rotate the map first)",
            filename=str(path),
        )
    negate = _required(values, "negate", path)
    if negate not in (0, 1):  # True and False too
        raise MazeError(f"'negate' must be 0 or 1, got {negate}", filename=str(path))
    occupied_thresh = _threshold(values, "occupied_thresh", path)
    free_thresh = _threshold(values, "free_thresh", path)
    mode = values.get("mode", "trinary")
    if mode not in MODES:
        raise MazeError(f"'mode' must be one of {', '.join(MODES)}, got {mode}", filename=str(path))
    image_path = path.parent / str(image)
    if image_path.suffix.lower() == ".pgm":
        (pixels, maxval), alpha = read_pgm(image_path), None
    else:
        pixels, alpha, maxval = read_image(image_path)
    shade = pixels / maxval
    if mode == "raw":  # the pixel is the occupancy in percent, 255 unknown; negate does not apply
        value = np.rint(shade * 255)
        free, unknown = value == 0, value == 255
    else:
        occupancy = shade if negate else 1.0 - shade
        free = occupancy < free_thresh
        if mode == "trinary":  # neither free nor above occupied_thresh: unknown
            unknown = ~free & (occupancy <= occupied_thresh)
        else:  # scale: values between the thresholds are costs, a transparent pixel is unknown
            unknown = np.zeros_like(free) if alpha is None else alpha < 1.0
            free &= ~unknown
    return OccupancyMap(
        scenario_name(path.stem),
        ~free[::-1],
        resolution,
        (origin[0], origin[1]),
        "map",
        unknown=unknown[::-1].copy(),
    )


def _barn_world(path: Path, world: int | None) -> OccupancyMap:
    """One world of BARN's ``barn-train.json``, with the start and goal of its 2020 timing runs.

    BARN's rows run along Gazebo's x and its columns along y, as the arena's x and y do: the arena is
    Gazebo's frame moved by :data:`BARN_ORIGIN`, with :data:`BARN_MARGIN` free cells added at each end
    of the columns.
    """
    try:
        document = json.loads(read_text(path, "BARN worlds"))
    except json.JSONDecodeError as error:
        raise MazeError(f"not valid JSON: {error.msg}", filename=str(path), line=error.lineno) from None
    worlds = document.get("worlds") if isinstance(document, dict) else None
    if not isinstance(worlds, list) or not all(isinstance(w, dict) and "grid" in w for w in worlds):
        raise MazeError(
            "not a file of BARN worlds (a 'worlds' list, each with its 'grid')", filename=str(path)
        )
    numbers = [w.get("world") for w in worlds]
    if world is None:
        raise MazeError(
            f"a file of {len(worlds)} BARN worlds: choose one with --world N ({_listed(numbers)})",
            filename=str(path),
        )
    if world not in numbers:
        raise MazeError(f"no world {world} in this file ({_listed(numbers)})", filename=str(path))
    chosen = worlds[numbers.index(world)]
    rows = chosen["grid"]
    if not (
        isinstance(rows, list) and rows and all(isinstance(r, str) and len(r) == len(rows[0]) for r in rows)
    ):
        raise MazeError(
            f"world {world}: 'grid' must be rows of '#' and '.' of one length", filename=str(path)
        )
    grid = np.array([[char == "#" for char in row] for row in rows], dtype=bool)
    occupied = np.pad(grid.T, ((BARN_MARGIN, BARN_MARGIN), (0, 0)))
    task = _barn_task(chosen.get("start_goal", {}))
    return OccupancyMap(f"barn_world_{world}", occupied, BARN_CELL, BARN_ORIGIN, "Gazebo", task)


def _barn_task(start_goal: dict[str, Any]) -> tuple[Point, Point] | None:
    """The start and goal of BARN's 2020 timing runs (Gazebo frame), when the world gives them."""
    points = [start_goal.get(f"timer_2020_{end}_gazebo") for end in ("start", "goal")]
    start, goal = points
    if not (isinstance(start, list) and len(start) >= 2 and isinstance(goal, list) and len(goal) >= 2):
        return None
    return (float(start[0]), float(start[1])), (float(goal[0]), float(goal[1]))


def _listed(numbers: list[Any]) -> str:
    shown = ", ".join(str(n) for n in numbers[:5])
    return f"worlds {shown}{', ...' if len(numbers) > 5 else ''}"
