"""Cells of an occupancy grid as shapes: obstacle cells merged into few rectangles, and the cells within
a disc's reach of an obstacle (the engine's dilation, done on a plain boolean grid).

Grids are ``bool[rows, cols]``, row 0 the lowest.
"""

from __future__ import annotations

import numpy as np

Cells = tuple[int, int, int, int]
"""A rectangle of cells: first row, last row, first column, last column (row 0 the lowest)."""


def wall_rectangles(occupied: np.ndarray) -> list[Cells]:
    """Disjoint rectangles that together are exactly the ``True`` cells, few of them.

    Row by row from the bottom, each run of cells not yet covered grows upwards while the row above
    holds the same columns uncovered: a wall of equal rows is one rectangle.
    """
    left = occupied.copy()
    rectangles = []
    for row in range(left.shape[0]):
        line = np.concatenate(([False], left[row], [False]))
        edges = np.flatnonzero(line[1:] != line[:-1])
        for first, end in zip(edges[::2].tolist(), edges[1::2].tolist()):
            top = row
            while top + 1 < left.shape[0] and left[top + 1, first:end].all():
                top += 1
            left[row : top + 1, first:end] = False
            rectangles.append((row, top, first, end - 1))
    return rectangles


def near_cells(occupied: np.ndarray, radius_cells: float, *, squares: bool = False) -> np.ndarray:
    """Cells with an obstacle cell's centre within ``radius_cells`` of theirs, the engine's disc
    (``Grid.from_arena``): ``dy`` rows away, ``floor(sqrt(r^2 - dy^2))`` columns either side. With
    ``squares``, an obstacle cell's square instead of its centre, touching included: where a disc of
    that radius on the cell's centre touches an obstacle, as the simulator's exact geometry finds."""
    rows, cols = occupied.shape
    counts = np.pad(np.cumsum(occupied, axis=1), ((0, 0), (1, 0)))
    near = np.zeros_like(occupied)
    half = 0.5 if squares else 0.0
    for dy in range(min(int(radius_cells + half + 1e-9), rows - 1) + 1):
        gap = max(dy - half, 0.0)
        span = int(np.floor(half + np.sqrt(max(radius_cells**2 - gap * gap, 0.0)) + 1e-9))
        low, high = np.maximum(np.arange(cols) - span, 0), np.minimum(np.arange(cols) + span + 1, cols)
        across = counts[:, high] > counts[:, low]  # an obstacle within span columns, in the same row
        near[dy:] |= across[: rows - dy]
        near[: rows - dy] |= across[dy:]
    return near
