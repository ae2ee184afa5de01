"""How many homotopy classes each floor of a population has, in one compiled call: what a suite's
archive measure and the ``classes`` fitness term read (:mod:`._classes` names the classes of one floor).

A floor's count is that of :func:`~mazegen.runtime.navigation._classes.topology`: the classes no longer
than ``detour`` times the shortest, at most ``max_classes``; 0 for an invalid floor or one without a
path. The floors are split over the threads in use, each with a scratch of its own.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.runtime.geometry import cspace, grid_args, raster_arrays
from mazegen.runtime.navigation._homotopy import (
    GOAL_STATES_PER_CLASS,
    LENGTH_TOLERANCE,
    class_scratch,
    floor_classes,
)
from mazegen.runtime.navigation._paths import kernel_args
from mazegen.runtime.threads import in_blocks
from mazegen.spec import DETOUR, MAX_CLASSES

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population
    from mazegen.runtime.geometry import Grid


def class_counts(
    pop: Population, grid: Grid, *, max_classes: int = MAX_CLASSES, detour: float = DETOUR
) -> np.ndarray:
    """``int64[N]``: the number of homotopy classes of each floor of ``pop`` on ``grid``'s task."""
    counts = np.zeros(pop.size, np.int64)
    if pop.size:
        in_blocks(
            _count_all, pop.size, *kernel_args(pop), grid_args(grid), np.int64(max_classes), float(detour),
            counts, per_thread=8,
        )  # fmt: skip
    return counts


@njit(cache=True, nogil=True)
def _count_all(
    first, last, shapes, ids, n_el, params, valid, grid, max_classes, detour, counts
):  # pragma: no cover
    rows, cols = grid[1], grid[2]
    raster = raster_arrays(grid, ids.shape[1], shapes[2].shape[1], shapes[2].shape[2])
    free = np.zeros((rows, grid[4].shape[1]), np.uint64)
    scratch = class_scratch(rows, cols, max_classes)
    walks = GOAL_STATES_PER_CLASS * max_classes
    lengths = np.empty(walks)
    keys = np.empty(walks, np.uint64)
    paths = np.empty((0, 0, 2))  # none: the number of classes alone
    turns = np.empty(walks, np.int64)
    points = grid[5] / grid[0]
    for i in range(first, last):
        counts[i] = 0
        if not valid[i]:
            continue
        cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
        found, _ = floor_classes(
            free, cols, grid[6], points, max_classes, detour, scratch, lengths, keys, paths, turns
        )
        if found == 0:
            continue
        shortest = lengths[:found].min()
        if not shortest < np.inf:  # every corridor too winding to pull taut
            continue
        kept = 0
        for k in range(found):
            if lengths[k] <= detour * shortest * (1.0 + LENGTH_TOLERANCE):
                kept += 1
        counts[i] = min(kept, max_classes)
