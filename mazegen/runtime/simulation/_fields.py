"""The fields the map-reading controllers look up: a navigation function and a clearance field per floor.

Both live on the configuration-space grid of :func:`mazegen.runtime.geometry._cspace.grid_of`
(cell ``(r, c)`` has its centre at ``((c + .5) cell, (r + .5) cell)``):

- ``clear``: the Euclidean distance from each cell centre to the nearest occupied cell's centre
  (the exact distance transform of the occupancy raster, Felzenszwalb and Huttenlocher 2012),
  or to the arena's edge (exact) when that is nearer; 0 on occupied cells. The raster marks
  every cell a part touches, so the true distance from a cell centre to the nearest obstacle
  differs from ``clear`` by at most half a cell's diagonal (:data:`CLEAR_ERROR` cells).
- ``nav``: the free-space distance to the goal from each cell centre over the free cells of the
  configuration space (robot radius inflated), by Dijkstra's algorithm (a bucket queue) on the
  8-connected cells (a diagonal step needs both cells beside it free, as the path search does); ``inf``
  where blocked or cut off from the goal. It is at most ``1 - π/8 ≈ 8 %`` longer than the
  shortest free-space path between the same cells.

Floors are built in parallel, each thread with its own scratch; nothing is allocated per floor.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.runtime.compiling import wrapped_leaf_kernel
from mazegen.runtime.geometry import cspace, grid_args, grid_of, is_set, raster_arrays
from mazegen.runtime.navigation import kernel_args
from mazegen.runtime.simulation._world import stacked
from mazegen.runtime.threads import in_blocks

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population
    from mazegen.spec import Robot

CLEAR_ERROR = math.sqrt(0.5)
"""Largest difference, in cells, between ``clear`` and the true distance from a cell centre to
the nearest obstacle or wall."""

_FAR = np.float32(np.inf)


def floor_fields(
    population: Population, robot: Robot | None = None, indices: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(nav float32[M, R, C], clear float32[M, R, C], grid float64[5])`` of the floors ``indices``
    (default: every valid individual; an invalid one has no elements), ``grid`` =
    ``(x0, y0, cell, rows, cols)``.

    The fields depend on the floor and the arena's robot radius only; ``robot`` is taken so
    that every caller passes what it drives with, and is not read.
    """
    del robot
    arena = population.arena
    grid = grid_of(arena)
    if indices is None:
        indices = np.flatnonzero(population.valid)
    indices = np.ascontiguousarray(indices, np.int64)
    m = indices.shape[0]
    nav = np.empty((m, grid.rows, grid.cols), np.float32)
    clear = np.empty((m, grid.rows, grid.cols), np.float32)
    if m:
        shapes, ids, n_el, params, _ = kernel_args(population)
        extent = np.array([arena.width, arena.height])
        in_blocks(_fields_all, m, shapes, ids, n_el, params, indices, grid_args(grid), extent, nav, clear)
    return nav, clear, np.array([0.0, 0.0, grid.cell, grid.rows, grid.cols])


def joined_fields(
    fields: list[tuple[np.ndarray, np.ndarray, np.ndarray]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The fields of several :func:`floor_fields` calls as one: ``(nav, clear, grid float64[M, 5])``,
    every floor's arrays padded to the largest grid with what the controllers read off a grid (``inf``
    and 0), so that a floor's lookups give what its own fields give."""
    if len(fields) == 1:
        nav, clear, grid = fields[0]
        return nav, clear, np.tile(grid, (nav.shape[0], 1))
    return (
        stacked([nav for nav, _, _ in fields], np.inf),
        stacked([clear for _, clear, _ in fields], 0.0),
        np.concatenate([np.tile(grid, (nav.shape[0], 1)) for nav, _, grid in fields]),
    )


@njit(cache=True, nogil=True)
def _fields_all(
    first, last, shapes, ids, n_el, params, indices, grid, extent, nav, clear
):  # pragma: no cover
    """Fill ``nav[m]`` and ``clear[m]`` for floor ``indices[m]``, ``m`` from ``first`` to ``last - 1``."""
    raster, free, occupied, scratch = raster_scratch(grid, ids, shapes)
    for m in range(first, last):
        i = indices[m]
        cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
        clearance(occupied, grid[0], extent, clear[m], scratch)
        navigation(free, grid[0], grid[5], grid[6], nav[m], scratch)


@njit(cache=True)
def raster_scratch(grid, ids, shapes):  # pragma: no cover - compiled
    """``(raster, free, occupied, scratch)`` of one thread building floors' fields on ``grid``: the
    configuration-space raster and free rows :func:`cspace` fills, the rows of occupied cells (a view
    of the raster), and :func:`field_scratch`."""
    rows, cols = grid[1], grid[2]
    reach = grid[3].shape[0] - 1
    raster = raster_arrays(grid, ids.shape[1], shapes[2].shape[1], shapes[2].shape[2])
    free = np.zeros((rows, grid[4].shape[1]), np.uint64)
    stride = raster[1].shape[0] // rows
    occupied = raster[0][0, reach * stride : (reach + rows) * stride].reshape((rows, stride))
    return raster, free, occupied, field_scratch(rows, cols)


@njit(cache=True)
def field_scratch(rows, cols):  # pragma: no cover - compiled
    """Scratch of :func:`clearance` and :func:`navigation` for one thread."""
    longest = max(rows, cols)
    return (
        np.empty((rows, cols)),  # squared distances in cells² after the column pass; Dijkstra's keys
        np.empty(longest),  # one row's transform
        np.empty(longest, np.int64),  # the lower envelope's parabolas
        np.empty(longest + 1),  # and where each starts
        np.empty(8 * rows * cols + 1),  # queue entries: keys,
        np.empty(8 * rows * cols + 1, np.int64),  # cells,
        np.empty(8 * rows * cols + 1, np.int64),  # and the next entry of the same bucket
        np.empty(4, np.int64),  # the first entry of each bucket of the ring
    )


@wrapped_leaf_kernel
def clearance(occupied, cell, extent, out, scratch):  # pragma: no cover - compiled
    """``out[r, c]``: distance from cell ``(r, c)``'s centre to the nearest occupied cell's centre
    or to the arena's edge, whichever is nearer (arena units)."""
    rows, cols = out.shape
    squared, done, hull, bounds = scratch[0], scratch[1], scratch[2], scratch[3]
    # Along columns: rows to the nearest occupied cell, a sweep down then up, squared.
    far = float(rows + cols + 1)
    for r in range(rows):
        for c in range(cols):
            squared[r, c] = 0.0 if is_set(occupied[r], c) else (squared[r - 1, c] + 1.0 if r else far)
    for r in range(rows - 2, -1, -1):
        for c in range(cols):
            squared[r, c] = min(squared[r, c], squared[r + 1, c] + 1.0)
    for r in range(rows):
        for c in range(cols):
            squared[r, c] *= squared[r, c]
    # Along rows: the lower envelope of the columns' parabolas.
    width, height = extent[0], extent[1]
    for r in range(rows):
        _lower_envelope(squared[r], cols, hull, bounds, done)
        y = (r + 0.5) * cell
        to_rows = min(y, height - y)
        for c in range(cols):
            x = (c + 0.5) * cell
            edge = max(min(to_rows, x, width - x), 0.0)
            out[r, c] = min(math.sqrt(done[c]) * cell, edge)


@njit(cache=True, inline="always")
def _lower_envelope(f, n, hull, bounds, out):  # pragma: no cover - compiled
    """``out[:n]``: the 1D squared distance transform ``min_q (p - q)² + f[q]`` of ``f[:n]``
    (Felzenszwalb and Huttenlocher's lower envelope of parabolas)."""
    k = 0
    hull[0] = 0
    bounds[0] = -np.inf
    bounds[1] = np.inf
    for q in range(1, n):
        s = 0.0
        while True:
            p = hull[k]
            s = ((f[q] + q * q) - (f[p] + p * p)) / (2.0 * (q - p))
            if s > bounds[k] or k == 0:
                break
            k -= 1
        if s <= bounds[k]:  # k == 0 and the new parabola is lower everywhere
            hull[0] = q
            continue
        k += 1
        hull[k] = q
        bounds[k] = s
        bounds[k + 1] = np.inf
    k = 0
    for p in range(n):
        while bounds[k + 1] < p:
            k += 1
        d = p - hull[k]
        out[p] = d * d + f[hull[k]]


@wrapped_leaf_kernel
def navigation(free, cell, points, ends, out, scratch):  # pragma: no cover - compiled
    """``out[r, c]``: distance to the goal from cell ``(r, c)``'s centre through free cells,
    8-connected, ``inf`` where the goal cannot be reached.

    Dijkstra's algorithm with a bucket queue of buckets one cell wide, the shortest step (Dinitz):
    no step from a key in the lowest bucket can land back in it, so every entry of that bucket is
    final, whatever their order. A step adds at most √2 cells, so three buckets in a ring hold
    every pending key.
    """
    rows, cols = out.shape
    best, keys, cells, links, heads = scratch[0], scratch[4], scratch[5], scratch[6], scratch[7]
    best[:] = np.inf
    out[:] = _FAR
    heads[:] = -1
    gr, gc = ends[2], ends[3]
    if not (0 <= gr < rows and 0 <= gc < cols and is_set(free[gr], gc)):
        return
    gx, gy = points[2], points[3]
    seed = math.hypot((gc + 0.5) * cell - gx, (gr + 0.5) * cell - gy)
    best[gr, gc] = seed
    per_cell = 1.0 / cell
    ring = heads.shape[0]
    bucket = int(seed * per_cell)
    used = file_entry(keys, cells, links, heads, 0, seed, gr * cols + gc, bucket % ring)
    pending = 1
    diagonal = math.sqrt(2.0) * cell
    while pending:
        bucket, key, r, c = take_lowest(keys, cells, links, heads, bucket, cols)
        pending -= 1
        if key > best[r, c] or out[r, c] < _FAR:  # a stale entry, or settled already
            continue
        out[r, c] = key
        for dr in range(-1, 2):
            nr = r + dr
            if nr < 0 or nr >= rows:
                continue
            for dc in range(-1, 2):
                nc = c + dc
                if (dr == 0 and dc == 0) or nc < 0 or nc >= cols or not is_set(free[nr], nc):
                    continue
                if dr != 0 and dc != 0:
                    if not (is_set(free[r], nc) and is_set(free[nr], c)):
                        continue
                    reached = key + diagonal
                else:
                    reached = key + cell
                if reached < best[nr, nc]:
                    best[nr, nc] = reached
                    # (never below the bucket being emptied, whatever the rounding)
                    slot = max(int(reached * per_cell), bucket + 1) % ring
                    used = file_entry(keys, cells, links, heads, used, reached, nr * cols + nc, slot)
                    pending += 1


@njit(cache=True, inline="always")
def take_lowest(keys, cells, links, heads, bucket, cols):  # pragma: no cover - compiled
    """``(bucket, key, row, col)``: the first entry of the lowest bucket from ``bucket`` on that holds
    any, taken off it (cells numbered ``row · cols + col``)."""
    ring = heads.shape[0]
    while heads[bucket % ring] < 0:
        bucket += 1
    entry = heads[bucket % ring]
    heads[bucket % ring] = links[entry]
    here = cells[entry]
    return bucket, keys[entry], here // cols, here - (here // cols) * cols


@njit(cache=True, inline="always")
def file_entry(keys, cells, links, heads, used, key, value, slot):  # pragma: no cover - compiled
    """Put ``(key, value)`` first in bucket ``slot``, in entry ``used``; returns the next free entry."""
    keys[used], cells[used], links[used] = key, value, heads[slot]
    heads[slot] = used
    return used + 1
