"""MovingAI grid benchmarks: an octile ``.map`` and a ``.scen`` with its start-goal problems, one per
task.

A map cell stands for the robot's centre, so the map is the engine's configuration
space (cells an obstacle grown by the robot radius or the arena's edge blocks are
``@``, the others ``.``) on a grid of the chosen cell size. The ``.scen`` holds the
start and goal cells and the optimal octile length between them (straight moves
cost 1, diagonal ones the square root of 2, no diagonal past a blocked cell),
found by an A* search on the written map. A task with no path there gets no problem line.
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel
from mazegen.runtime.documents import Floor
from mazegen.runtime.exporters._floor import ExportOptions, floor_tasks

SQRT2 = math.sqrt(2.0)


@leaf_kernel
def _octile(dr, dc):  # pragma: no cover - compiled
    """Octile distance over ``dr`` rows and ``dc`` columns."""
    low, high = min(abs(dr), abs(dc)), max(abs(dr), abs(dc))
    return high - low + SQRT2 * low


@njit(cache=True)
def octile_length(free, start, goal):  # pragma: no cover - compiled
    """Length of the shortest 8-connected path from ``start`` to ``goal`` over ``free`` cells.

    Args:
        free: ``bool[rows, cols]``.
        start: ``(row, col)``.
        goal: ``(row, col)``.

    Returns:
        The octile length, ``inf`` when no path joins them; a diagonal move needs
        both cells it passes between free (no corner cutting).
    """
    rows, cols = free.shape
    (sr, sc), (gr, gc) = start, goal
    if not (free[sr, sc] and free[gr, gc]):
        return np.inf
    best = np.full((rows, cols), np.inf)
    done = np.zeros((rows, cols), np.bool_)
    best[sr, sc] = 0.0
    queue = [(_octile(gr - sr, gc - sc), 0.0, sr * cols + sc)]
    while queue:
        _, length, node = heapq.heappop(queue)
        r, c = node // cols, node % cols
        if done[r, c]:
            continue
        if r == gr and c == gc:
            return length
        done[r, c] = True
        for dr in range(-1, 2):
            for dc in range(-1, 2):
                nr, nc = r + dr, c + dc
                if (dr == 0 and dc == 0) or not (0 <= nr < rows and 0 <= nc < cols) or not free[nr, nc]:
                    continue
                if dr != 0 and dc != 0 and not (free[r, nc] and free[nr, c]):
                    continue
                step = length + (SQRT2 if dr != 0 and dc != 0 else 1.0)
                if step < best[nr, nc]:
                    best[nr, nc] = step
                    heapq.heappush(queue, (step + _octile(gr - nr, gc - nc), step, nr * cols + nc))
    return np.inf


def map_bytes(free: np.ndarray) -> bytes:
    """The ``.map`` file of a grid whose row 0 is at y = 0 (the file's last line)."""
    rows, cols = free.shape
    cells = np.where(free[::-1], ord("."), ord("@")).astype(np.uint8)
    lines = np.hstack([cells, np.full((rows, 1), ord("\n"), np.uint8)])
    return f"type octile\nheight {rows}\nwidth {cols}\nmap\n".encode("ascii") + lines.tobytes()


def movingai_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.map`` and ``NAME.scen`` of a scenario, on a grid of ``options.cell`` (default the engine's).

    Raises:
        MazeError: When the scenario's spec is unknown, or for a bad cell size.
    """
    free, grid = floor.configuration_space(options.cell)
    name = f"{floor.name}.map"
    scen = ["version 1"]
    flipped = free[::-1].copy()
    ends = [(task["start"], task["goal"]) for task in floor_tasks(floor)] or [(grid.start, grid.goal)]
    for start, goal in ends:
        task = grid.for_task((float(start[0]), float(start[1])), (float(goal[0]), float(goal[1])))
        # MovingAI counts rows from the top.
        (sr, sc), (gr, gc) = ((grid.rows - 1 - r, c) for r, c in (task.start_cell, task.goal_cell))
        length = octile_length(flipped, (sr, sc), (gr, gc))
        if math.isfinite(length):
            bucket = int(length // 4)
            scen.append(f"{bucket}\t{name}\t{grid.cols}\t{grid.rows}\t{sc}\t{sr}\t{gc}\t{gr}\t{length:.8f}")
    return {
        name: map_bytes(free),
        f"{floor.name}.scen": ("\n".join(scen) + "\n").encode("utf-8"),
    }
