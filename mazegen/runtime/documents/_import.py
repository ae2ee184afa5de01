"""Scenario documents from an occupancy map (``mazegen import``): its obstacle cells merged into walls, a
spec of its arena for every command to read them under, and one document per task.

The arena is the map's extent, in metres, its lower-left corner at (0, 0); its navigation grid is the
map's cells. Each wall is a rect inset by :data:`INSET` of a cell on every side, so that the engine,
which marks every cell a part touches, marks exactly the map's obstacle cells: an edge lying on a cell
border would mark the neighbour too, and a document's four decimals could move it there.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.maps import Cells, OccupancyMap, draw_tasks, standing_cells, wall_rectangles
from mazegen.runtime.documents._scenario import FORMAT, VERSION, completed_document
from mazegen.runtime.documents._task import task_spec
from mazegen.spec import Point, Spec, task_point_problem

INSET = 0.02
"""Fraction of a cell each wall keeps off the cell borders: at the smallest resolution (0.01 m) still
twice a document's rounding of a corner (1e-4 m)."""

MAX_WALLS = 1000
"""A scenario holds at most this many elements (the language's bound on ``max elements``)."""

MAX_CELLS_PER_SIDE = 1024
"""The most cells a side of the navigation grid may have (the language's bound on ``grid``)."""

WALL = "wall"
"""The one element type of an imported floor."""


@dataclass(frozen=True)
class ImportedMap:
    """A map on its way to documents: its walls, its arena, and where the robot's centre may stand.

    Attributes:
        map: The map read.
        robot_radius: The robot's radius, metres.
    """

    map: OccupancyMap
    robot_radius: float

    def __post_init__(self) -> None:
        rows, cols = self.map.occupied.shape
        if max(rows, cols) > MAX_CELLS_PER_SIDE or min(rows, cols) < 4:
            raise MazeError(
                f"the map is {cols} x {rows} cells: a floor has 4 to {MAX_CELLS_PER_SIDE} cells a side"
            )
        if 2 * self.robot_radius >= min(self.size):
            raise MazeError(
                f"a robot of radius {self.robot_radius:g} m does not fit in a map of {self.size[0]:g} x "
                f"{self.size[1]:g} m"
            )
        if len(self.walls) > MAX_WALLS:
            raise MazeError(
                f"the map's obstacles make {len(self.walls)} walls: a scenario holds at most {MAX_WALLS} "
                "(use a coarser map)"
            )

    @cached_property
    def walls(self) -> list[Cells]:
        """The obstacle cells merged into rectangles (:func:`wall_rectangles`)."""
        return wall_rectangles(self.map.occupied)

    @property
    def size(self) -> Point:
        """The arena's width and height, metres."""
        rows, cols = self.map.occupied.shape
        return round(cols * self.map.resolution, 9), round(rows * self.map.resolution, 9)

    @cached_property
    def _cells(self) -> tuple[np.ndarray, np.ndarray]:
        return standing_cells(self.map.occupied, self.map.resolution, *self.size, self.robot_radius)

    @property
    def robot_free(self) -> np.ndarray:
        """``bool[rows, cols]``: cells where the robot's centre may stand, as the engine decides it: no
        obstacle cell's centre within the radius of its centre, and no closer to the arena's edge."""
        return self._cells[0]

    @property
    def standing(self) -> np.ndarray:
        """``bool[rows, cols]``: cells of :attr:`robot_free` whose centre keeps the robot's disc off every
        obstacle cell and the edge, touching none: where a drawn task's robot starts and stops (the
        simulator decides contact on the walls' exact shapes, not on their cells' centres)."""
        return self._cells[1]

    def arena_point(self, point: Point) -> Point:
        """A point of the map's frame in the arena's."""
        return round(point[0] - self.map.origin[0], 9), round(point[1] - self.map.origin[1], 9)

    def map_point(self, point: Point) -> Point:
        """A point of the arena in the map's frame."""
        return round(point[0] + self.map.origin[0], 9), round(point[1] + self.map.origin[1], 9)

    def checked_point(self, label: str, given: Point) -> Point:
        """``given`` (the map's frame) in the arena, where the robot can stand.

        Raises:
            MazeError: For a point outside the map, on an obstacle cell (naming it), or nearer an
                obstacle or the map's edge than the robot radius.
        """
        point = self.arena_point(given)
        width, height = self.size
        shown = f"{label} ({given[0]:g}, {given[1]:g})"
        problem = task_point_problem(label, point, width, height, self.robot_radius)
        if problem is not None and not (0 <= point[0] <= width and 0 <= point[1] <= height):
            low, high = self.map_point((0.0, 0.0)), self.map_point((width, height))
            raise MazeError(
                f"{shown} is outside the map, which spans x {low[0]:g}..{high[0]:g}, "
                f"y {low[1]:g}..{high[1]:g} ({self.map.frame} frame)"
            )
        if problem is not None:
            raise MazeError(
                f"{shown} is closer to the map's edge than the robot radius {self.robot_radius:g} m"
            )
        row, col = self._cell(point)
        if self.map.occupied[row, col]:
            raise MazeError(f"{shown} is on an obstacle: cell (column {col}, row {row} from the bottom)")
        # A start whose disc touches a wall is a collision before the first step; a goal is arrived at
        # within the goal tolerance, before any touch (BARN's own goals touch a wall cell's square).
        if not self.robot_free[row, col] or (label == "start" and self._touches(point)):
            raise MazeError(
                f"{shown} is nearer an obstacle than the robot radius {self.robot_radius:g} m: "
                f"cell (column {col}, row {row} from the bottom)"
            )
        return point

    def _touches(self, point: Point) -> bool:
        """Whether the robot's disc on ``point`` touches an obstacle cell (its square, exactly)."""
        cell, radius = self.map.resolution, self.robot_radius
        row, col = self._cell(point)
        reach = int(radius / cell) + 2
        r0, c0 = max(row - reach, 0), max(col - reach, 0)
        near_rows, near_cols = np.nonzero(self.map.occupied[r0 : row + reach + 1, c0 : col + reach + 1])
        dx = np.maximum(np.abs((near_cols + c0 + 0.5) * cell - point[0]) - cell / 2, 0.0)
        dy = np.maximum(np.abs((near_rows + r0 + 0.5) * cell - point[1]) - cell / 2, 0.0)
        return bool((np.hypot(dx, dy) <= radius).any())

    def _cell(self, point: Point) -> tuple[int, int]:
        rows, cols = self.map.occupied.shape
        cell = self.map.resolution
        return min(int(point[1] // cell), rows - 1), min(int(point[0] // cell), cols - 1)

    def random_tasks(self, count: int, seed: int) -> list[tuple[Point, Point]]:
        """``count`` starts and goals at the centres of cells the robot can stand on touching nothing
        (:attr:`standing`), each goal reachable from its start (:func:`draw_tasks`).

        Raises:
            MazeError: When no two free cells are connected for the robot.
        """
        try:
            return draw_tasks(self.robot_free, self.standing, self.map.resolution, count, seed)
        except ValueError:
            raise MazeError(
                f"no two free cells are connected for a robot of radius {self.robot_radius:g} m: "
                "no task can be drawn (give a smaller --robot-radius)"
            ) from None

    def maze_text(self, task: tuple[Point, Point], source: str) -> str:
        """The spec of the floor, in the language: its arena, the wall type and a scenario of its walls."""
        width, height = self.size
        cell = self.map.resolution
        smallest = round(cell * (1 - 2 * INSET), 9)
        (sx, sy), (gx, gy) = task
        origin = self.map.origin
        return "\n".join(
            [
                f"// Imported by mazegen import from {json.dumps(source)}: {len(self.walls)} walls.",
                f"// A point (x, y) of the {self.map.frame} frame is the arena's "
                f"(x {_shift(-origin[0])}, y {_shift(-origin[1])}), metres.",
                "",
                f"element {WALL} {{",
                "    shape rect",
                f"    size {_number(smallest)}..{_number(width)} x {_number(smallest)}..{_number(height)}",
                '    colour "#3d3d3d"  class wall  height 1',
                "}",
                "",
                f"arena {self.map.name} {{",
                f"    size {_number(width)} x {_number(height)} m",
                f"    start ({_number(sx)}, {_number(sy)})   goal ({_number(gx)}, {_number(gy)})",
                f"    robot radius {_number(self.robot_radius)}",
                f"    grid {_number(cell)}",
                "}",
                "",
                f"scenario {self.map.name} on {self.map.name} {{",
                f"    elements {WALL}",
                f"    max elements {max(len(self.walls), 1)}",
                "}",
                "",
                "fitness {",
                "    count",
                "    solvable required",
                "}",
                "",
            ]
        )

    def documents(self, spec: Spec, tasks: list[tuple[Point, Point]]) -> list[dict[str, Any]]:
        """One complete scenario document per task, its walls the map's.

        Raises:
            MazeError: For a task whose start and goal the robot cannot connect.
        """
        cell = self.map.resolution
        inset = INSET * cell
        elements = [
            {
                "type": WALL,
                "x": round((first_col + last_col + 1) * cell / 2, 9),
                "y": round((first_row + last_row + 1) * cell / 2, 9),
                "rotation": 0.0,
                "width": round((last_col - first_col + 1) * cell - 2 * inset, 9),
                "depth": round((last_row - first_row + 1) * cell - 2 * inset, 9),
            }
            for first_row, last_row, first_col, last_col in self.walls
        ]
        documents = []
        for start, goal in tasks:
            document = {"format": FORMAT, "version": VERSION, "scenario": spec.name, "elements": elements}
            document["arena"] = {"start": list(start), "goal": list(goal)}
            complete = completed_document(task_spec(spec, document, self.map.name), document, self.map.name)
            if not complete["metrics"]["solvable"]:
                (x0, y0), (x1, y1) = (self.map_point(point) for point in (start, goal))
                raise MazeError(
                    f"start ({x0:g}, {y0:g}) and goal ({x1:g}, {y1:g}) are not connected for a robot of "
                    f"radius {self.robot_radius:g} m"
                )
            documents.append(complete)
        return documents


def _number(value: float) -> str:
    """A number as the language writes it: decimals, no exponent (``1e-05`` is ``0.00001``)."""
    text = f"{value:.9f}".rstrip("0").rstrip(".")
    return text if text not in ("", "-0") else "0"


def _shift(value: float) -> str:
    return f"{'-' if value < 0 else '+'} {abs(value)!r}"
