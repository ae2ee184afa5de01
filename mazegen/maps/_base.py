"""A map as the base of an arena (``arena hall { map "hall.yaml" }``): read once when the spec is
loaded, kept in the spec as packed cells (:class:`~mazegen.spec.BaseMap`), unpacked where a grid,
a world or an export needs them."""

from __future__ import annotations

import base64
import hashlib
import math
from functools import lru_cache
from pathlib import Path

import numpy as np

from mazegen.maps._cells import wall_rectangles
from mazegen.maps._occupancy import read_occupancy_map
from mazegen.spec import BaseMap, Box

UNKNOWN = ("blocked", "free")
"""What an arena may make of its map's unknown cells (``unknown blocked``, the default, or ``free``)."""


def read_base_map(path: Path, *, source: str, units_per_metre: float, unknown: str = "blocked") -> BaseMap:
    """The base map of ``path`` (a map_server YAML), in arena units of ``1 / units_per_metre`` metres.

    Raises:
        MazeError: For a file that cannot be read as a map (naming it).
    """
    read = read_occupancy_map(path)
    blocked = read.occupied.copy()
    if unknown == "free" and read.unknown is not None:
        blocked &= ~read.unknown
    return base_map_of(
        blocked,
        source=source,
        resolution=read.resolution * units_per_metre,
        origin=read.origin,
        unknown=unknown,
    )


def base_map_of(
    blocked: np.ndarray, *, source: str, resolution: float, origin: tuple[float, float], unknown: str
) -> BaseMap:
    """A :class:`BaseMap` of the cells ``blocked`` (``bool[rows, cols]``, row 0 the lowest)."""
    cells = np.ascontiguousarray(blocked, dtype=bool)
    packed = np.packbits(cells.ravel(), bitorder="little")
    return BaseMap(
        source=source,
        resolution=float(resolution),
        rows=int(cells.shape[0]),
        cols=int(cells.shape[1]),
        origin=(float(origin[0]), float(origin[1])),
        unknown=unknown,
        blocked=base64.b64encode(packed.tobytes()).decode("ascii"),
    )


@lru_cache(maxsize=64)
def base_cells(base: BaseMap) -> np.ndarray:
    """``bool[rows, cols]`` of the base's blocked cells, row 0 the lowest (read-only, unpacked once)."""
    packed = np.frombuffer(base64.b64decode(base.blocked), dtype=np.uint8)
    bits = np.unpackbits(packed, count=base.rows * base.cols, bitorder="little")
    cells = bits.astype(bool).reshape(base.rows, base.cols)
    cells.flags.writeable = False
    return cells


@lru_cache(maxsize=64)
def wall_boxes(base: BaseMap) -> tuple[tuple[float, float, float, float], ...]:
    """The base's walls as few disjoint boxes ``(x0, y0, x1, y1)`` in arena units, together exactly its
    blocked cells (:func:`~mazegen.maps._cells.wall_rectangles`): what worlds extrude and pictures fill."""
    cell = base.resolution
    return tuple(
        (c0 * cell, r0 * cell, (c1 + 1) * cell, (r1 + 1) * cell)
        for r0, r1, c0, c1 in wall_rectangles(base_cells(base))
    )


@lru_cache(maxsize=64)
def free_box(base: BaseMap) -> Box:
    """The smallest box around the base's free cells, in arena units (the whole map when none is free):
    the walls an element ``against wall`` stands against, the inner faces of a building's outer walls."""
    free = ~base_cells(base)
    rows, cols = np.flatnonzero(free.any(axis=1)), np.flatnonzero(free.any(axis=0))
    if rows.size == 0:
        return (0.0, 0.0, base.cols * base.resolution, base.rows * base.resolution)
    cell = base.resolution
    return (
        float(cols[0] * cell),
        float(rows[0] * cell),
        float((cols[-1] + 1) * cell),
        float((rows[-1] + 1) * cell),
    )


def base_on_grid(base: BaseMap, cell: float, rows: int, cols: int) -> np.ndarray:
    """``bool[rows, cols]``: the cells of a grid of ``cell`` (arena units) that a blocked cell of the base
    overlaps (with area: a base cell that only touches a grid cell's edge leaves it free)."""
    blocked = base_cells(base)
    row_of = _cover(base.rows, base.resolution, rows, cell)
    col_of = _cover(base.cols, base.resolution, cols, cell)
    # A grid cell is blocked when any base cell in its rows and columns is: any over rows, then columns.
    out = np.zeros((rows, cols), dtype=bool)
    by_row = np.zeros((rows, base.cols), dtype=bool)
    for r, (a, b) in enumerate(row_of):
        if b > a:
            by_row[r] = blocked[a:b].any(axis=0)
    for c, (a, b) in enumerate(col_of):
        if b > a:
            out[:, c] = by_row[:, a:b].any(axis=1)
    return out


def _cover(count: int, size: float, grid_count: int, grid_size: float) -> list[tuple[int, int]]:
    """For each of ``grid_count`` cells of ``grid_size``, the base cells ``[a, b)`` of ``size`` that overlap
    it with some length (``1e-9`` of a cell of rounding either way)."""
    spans = []
    for k in range(grid_count):
        low, high = k * grid_size / size, (k + 1) * grid_size / size
        a = max(int(np.floor(low + 1e-9)), 0)
        b = min(int(np.ceil(high - 1e-9)), count)
        spans.append((a, b))
    return spans


def point_on_walls(base: BaseMap, label: str, point: tuple[float, float], radius: float) -> str | None:
    """Why ``point`` cannot be the ``start`` or ``goal`` (``label``): the robot's disc of ``radius`` there
    overlaps or touches one of the base's blocked cells; or None when it can."""
    x, y = point
    cell = base.resolution
    c0, c1 = max(math.floor((x - radius) / cell), 0), min(math.floor((x + radius) / cell), base.cols - 1)
    r0, r1 = max(math.floor((y - radius) / cell), 0), min(math.floor((y + radius) / cell), base.rows - 1)
    rows, cols = np.nonzero(base_cells(base)[r0 : r1 + 1, c0 : c1 + 1])
    left, low = (cols + c0) * cell, (rows + r0) * cell
    dx = np.maximum(np.maximum(left - x, x - (left + cell)), 0.0)
    dy = np.maximum(np.maximum(low - y, y - (low + cell)), 0.0)
    if not np.any(dx * dx + dy * dy <= radius * radius):
        return None
    return f"{label} ({x:g}, {y:g}) is on the map's walls or closer to them than the robot radius {radius:g}"


def base_digest(base: BaseMap) -> str:
    """16 hex digits of the SHA-256 of the base's cells and their size: equal digests, equal walls."""
    text = f"{base.rows} {base.cols} {base.resolution!r} {base.blocked}"
    return hashlib.sha256(text.encode("ascii")).hexdigest()[:16]
