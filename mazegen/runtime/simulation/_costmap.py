"""move_base's maps of a floor, built once per floor: the costmap and its two planners' fields.

On a grid of the controller's own ``resolution`` (costmap_2d's cells; cell ``(r, c)`` has its centre
at ``((c + .5) cell, (r + .5) cell)``):

- ``clear``: the distance from each cell centre to the nearest obstacle cell's centre or the arena's
  edge (:func:`mazegen.runtime.simulation._fields.clearance`), 0 on obstacle cells. A cell's cost is
  costmap_2d's inflation of it (:func:`cell_cost`): 254 on an obstacle cell, 253 within the inscribed
  radius of the padded footprint, ``252 · exp(-(d - inscribed) / decay)`` (truncated) out to
  ``inflation``, 0 beyond.
- ``nav[0]``: navfn's potential, the cheapest way to the goal from each cell: Dijkstra's algorithm on
  the 8-connected cells, a cell costing navfn's ``50 + 0.8 · cost`` (:data:`NEUTRAL`, :data:`FACTOR`)
  and a step between two cells the mean of theirs times the step's length in cells; cells of cost 253
  or more are walls. navfn's own update interpolates between neighbours (a smoother potential); the
  plan descends this one.
- ``nav[1]``: base_local_planner's goal distance, cells from the goal by 4-connected steps through
  cells of cost below 253 (its ``MapGrid`` wavefront), ``inf`` where none reaches.
- ``nav[2]``: each cell's cost.

Floors are built in parallel, each thread with its own scratch.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.controllers import BUNDLED
from mazegen.errors import MazeError
from mazegen.runtime.compiling import inner_kernel, leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.geometry import cspace, grid_args, grid_of
from mazegen.runtime.navigation import kernel_args
from mazegen.runtime.simulation._fields import clearance, file_entry, raster_scratch, take_lowest
from mazegen.runtime.threads import in_blocks

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population
    from mazegen.runtime.geometry import Grid
    from mazegen.spec import Arena

LETHAL, INSCRIBED = 254.0, 253.0
"""costmap_2d's costs of an obstacle cell and of a cell within the inscribed radius."""
NEUTRAL, FACTOR = 50.0, 0.8
"""navfn's cost of a free cell, and what each unit of costmap cost adds to it."""
RING = 10
"""Buckets of the potential's queue: a step costs at most √2 · (NEUTRAL + FACTOR · 252) < 8 buckets
of one NEUTRAL-cost step."""

_ROW = BUNDLED["movebase"]
_LENGTH, _WIDTH, _PADDING = _ROW.index("length"), _ROW.index("width"), _ROW.index("padding")
_INFLATION, _DECAY, _RESOLUTION = _ROW.index("inflation"), _ROW.index("decay"), _ROW.index("resolution")


def inscribed_radius(params: np.ndarray) -> float:
    """The padded footprint's inscribed radius: half its width (arena units)."""
    return 0.5 * float(params[_WIDTH]) + float(params[_PADDING])


MOST_CELLS = 4096
"""Costmap cells on a side at most: 16 M cells, 200 MB of fields a floor."""


def costmap_grid(arena: Arena, params: np.ndarray) -> Grid:
    """The costmap's grid on ``arena``: cells of the controller's ``resolution``.

    Raises:
        MazeError: a resolution that makes more than :data:`MOST_CELLS` cells on a side.
    """
    resolution = float(params[_RESOLUTION])
    if max(arena.width, arena.height) / resolution > MOST_CELLS:
        raise MazeError(
            f"controller movebase's resolution {resolution:g} makes more than {MOST_CELLS} cells on a side "
            f"of arena '{arena.name}' ({arena.width:g} x {arena.height:g} {arena.unit})"
        )
    return grid_of(replace(arena, grid=resolution, robot_radius=inscribed_radius(params)))


def costmap_fields(
    population: Population, params: np.ndarray, indices: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(nav float32[M, 2, R, C], clear float32[M, R, C], grid float64[5])`` of the floors
    ``indices``, for movebase's parameters ``params`` (arena units); ``grid`` =
    ``(x0, y0, resolution, rows, cols)``."""
    arena = population.arena
    grid = costmap_grid(arena, params)
    indices = np.ascontiguousarray(indices, np.int64)
    m = indices.shape[0]
    nav = np.empty((m, 3, grid.rows, grid.cols), np.float32)
    clear = np.empty((m, grid.rows, grid.cols), np.float32)
    if m:
        shapes, ids, n_el, kernel_params, _ = kernel_args(population)
        extent = np.array([arena.width, arena.height])
        costs = np.array([inscribed_radius(params), params[_INFLATION], params[_DECAY]])
        # costmap_2d's worldToMap: the cell the goal lies in (MazeGen's grid puts a point on an edge below)
        goal = (
            min(int(arena.goal[1] / grid.cell), grid.rows - 1),
            min(int(arena.goal[0] / grid.cell), grid.cols - 1),
        )
        arrays = (shapes, ids, n_el, kernel_params, indices, grid_args(grid), extent, costs, goal)
        in_blocks(_costmaps_all, m, *arrays, nav, clear)
    return nav, clear, np.array([0.0, 0.0, grid.cell, grid.rows, grid.cols])


@njit(cache=True, nogil=True)
def _costmaps_all(
    first, last, shapes, ids, n_el, params, indices, grid, extent, costs, goal, nav, clear
):  # pragma: no cover - compiled
    """Fill ``nav[m]`` and ``clear[m]`` for floor ``indices[m]``, ``m`` from ``first`` to ``last - 1``."""
    raster, free, occupied, scratch = raster_scratch(grid, ids, shapes)
    heads = np.empty(RING, np.int64)
    goal_row, goal_col = goal
    for m in range(first, last):
        i = indices[m]
        cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
        clearance(occupied, grid[0], extent, clear[m], scratch)
        potential(clear[m], costs, goal_row, goal_col, nav[m, 0], scratch, heads)
        goal_distance(clear[m], costs, goal_row, goal_col, nav[m, 1], scratch[5])
        for r in range(clear.shape[1]):
            for c in range(clear.shape[2]):
                nav[m, 2, r, c] = cell_cost(clear[m, r, c], costs[0], costs[1], costs[2])


@njit(cache=True, inline="always")
def cell_cost(d, inscribed, inflation, decay):  # pragma: no cover - compiled
    """costmap_2d's cost of a cell whose centre is ``d`` from the nearest obstacle cell's centre."""
    if d <= 0.0:
        return LETHAL
    if d <= inscribed:
        return INSCRIBED
    if d > inflation:
        return 0.0
    return float(math.floor((INSCRIBED - 1.0) * math.exp(-(d - inscribed) / decay)))


@leaf_kernel
def navfn_cost(d, costs):  # pragma: no cover - compiled
    """navfn's cost of crossing a cell ``d`` from the nearest obstacle: ``inf`` for a wall."""
    cost = cell_cost(d, costs[0], costs[1], costs[2])
    return math.inf if cost >= INSCRIBED else NEUTRAL + FACTOR * cost


@inner_kernel
def potential(clear, costs, goal_row, goal_col, out, scratch, heads):  # pragma: no cover - compiled
    """``out[r, c]``: navfn's potential, the cheapest 8-connected way from cell ``(r, c)`` to the goal's
    cell (``inf`` where none reaches); the goal's cell is free whatever its cost, as navfn seeds it.

    Dijkstra's algorithm with a bucket queue of buckets one NEUTRAL-cost step wide, the cheapest step
    (Dinitz): no step from a key in the lowest bucket lands back in it, so that bucket is final.
    """
    rows, cols = out.shape
    best, keys, cells, links = scratch[0], scratch[4], scratch[5], scratch[6]
    best[:] = np.inf
    out[:] = np.inf
    heads[:] = -1
    if not (0 <= goal_row < rows and 0 <= goal_col < cols):
        return
    ring = heads.shape[0]
    width = 1.0 / NEUTRAL
    best[goal_row, goal_col] = 0.0
    used = file_entry(keys, cells, links, heads, 0, 0.0, goal_row * cols + goal_col, 0)
    pending, bucket = 1, 0
    diagonal = math.sqrt(2.0)
    while pending:
        bucket, key, r, c = take_lowest(keys, cells, links, heads, bucket, cols)
        pending -= 1
        if key > best[r, c] or out[r, c] < np.inf:
            continue
        out[r, c] = key
        own = NEUTRAL if (r == goal_row and c == goal_col) else navfn_cost(clear[r, c], costs)
        for dr in range(-1, 2):
            nr = r + dr
            if nr < 0 or nr >= rows:
                continue
            for dc in range(-1, 2):
                nc = c + dc
                if (dr == 0 and dc == 0) or nc < 0 or nc >= cols:
                    continue
                theirs = navfn_cost(clear[nr, nc], costs)
                if theirs == math.inf:
                    continue
                reached = key + 0.5 * (own + theirs) * (diagonal if dr != 0 and dc != 0 else 1.0)
                if reached < best[nr, nc]:
                    best[nr, nc] = reached
                    slot = max(int(reached * width), bucket + 1) % ring
                    used = file_entry(keys, cells, links, heads, used, reached, nr * cols + nc, slot)
                    pending += 1


@inner_kernel
def goal_distance(clear, costs, goal_row, goal_col, out, queue):  # pragma: no cover - compiled
    """``out[r, c]``: 4-connected steps from the goal's cell to cell ``(r, c)`` through cells of cost
    below 253 (``inf`` where none reaches), by breadth-first search."""
    rows, cols = out.shape
    out[:] = np.inf
    if not (0 <= goal_row < rows and 0 <= goal_col < cols):
        return
    out[goal_row, goal_col] = 0.0
    queue[0] = goal_row * cols + goal_col
    head, tail = 0, 1
    while head < tail:
        here = queue[head]
        head += 1
        r, c = here // cols, here - (here // cols) * cols
        step = out[r, c] + 1.0
        for k in range(4):
            nr = r + (1 if k == 0 else -1 if k == 1 else 0)
            nc = c + (1 if k == 2 else -1 if k == 3 else 0)
            if nr < 0 or nr >= rows or nc < 0 or nc >= cols or out[nr, nc] < np.inf:
                continue
            if cell_cost(clear[nr, nc], costs[0], costs[1], costs[2]) >= INSCRIBED:
                continue
            out[nr, nc] = step
            queue[tail] = nr * cols + nc
            tail += 1


@wrapped_leaf_kernel
def descend(potential, clear, costs, row, col, within, plan):  # pragma: no cover - compiled
    """navfn's plan from cell ``(row, col)``: each step to the neighbour that keeps the cheapest way to
    the goal (the robot's own cell free, as navfn clears it). The plan's cells within ``within``
    (Manhattan, cells) of the start go to ``plan``, as many as it holds; returns how many, or -1 when
    no way reaches the goal."""
    rows, cols = potential.shape
    r, c = row, col
    own = NEUTRAL  # the robot's cell, cleared
    level = math.inf
    kept = 0
    for _ in range(rows * cols):
        if abs(r - row) + abs(c - col) <= within and kept < plan.shape[0]:
            plan[kept, 0], plan[kept, 1] = r, c
            kept += 1
        if potential[r, c] == 0.0:
            return kept
        next_r, next_c, through = -1, -1, math.inf
        for dr in range(-1, 2):
            nr = r + dr
            if nr < 0 or nr >= rows:
                continue
            for dc in range(-1, 2):
                nc = c + dc
                if (dr == 0 and dc == 0) or nc < 0 or nc >= cols or potential[nr, nc] == math.inf:
                    continue
                step = math.sqrt(2.0) if dr != 0 and dc != 0 else 1.0
                # The goal's cell crosses at NEUTRAL whatever its cost, as the potential seeded it.
                theirs = NEUTRAL if potential[nr, nc] == 0.0 else navfn_cost(clear[nr, nc], costs)
                way = potential[nr, nc] + 0.5 * step * (own + theirs)
                if way < through:
                    next_r, next_c, through = nr, nc, way
        if next_r < 0 or potential[next_r, next_c] >= level:
            return -1  # cut off, or (float rounding) no longer descending
        level = potential[next_r, next_c]
        r, c = next_r, next_c
        own = navfn_cost(clear[r, c], costs)
    return -1
