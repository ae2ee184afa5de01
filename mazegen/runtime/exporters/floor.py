"""What every export of a floor shares: its options, its scale in metres, its grids, and safe names.

Drawings, JSON and Gazebo worlds need only the document (its elements' world
polygons). Occupancy maps need the engine's own grid, which the floor's spec defines
(:class:`~mazegen.runtime.documents.floor.Floor`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.documents.floor import Floor
from mazegen.runtime.geometry.cspace import Grid, grid_of, point_grid_of
from mazegen.runtime.navigation.paths import free_cells
from mazegen.spec import Arena

EXPORT_METRES_PER_UNIT = {"mm": 0.001, "cm": 0.01, "m": 1.0, "px": 0.01}
"""Metres per arena unit in exports: ``px`` has no physical size, so exports take 1 px = 1 cm
(:data:`mazegen.spec.METRES_PER_UNIT` sizes a pixel from the robot instead)."""

MAX_CELLS_PER_SIDE = 4096
"""Largest grid side a grid export accepts: beyond it maps are too large to search."""

SCALE_BOUNDS = (1e-6, 1000.0)
"""Metres per arena unit an export accepts: from micrometres to kilometres, which the
exports' six decimals of a metre and their coordinates can still write."""


_UNSAFE = re.compile(r"[\s\x00-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")
"""Whitespace, control characters, lone surrogates and the two non-characters XML forbids."""


def safe_name(text: str) -> str:
    """``text`` with each character :data:`_UNSAFE` matches replaced by ``_``.

    Safe in file names, XML text and comments, YAML and the tab-separated lines of
    MovingAI's ``.scen``, whatever name the user's file has.
    """
    return _UNSAFE.sub("_", text)


_RIGHT_ANGLE = 1e-3
"""Largest |cos| between neighbouring edges of a rectangular part (rounded vertices are not exact)."""


def yaml_number(value: float) -> str:
    """A YAML number: at most nine decimals, no ``-0.0``."""
    return repr(round(value, 9) + 0.0)


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
        scale: Metres per arena unit, or None for the unit's own (:data:`EXPORT_METRES_PER_UNIT`).
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
        return [name for name in ("scale", "cell") if getattr(self, name) is not None]


def file_stem(floor: Floor) -> str:
    """Stem every file exported of ``floor`` is named after (``best-01``), made safe (:func:`safe_name`)."""
    return safe_name(floor.source.stem)


def export_scale(floor: Floor, options: ExportOptions) -> float:
    """Metres per arena unit of an export: ``options.scale``, else the arena unit's
    (:data:`EXPORT_METRES_PER_UNIT`).

    Raises:
        MazeError: For a unit of unknown size and no scale.
    """
    if options.scale is not None:
        return options.scale
    unit = floor.arena.get("unit")
    if unit not in EXPORT_METRES_PER_UNIT:
        raise MazeError(
            f"arena unit {unit!r} has no known size in metres: give --scale", filename=floor.where
        )
    return EXPORT_METRES_PER_UNIT[unit]


def occupancy(floor: Floor, cell: float | None = None) -> tuple[np.ndarray, Grid]:
    """``bool[rows, cols]``: the cells the elements occupy on a grid of ``cell``, by default the
    engine's (row 0 at y = 0).

    The engine's configuration space for a point robot: no disc dilation, and blocked
    only where elements touch, or for a partial edge cell whose centre lies outside the arena.

    Raises:
        MazeError: For a floor without its spec, or a cell that gives too large a grid.
    """
    grid = point_grid_of(_arena_of_cell(floor, cell, "an occupancy map"))
    return ~free_cells(floor.population, grid, 0), grid


def configuration_space(floor: Floor, cell: float | None) -> tuple[np.ndarray, Grid]:
    """``bool[rows, cols]`` free cells for the robot's centre, on a grid of ``cell`` (row 0 at y = 0).

    Raises:
        MazeError: For a floor without its spec, or a cell that gives too large a grid.
    """
    grid = grid_of(_arena_of_cell(floor, cell, "a grid map"))
    return free_cells(floor.population, grid, 0), grid


def _arena_of_cell(floor: Floor, cell: float | None, what: str) -> Arena:
    """The spec's arena with its grid of ``cell`` arena units (None: the spec's own grid)."""
    arena = floor.needs_spec(what).arena
    if cell is None:
        return arena
    sides = [math.ceil(side / cell - 1e-9) for side in (arena.width, arena.height)]
    if max(sides) > MAX_CELLS_PER_SIDE:
        raise MazeError(
            f"--cell {cell:g} gives a {sides[0]} x {sides[1]} grid; "
            f"at most {MAX_CELLS_PER_SIDE} cells a side: choose a larger cell"
        )
    return replace(arena, grid=cell)
