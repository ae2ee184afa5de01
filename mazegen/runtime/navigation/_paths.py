"""Can the robot get from start to goal, and how far must it go: the path search.

On the configuration space of :mod:`mazegen.runtime.geometry._cspace`, per individual:

1. **Straight line**: when every cell the start-goal segment touches is free, that
   segment is the path and nothing else is searched.
2. **Rectangles**: the free cells are split into rectangles
   (:mod:`mazegen.runtime.geometry._rectangles`); two that share an edge are connected. The
   scenario is solvable when the rectangles holding the start and goal cells are
   connected.
3. **Path**: an A* search over rectangles (a rectangle is entered where the line
   from the previous entry point towards the goal crosses into it, or as near as
   the shared edge allows; the straight line to the goal guides the search; the
   queue is bucketed by whole cells), then the shortest path through the chosen
   corridor of rectangles by the funnel algorithm (string pulling through the
   portals between them). The path found is collision-free; being chosen over
   rectangles, its corridor is not always the shortest one.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel, leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.geometry import (
    ABOVE,
    BELOW,
    DOWN_COUNT,
    DOWN_FIRST,
    FIRST_COL,
    FIRST_ROW,
    LAST_COL,
    LAST_ROW,
    UP_COUNT,
    UP_FIRST,
    Grid,
    cspace,
    decompose,
    floor_cells,
    grid_args,
    raster_arrays,
    rectangle_arrays,
    runs_per_row,
    straight_free,
    unpack,
)
from mazegen.runtime.threads import in_blocks

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population


# Columns of the search's per-rectangle arrays.
COST, X, Y = 0, 1, 2
PREVIOUS, SETTLED = 0, 1  # columns of the int array (``marks``)


@dataclass(frozen=True)
class Navigation:
    """Solvability and path of every individual of a population.

    Attributes:
        solvable: ``bool[N]``: a path joins start and goal (False for invalid individuals).
        path_length: ``float64[N]``: its length in arena units, NaN when unsolvable.
        coverage: ``float64[N]``: fraction of the grid's cells the elements occupy.
        straight: Straight-line distance from start to goal.
        cell: The grid's cell size (path length in cells = ``path_length / cell``).
    """

    solvable: np.ndarray
    path_length: np.ndarray
    coverage: np.ndarray
    straight: float
    cell: float

    @classmethod
    def over_tasks(cls, tasks: Sequence[Navigation]) -> Navigation:
        """The navigation of floors of several tasks, one navigation each: solvable where every task is,
        the path length and straight distance the tasks' mean, the coverage the floor's."""
        first = tasks[0]
        return cls(
            np.logical_and.reduce([task.solvable for task in tasks]),
            np.mean(np.stack([task.path_length for task in tasks]), axis=0),
            first.coverage,
            float(np.mean([task.straight for task in tasks])),
            first.cell,
        )


def kernel_args(pop: Population) -> tuple:
    """The population's arrays as the compiled kernels take them."""
    return (
        pop.table.shapes,
        np.ascontiguousarray(pop.element_ids, np.int32),
        np.ascontiguousarray(pop.n_elements, np.int32),
        np.ascontiguousarray(pop.params, np.float64),
        np.ascontiguousarray(pop.valid, np.bool_),
    )


def navigate(pop: Population, grid: Grid) -> Navigation:
    """Solvability, path length and coverage of every individual of ``pop`` on ``grid``."""
    n = pop.size
    solvable = np.zeros(n, dtype=np.bool_)
    length = np.full(n, np.nan)
    coverage = np.zeros(n)
    if n:
        outputs = (solvable, length, coverage)
        in_blocks(_navigate_all, n, *kernel_args(pop), grid_args(grid), *outputs, per_thread=16)
    straight = math.dist(grid.start, grid.goal)
    return Navigation(solvable, length, coverage, straight, grid.cell)


def free_cells(pop: Population, grid: Grid, index: int) -> np.ndarray:
    """``bool[rows, cols]`` configuration-space free cells of one individual (to inspect or test a floor)."""
    table = pop.table
    free = np.zeros((grid.rows, grid.words), np.uint64)
    parts, vertices = table.unit.shape[1:3]
    raster = raster_arrays(grid_args(grid), pop.element_ids.shape[1], parts, vertices)
    cspace(
        table.shapes,
        np.ascontiguousarray(pop.element_ids[index], np.int32),
        int(pop.n_elements[index]),
        np.ascontiguousarray(pop.params[index], np.float64),
        grid_args(grid),
        raster,
        free,
    )
    return unpack(free, grid.cols)


def path_of(pop: Population, grid: Grid, index: int) -> np.ndarray | None:
    """``float64[n, 2]``: the corners of individual ``index``'s path, start to goal, or None if unsolvable."""
    return paths_of(pop, grid, np.array([index]))[0]


def paths_of(pop: Population, grid: Grid, rows: np.ndarray | None = None) -> list[np.ndarray | None]:
    """:func:`path_of` of each individual of ``rows`` (all by default), searched with one scratch."""
    rows = np.arange(pop.size) if rows is None else np.asarray(rows, dtype=np.int64)
    shapes, ids, n_el, params, valid = kernel_args(pop)
    corners, ends = _corner_paths(shapes, ids, n_el, params, valid, grid_args(grid), rows)
    return [
        corners[ends[k] : ends[k + 1]].copy() if ends[k + 1] > ends[k] else None for k in range(rows.size)
    ]


@njit(cache=True)
def _corner_paths(shapes, ids, n_el, params, valid, grid, rows):  # pragma: no cover - compiled
    """The corners of the paths of ``rows`` one after another, and where each ends (an empty
    stretch: no path)."""
    scratch = route_scratch(shapes, ids.shape[1], grid)
    ends = np.zeros(rows.shape[0] + 1, dtype=np.int64)
    corners = np.empty((2 * rows.shape[0] + 2, 2))  # room for straight paths; bent ones grow it
    for k in range(rows.shape[0]):
        i, turns = rows[k], 0
        if valid[i]:
            _, found, _, turns = route(shapes, ids[i], n_el[i], params[i], grid, scratch)
            turns = turns if found else 0
        if ends[k] + turns > corners.shape[0]:
            grown = np.empty((2 * (ends[k] + turns), 2))
            copy_points(corners, np.int64(0), grown, np.int64(0), ends[k])
            corners = grown
        copy_points(scratch[5], np.int64(0), corners, ends[k], turns)
        ends[k + 1] = ends[k] + turns
    return corners, ends


@wrapped_leaf_kernel
def copy_points(source, start, out, out_start, count):  # pragma: no cover - compiled
    """``out[out_start:][:count] = source[start:][:count]`` for rows of two coordinates, as a loop (a
    slice assignment compiles a shape check and its message)."""
    taken, put = source[start : start + count], out[out_start : out_start + count]
    for k in range(count):
        put[k, 0] = taken[k, 0]
        put[k, 1] = taken[k, 1]


@njit(cache=True, nogil=True)
def _navigate_all(
    first, last, shapes, ids, n_el, params, valid, grid, solvable, length, coverage
):  # pragma: no cover
    """Fill ``solvable``, ``length`` and ``coverage`` of individuals ``first`` to ``last - 1``."""
    cells = floor_cells(grid)
    scratch = route_scratch(shapes, ids.shape[1], grid)
    for i in range(first, last):
        if not valid[i]:
            continue
        occupied, found, total, _ = route(shapes, ids[i], n_el[i], params[i], grid, scratch)
        coverage[i] = occupied / cells
        solvable[i] = found
        if found:
            length[i] = total


@njit(cache=True)
def route_scratch(shapes, slots, grid):  # pragma: no cover - compiled
    """Scratch arrays of :func:`route` for one thread: raster, free rows, rectangles and search."""
    rows, cols, border = grid[1], grid[2], grid[4]
    capacity = rows * runs_per_row(cols)
    return (
        raster_arrays(grid, slots, shapes[2].shape[1], shapes[2].shape[2]),
        np.zeros((rows, border.shape[1]), np.uint64),  # free cells
        rectangle_arrays(rows, cols),
        _search_arrays(capacity, 4 * (rows + cols) + 16),
        np.zeros((capacity + 2, 4)),  # portals
        np.zeros((capacity + 2, 2)),  # path corners
    )


@wrapped_leaf_kernel
def route(shapes, ids, count, params, grid, scratch):  # pragma: no cover - compiled
    """Configuration space and path of one individual.

    Returns (occupied cells, found, path length, corners); the free rows are
    ``scratch[1]`` and the path's corners, start to goal, ``scratch[5][:corners]``.
    """
    raster, free, rectangles, search, portals, corners = scratch
    occupied = cspace(shapes, ids, count, params, grid, raster, free)
    points = grid[5]
    if straight_free(free, grid[2], grid[0], points):  # the shortest path of all: no search
        corners[0, 0], corners[0, 1] = points[0], points[1]
        corners[1, 0], corners[1, 1] = points[2], points[3]
        return occupied, True, math.hypot(points[2] - points[0], points[3] - points[1]), 2
    nodes, start, goal = decompose(free, grid[2], grid[6], rectangles)
    if start < 0 or goal < 0:
        return occupied, False, 0.0, 0
    found, total, turns = _shortest(rectangles, nodes, start, goal, grid, search, portals, corners)
    return occupied, found, total, turns


@inner_kernel
def _search_arrays(capacity, buckets):  # pragma: no cover - compiled
    """Scratch arrays of one search over at most ``capacity`` rectangles."""
    return (
        np.zeros((capacity, 3)),  # per rectangle: cost so far, entry point x and y
        np.zeros((capacity, 2), np.int64),  # per rectangle: previous rectangle, settled
        np.full(buckets, -1, np.int64),  # queue: first entry of each bucket (-1: empty)
        np.zeros((4 * capacity + 8, 2), np.int64),  # queue entries: next entry in the same bucket, rectangle
        np.zeros(capacity + 2, np.int64),  # corridor
    )


@leaf_kernel
def _shortest(rectangles, count, start, goal, grid, search, portals, corners):  # pragma: no cover - compiled
    """Search rectangle ``start`` → ``goal``; returns (found, path length, corners written to ``corners``).

    The search works in cell units (a rectangle's edges are then its row and column
    numbers), which keeps multiplications off its chain of dependent steps.
    """
    rects, edges = rectangles[0], rectangles[1]
    cell = grid[0]
    sx, sy, gx, gy = grid[5][0] / cell, grid[5][1] / cell, grid[5][2] / cell, grid[5][3] / cell
    state, marks, heads, entries, corridor = search
    for q in range(count):
        state[q, COST] = np.inf
        marks[q, SETTLED] = 0
    state[start, COST], state[start, X], state[start, Y] = 0.0, sx, sy
    marks[start, PREVIOUS] = -1
    # A bucket queue ordered by (cost so far + straight line still to go) in cells:
    # constant-time pushes and pops; within a bucket the order is last in, first out.
    last = heads.shape[0] - 1
    lowest = min(int(math.sqrt((gx - sx) * (gx - sx) + (gy - sy) * (gy - sy))), last)
    first_used = highest = lowest
    used = enqueue(heads, entries, 0, lowest, start)
    while True:
        lowest, here = dequeue(heads, entries, lowest, highest)
        if here < 0:
            break
        if marks[here, SETTLED]:
            continue
        marks[here, SETTLED] = 1
        if here == goal:
            break
        spent, ex, ey = state[here, COST], state[here, X], state[here, Y]
        for side in range(2):  # the rectangles above, then those below
            first = rects[here, UP_FIRST] if side == 0 else rects[here, DOWN_FIRST]
            n = rects[here, UP_COUNT] if side == 0 else rects[here, DOWN_COUNT]
            y = float(rects[here, LAST_ROW] + 1 if side == 0 else rects[here, FIRST_ROW])
            aim = aim_across(ex, ey, gx, gy, y)
            rise = (y - ey) * (y - ey)
            rise_to_goal = (gy - y) * (gy - y)
            lo_here = rects[here, FIRST_COL]
            hi_here = rects[here, LAST_COL] + 1
            for e in range(first, first + n):
                q = edges[e, ABOVE] if side == 0 else edges[e, BELOW]
                if marks[q, SETTLED]:
                    continue
                x = min(max(aim, max(lo_here, rects[q, FIRST_COL])), min(hi_here, rects[q, LAST_COL] + 1))
                # sqrt, not hypot: hypot's overflow care costs more than it saves here
                reached = spent + math.sqrt((x - ex) * (x - ex) + rise)
                if reached < state[q, COST]:
                    state[q, COST], state[q, X], state[q, Y] = reached, x, y
                    marks[q, PREVIOUS] = here
                    bucket = min(int(reached + math.sqrt((gx - x) * (gx - x) + rise_to_goal)), last)
                    used = enqueue(heads, entries, used, bucket, q)
                    lowest = min(lowest, bucket)
                    first_used = min(first_used, bucket)
                    highest = max(highest, bucket)
    heads[first_used : highest + 1] = -1  # the queue empty again for the next search
    if not marks[goal, SETTLED]:
        return False, 0.0, 0
    hops = 0
    q = goal
    while q >= 0:
        corridor[hops] = q
        hops += 1
        q = marks[q, PREVIOUS]
    total, turns = funnel(rects, corridor, hops, sx, sy, gx, gy, portals, corners)
    for t in range(turns):
        corners[t, 0] *= cell
        corners[t, 1] *= cell
    return True, total * cell, turns


@njit(cache=True, inline="always")
def enqueue(heads, entries, used, bucket, node):  # pragma: no cover - compiled
    """Push ``node`` into ``bucket`` of a bucket queue (``heads``: each bucket's last entry, -1 empty;
    ``entries``: the next entry in its bucket and the node); returns the entries used."""
    entries[used, 0] = heads[bucket]
    entries[used, 1] = node
    heads[bucket] = used
    return used + 1


@njit(cache=True, inline="always")
def dequeue(heads, entries, lowest, highest):  # pragma: no cover - compiled
    """Pop the last entry of the lowest non-empty bucket from ``lowest`` to ``highest``: (that bucket,
    its node), the node -1 when the queue is empty."""
    while lowest <= highest and heads[lowest] < 0:
        lowest += 1
    if lowest > highest:
        return lowest, -1
    taken = heads[lowest]
    heads[lowest] = entries[taken, 0]
    return lowest, entries[taken, 1]


@njit(cache=True, inline="always")
def aim_across(ex, ey, gx, gy, y):  # pragma: no cover - compiled
    """Where to cross the edge at row line ``y`` from the entry point ``(ex, ey)``: where the line
    towards the goal ``(gx, gy)`` crosses it, straight on when the goal is not ahead (the caller
    clamps it to the edge)."""
    if (gy - ey) * (y - ey) > 0.0 and abs(gy - ey) >= abs(y - ey):
        return ex + (gx - ex) * (y - ey) / (gy - ey)
    return ex


@wrapped_leaf_kernel
def funnel(rects, corridor, hops, sx, sy, gx, gy, portals, corners):  # pragma: no cover - compiled
    """The shortest path from start to goal through the corridor's portals, in cell units: (length, corners).

    ``corridor[hops - 1] .. corridor[0]`` are the rectangles from start to goal. Each
    portal is the edge two consecutive rectangles share, written (left, right) as seen
    when walking through it; the funnel algorithm pulls the path taut. The path's
    vertices, start and goal included, go to ``corners``.
    """
    _portal(portals, 0, sx, sy, sx, sy)
    n = 1
    for h in range(hops - 1, 0, -1):
        a, b = corridor[h], corridor[h - 1]
        lo = float(max(rects[a, FIRST_COL], rects[b, FIRST_COL]))
        hi = float(min(rects[a, LAST_COL], rects[b, LAST_COL]) + 1)
        up = rects[b, FIRST_ROW] > rects[a, LAST_ROW]
        y = float(rects[b, FIRST_ROW] if up else rects[a, FIRST_ROW])
        if up:  # walking up (+y): left is smaller x
            _portal(portals, n, lo, y, hi, y)
        else:
            _portal(portals, n, hi, y, lo, y)
        n += 1
    _portal(portals, n, gx, gy, gx, gy)
    n += 1
    total = 0.0
    ax, ay = sx, sy
    corners[0, 0], corners[0, 1] = ax, ay
    turns = 1
    lx, ly, rx, ry = portals[0, 0], portals[0, 1], portals[0, 2], portals[0, 3]
    left_at = 0
    right_at = 0
    i = 1
    while i < n:
        plx, ply, prx, pry = portals[i, 0], portals[i, 1], portals[i, 2], portals[i, 3]
        corner = -1  # set when one side crosses the other: that side's far corner is on the path
        # Tighten the right side.
        if _cross(ax, ay, rx, ry, prx, pry) >= 0.0:
            if (ax == rx and ay == ry) or _cross(ax, ay, lx, ly, prx, pry) < 0.0:
                rx, ry, right_at = prx, pry, i
            else:
                corner, cx, cy = left_at, lx, ly
        # Tighten the left side.
        if corner < 0 and _cross(ax, ay, lx, ly, plx, ply) <= 0.0:
            if (ax == lx and ay == ly) or _cross(ax, ay, rx, ry, plx, ply) > 0.0:
                lx, ly, left_at = plx, ply, i
            else:
                corner, cx, cy = right_at, rx, ry
        if corner >= 0:  # walk to the corner and restart the funnel there
            total += math.sqrt((cx - ax) * (cx - ax) + (cy - ay) * (cy - ay))
            ax, ay = cx, cy
            corners[turns, 0], corners[turns, 1] = ax, ay
            turns += 1
            lx, ly, rx, ry = ax, ay, ax, ay
            left_at = right_at = i = corner
        i += 1
    corners[turns, 0], corners[turns, 1] = gx, gy
    return total + math.sqrt((gx - ax) * (gx - ax) + (gy - ay) * (gy - ay)), turns + 1


@njit(cache=True, inline="always")
def _portal(portals, n, lx, ly, rx, ry):  # pragma: no cover - compiled
    portals[n, 0], portals[n, 1], portals[n, 2], portals[n, 3] = lx, ly, rx, ry


@njit(cache=True, inline="always")
def _cross(ax, ay, bx, by, cx, cy):  # pragma: no cover - compiled
    """Twice the signed area of triangle a, b, c: positive when c lies left of a → b."""
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
