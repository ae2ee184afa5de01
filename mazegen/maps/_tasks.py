"""Tasks drawn at random on a floor's free space, as nav2's planner benchmark draws its start and goal
pairs: each start and goal at the centre of a cell where the robot stands touching nothing, the goal
reachable from the start for the robot, and at least a given distance from it."""

from __future__ import annotations

from collections import deque

import numpy as np

from mazegen.maps._cells import near_cells

Point = tuple[float, float]

TRIES = 1000
"""Starts drawn for one task before a minimum distance no goal can keep is given up."""


def standing_cells(
    walls: np.ndarray, cell: float, width: float, height: float, radius: float
) -> tuple[np.ndarray, np.ndarray]:
    """Where the centre of a robot of ``radius`` may be on a grid of ``cell`` with ``walls``
    (``bool[rows, cols]``, row 0 the lowest), and where it stands touching nothing.

    Returns:
        ``(free, standing)``, both ``bool[rows, cols]``: ``free`` has no wall cell's centre within the
        radius of the cell's centre and the edge of the ``width x height`` floor no nearer (the engine's
        rule); ``standing`` is ``free`` with the disc off every wall cell's square, touching none.
    """
    rows, cols = walls.shape
    blocked = near_cells(walls, radius / cell)
    centres_x = (np.arange(cols) + 0.5) * cell
    centres_y = (np.arange(rows) + 0.5) * cell
    blocked |= ((centres_y < radius) | (centres_y > height - radius))[:, None]
    blocked |= ((centres_x < radius) | (centres_x > width - radius))[None, :]
    free = ~blocked
    return free, free & ~near_cells(walls, radius / cell, squares=True)


def components(free: np.ndarray) -> np.ndarray:
    """``int[rows, cols]``: the 4-connected component of each free cell, -1 for a blocked one."""
    rows, cols = free.shape
    labels = np.full(free.shape, -1, dtype=np.int64)
    flat_free, flat = free.ravel(), labels.ravel()
    label = 0
    for seed in np.flatnonzero(flat_free).tolist():
        if flat[seed] >= 0:
            continue
        flat[seed] = label
        queue = deque([seed])
        while queue:
            index = queue.popleft()
            row, col = divmod(index, cols)
            for neighbour, inside in (
                (index - cols, row > 0),
                (index + cols, row + 1 < rows),
                (index - 1, col > 0),
                (index + 1, col + 1 < cols),
            ):
                if inside and flat_free[neighbour] and flat[neighbour] < 0:
                    flat[neighbour] = label
                    queue.append(neighbour)
        label += 1
    return labels


def draw_tasks(
    free: np.ndarray, standing: np.ndarray, cell: float, count: int, seed: int, min_distance: float = 0.0
) -> list[tuple[Point, Point]]:
    """``count`` starts and goals at the centres of ``standing`` cells, each goal joined to its start by
    ``free`` cells and at least ``min_distance`` from it (a different cell when 0), drawn with
    ``numpy.random.default_rng(seed)``.

    Raises:
        ValueError: saying why, when no two cells are joined, or no start finds a goal far enough
            away in :data:`TRIES` draws.
    """
    labels = components(free).ravel()
    cells = np.flatnonzero((labels >= 0) & standing.ravel())
    sizes = np.bincount(labels[cells]) if cells.size else np.zeros(0, dtype=np.int64)
    candidates = cells[sizes[labels[cells]] >= 2]
    if candidates.size == 0:
        raise ValueError("no two cells where the robot stands are joined for it")
    rng = np.random.default_rng(seed)
    cols = free.shape[1]
    x, y = (cells % cols + 0.5) * cell, (cells // cols + 0.5) * cell
    tasks = []
    for _ in range(count):
        for _ in range(TRIES):
            start = int(rng.choice(candidates))
            sx, sy = (start % cols + 0.5) * cell, (start // cols + 0.5) * cell
            goals = (labels[cells] == labels[start]) & (cells != start)
            if min_distance > 0:
                goals &= np.hypot(x - sx, y - sy) >= min_distance
            if goals.any():
                break
        else:
            raise ValueError(f"no start found a goal joined to it and {min_distance:g} or more away")
        goal = int(rng.choice(cells[goals]))
        tasks.append((_centre(start, cols, cell), _centre(goal, cols, cell)))
    return tasks


def _centre(index: int, cols: int, cell: float) -> Point:
    row, col = divmod(index, cols)
    return round((col + 0.5) * cell, 9), round((row + 0.5) * cell, 9)
