"""What every export shares: its options, and the numbers and shapes the formats write alike.

The scenario an export reads is a :class:`~mazegen.runtime.documents._floor.Floor`.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.documents import Floor, safe_name
from mazegen.spec import METRES_PER_UNIT

SCALE_BOUNDS = (1e-6, 1000.0)
"""Metres per arena unit an export accepts: from micrometres to kilometres, which the
exports' six decimals of a metre and their coordinates can still write."""


_RIGHT_ANGLE = 1e-3
"""Largest |cos| between neighbouring edges of a rectangular part (rounded vertices are not exact)."""


def yaml_number(value: float) -> str:
    """A YAML number: at most nine decimals, no ``-0.0``."""
    return repr(round(value, 9) + 0.0)


def arena_corner(floor: Floor, metres: float) -> tuple[float, float]:
    """The map frame's ``(x, y)`` of the arena's lower-left corner in the export's metres: (0, 0), or
    the origin of the map the floor is built on, scaled as the floor is (``--scale`` scales the map
    about its frame's origin).

    Raises:
        MazeError: For a floor on a map whose spec is unknown.
    """
    base = floor.base("an export")
    if base is None:
        return 0.0, 0.0
    units = METRES_PER_UNIT[floor.arena["unit"]]  # the spec's metres per unit (a map's arena has mm, cm or m)
    return base.origin[0] / units * metres, base.origin[1] / units * metres


def map_note(floor: Floor, metres: float) -> str | None:
    """Where a world in the arena's frame lies in the frame of the map the floor is built on
    (``on map "hall.yaml": (x, y) here is (x -2, y -1.5) in its frame``), None on no map."""
    if "map" not in floor.arena:
        return None
    x, y = arena_corner(floor, metres)
    source = json.dumps(safe_name(str(floor.arena["map"]["source"])))
    return f"on map {source}: (x, y) here is (x {x:+g}, y {y:+g}) in its frame"


def floor_tasks(floor: Floor) -> list[dict]:
    """The tasks of a floor of several (its document's ``arena.tasks``), none for a floor of one."""
    return list(floor.arena.get("tasks", ()))


def task_pose(
    task: dict, end: str, metres: float, corner: tuple[float, float]
) -> tuple[float, float, float | None]:
    """``(x, y, yaw)`` of a task's ``start`` or ``goal`` in an export's frame (metres, the arena's corner
    at ``corner``), yaw in radians or None where the task gives no heading."""
    x, y = (float(v) * metres + at for v, at in zip(task[end], corner))
    heading = task.get(f"{end}_heading")
    return x, y, None if heading is None else math.radians(heading)


def task_comments(floor: Floor, metres: float, corner: tuple[float, float]) -> list[str]:
    """One line per task of a floor of several, ``task "dock -> line1": start [x, y, yaw], goal [...]``
    (metres, radians, ``~`` for no heading), for a world's comments."""

    def shown(pose: tuple[float, float, float | None]) -> str:
        return "[" + ", ".join("~" if v is None else yaml_number(v) for v in pose) + "]"

    lines = []
    for task in floor_tasks(floor):
        start, goal = (shown(task_pose(task, end, metres, corner)) for end in ("start", "goal"))
        lines.append(f"task {json.dumps(str(task['name']))}: start {start}, goal {goal}")
    return lines


def rectangle_of(corners: np.ndarray) -> tuple[tuple[float, float], float, float, float] | None:
    """Centre, length, width and yaw of a four-cornered part if it is a rectangle, else None."""
    if len(corners) != 4:
        return None
    edges = np.roll(corners, -1, axis=0) - corners
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    if lengths.min() <= 0:
        return None
    cosines = np.abs(np.sum(edges * np.roll(edges, -1, axis=0), axis=1)) / (lengths * np.roll(lengths, -1))
    if cosines.max() > _RIGHT_ANGLE:
        return None
    cx, cy = corners.mean(axis=0)
    return (float(cx), float(cy)), float(lengths[0]), float(lengths[1]), math.atan2(edges[0, 1], edges[0, 0])


@dataclass(frozen=True)
class ExportOptions:
    """Settings of an export that are not in the scenario, checked as they are made.

    Attributes:
        scale: Metres per arena unit, or None for the unit's own
            (:data:`~mazegen.runtime.documents._floor.EXPORT_METRES_PER_UNIT`).
        cell: Cell size of a grid map (ROS, MovingAI) in arena units, or None for the engine's grid cell.

    Raises:
        MazeError: For a scale outside :data:`SCALE_BOUNDS`, or a cell that is not a positive number.
    """

    scale: float | None = None
    cell: float | None = None

    def __post_init__(self) -> None:
        low, high = SCALE_BOUNDS
        if self.scale is not None and not low <= self.scale <= high:  # NaN too
            raise MazeError(
                f"--scale must be from {low:g} to {high:g} metres per arena unit, got {self.scale:g}"
            )
        if self.cell is not None and not (math.isfinite(self.cell) and self.cell > 0):
            raise MazeError(f"--cell must be a positive number of arena units, got {self.cell:g}")

    def given(self) -> list[str]:
        """The names of the options set (``["cell"]``)."""
        return [field.name for field in fields(self) if getattr(self, field.name) is not None]
