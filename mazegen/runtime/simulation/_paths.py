"""MazeGen's own paths of the driven floors: their lengths (BARN's optimal time) and corners.

The search is :func:`mazegen.runtime.navigation.paths.route`, the one the solvability and
difficulty metrics run, so a floor's optimal time is the path length the metrics report. It runs
in parallel over the driven floors, each block of floors with its own scratch: once for the
lengths and corner counts, and, for controllers that follow the path, again to copy the corners.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from numba import njit, prange

from mazegen.runtime.engine.population import Population
from mazegen.runtime.geometry.cspace import grid_args, grid_of
from mazegen.runtime.navigation.paths import kernel_args, route, route_scratch


@dataclass(frozen=True)
class FloorPaths:
    """The paths of M driven floors.

    Attributes:
        length: ``float64[M]`` path length in arena units, NaN where MazeGen finds no path.
        corners: ``float64[M, C, 2]`` the path's corners, start to goal, padded; ``C`` is 1 when
            the corners were not asked for.
        count: ``int64[M]`` corners of each path (0 without a path).
    """

    length: np.ndarray
    corners: np.ndarray
    count: np.ndarray


def floor_paths(population: Population, indices: np.ndarray, *, corners: bool) -> FloorPaths:
    """Paths of individuals ``indices`` of ``population`` (and their corners when ``corners``)."""
    shapes, ids, n_el, params, valid = kernel_args(population)
    rows = np.ascontiguousarray(indices, np.int64)
    args = grid_args(grid_of(population.arena))
    m = len(rows)
    length = np.full(m, np.nan)
    count = np.zeros(m, np.int64)
    blocks = min(m, 8 * numba.get_num_threads())
    if m:
        _paths(shapes, ids, n_el, params, valid, rows, args, blocks, length, count, np.zeros((0, 1, 2)))
    points = np.zeros((m, max(1, int(count.max(initial=0))) if corners else 1, 2))
    if corners and m:
        _paths(shapes, ids, n_el, params, valid, rows, args, blocks, length, count, points)
    return FloorPaths(length, points, count)


@njit(cache=True, parallel=True)
def _paths(shapes, ids, n_el, params, valid, rows, grid, blocks, length, count, points):  # pragma: no cover
    """Lengths and corner counts of the paths of ``rows``; their corners too when ``points`` has rows."""
    m = rows.shape[0]
    for block in prange(blocks):
        scratch = route_scratch(shapes, ids.shape[1], grid)
        for j in range(block * m // blocks, (block + 1) * m // blocks):
            i = rows[j]
            if not valid[i]:
                continue
            _, found, total, turns = route(shapes, ids[i], n_el[i], params[i], grid, scratch)
            if not found:
                continue
            length[j] = total
            count[j] = turns
            if points.shape[0]:
                points[j, :turns] = scratch[5][:turns]
