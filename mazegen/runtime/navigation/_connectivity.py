"""Can the robot get from start to goal at all: solvability without the path.

Most fitnesses read whether a floor is solvable, not how long its path is. Then, per
individual, on the configuration space of :mod:`mazegen.runtime.geometry._cspace`:

1. **Straight line**: a free start-goal segment settles it, as in the path search.
2. **Components**: each row's free cells form runs; a run is joined, in a union-find,
   to every run of the row below it overlaps (a row equal to the row below joins
   nothing new). The floor is solvable when the start's and the goal's runs have the
   same root.

Cells connect exactly as they do in :mod:`mazegen.runtime.navigation._paths` (through a shared
edge), so the answer is the same; what is skipped is building rectangles and searching
them, more than half the cost of a path.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.geometry import (
    Grid,
    cspace,
    grid_args,
    raster_arrays,
    row_runs_of,
    run_arrays,
    run_label_at,
    runs_per_row,
    same_as_below,
    straight_free,
)
from mazegen.runtime.navigation._paths import kernel_args
from mazegen.runtime.threads import in_blocks

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population


@dataclass(frozen=True)
class Reach:
    """Solvability and coverage of every individual of a population, without paths.

    Attributes:
        solvable: ``bool[N]``: a path joins start and goal (False for invalid individuals).
        coverage: ``float64[N]``: fraction of the grid's cells the elements occupy.
    """

    solvable: np.ndarray
    coverage: np.ndarray


def reach(pop: Population, grid: Grid) -> Reach:
    """Solvability and coverage of every individual of ``pop`` on ``grid``."""
    n = pop.size
    solvable = np.zeros(n, dtype=np.bool_)
    coverage = np.zeros(n)
    if n:
        in_blocks(_reach_all, n, *kernel_args(pop), grid_args(grid), solvable, coverage, per_thread=16)
    return Reach(solvable, coverage)


@njit(cache=True, nogil=True)
def _reach_all(first, last, shapes, ids, n_el, params, valid, grid, solvable, coverage):  # pragma: no cover
    """Fill ``solvable`` and ``coverage`` of individuals ``first`` to ``last - 1``."""
    rows, cols = grid[1], grid[2]
    raster = raster_arrays(grid, ids.shape[1], shapes[2].shape[1], shapes[2].shape[2])
    free = np.zeros((rows, grid[4].shape[1]), np.uint64)
    runs, parent = component_arrays(rows, cols)
    for i in range(first, last):
        if not valid[i]:
            continue
        occupied = cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
        coverage[i] = occupied / (rows * cols)
        solvable[i] = straight_free(free, cols, grid[0], grid[5]) or connected(
            free, cols, grid[6], runs, parent
        )


def reachable(pop: Population, grid: Grid) -> np.ndarray:
    """``float64[N]``: the share of each floor's free cells (where the robot's centre may stand) joined
    to its start's cell, 0 for an invalid individual: 1 when no element closes off a pocket."""
    out = np.zeros(pop.size)
    if pop.size:
        in_blocks(_reachable_all, pop.size, *kernel_args(pop), grid_args(grid), out, per_thread=16)
    return out


@njit(cache=True, nogil=True)
def _reachable_all(first, last, shapes, ids, n_el, params, valid, grid, out):  # pragma: no cover - compiled
    """Fill ``out`` of individuals ``first`` to ``last - 1``."""
    rows, cols = grid[1], grid[2]
    raster = raster_arrays(grid, ids.shape[1], shapes[2].shape[1], shapes[2].shape[2])
    free = np.zeros((rows, grid[4].shape[1]), np.uint64)
    runs, parent = component_arrays(rows, cols)
    sizes = np.zeros(parent.shape[0], np.int64)
    for i in range(first, last):
        if valid[i]:
            cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
            out[i] = _reachable_share(free, cols, grid[6], runs, parent, sizes)


@leaf_kernel
def _reachable_share(free, cols, cells, runs, parent, sizes):  # pragma: no cover - compiled
    """The share of the free cells of bit rows ``free`` joined to the start cell (``cells[:2]``) through
    free cells sharing edges; ``sizes`` (all zero, and left so) counts each run label's cells."""
    count = 0
    last = 0
    n_last = 0
    start = -1
    total = 0
    for r in range(free.shape[0]):
        last, n_last, count = _row_joined(free, r, cols, runs, parent, last, n_last, count)
        for j in range(n_last):
            length = runs[last, j, 1] - runs[last, j, 0] + 1
            sizes[runs[last, j, 2]] += length
            total += length
        if r == cells[0]:
            start = run_label_at(runs, last, n_last, cells[1])
    reached = 0
    root = _root(parent, start) if start >= 0 else -1
    for label in range(count):
        if root >= 0 and _root(parent, label) == root:
            reached += sizes[label]
        sizes[label] = 0
    return reached / total if total else 0.0


@njit(cache=True)
def component_arrays(rows, cols):  # pragma: no cover - compiled
    """Scratch of :func:`connected` on a ``rows`` x ``cols`` grid: two rows' runs, and the union-find."""
    return run_arrays(np.int64(2), cols), np.zeros(rows * runs_per_row(cols), np.int64)


@wrapped_leaf_kernel
def connected(free, cols, cells, runs, parent):  # pragma: no cover - compiled
    """Whether the start and goal cells of bit rows ``free`` are joined by free cells sharing edges.

    Args:
        free: ``uint64[rows, words]`` bit rows of free cells.
        cols: Columns of the grid.
        cells: ``int64[4]``: start row and column, goal row and column.
        runs, parent: From :func:`component_arrays`.
    """
    count = 0
    last = 0  # which half of runs holds the row below's runs
    n_last = 0
    start = goal = -1
    for r in range(free.shape[0]):
        last, n_last, count = _row_joined(free, r, cols, runs, parent, last, n_last, count)
        if r == cells[0]:
            start = run_label_at(runs, last, n_last, cells[1])
        if r == cells[2]:
            goal = run_label_at(runs, last, n_last, cells[3])
    return start >= 0 and goal >= 0 and _root(parent, start) == _root(parent, goal)


@njit(cache=True, inline="always")
def _row_joined(free, r, cols, runs, parent, last, n_last, count):  # pragma: no cover - compiled
    """Row ``r``'s runs labelled, their sets joined to those of the row below's runs (``runs[last]``,
    ``n_last`` of them) they overlap: returns the row's slot, its run count and the labels used so far.
    A row equal to the row below keeps its runs and labels."""
    if same_as_below(free, r):
        return last, n_last, count
    now = 1 - last
    n_now = row_runs_of(free, r, cols, runs, now)
    return now, n_now, _join_runs(runs, last, n_last, now, n_now, parent, count)


@njit(cache=True, inline="always")
def _join_runs(runs, below, n_below, here, n_here, parent, count):  # pragma: no cover - compiled
    """Label each run of ``runs[here]`` as the first run below it overlaps, uniting that run's set
    with those of the others it overlaps (a new label when it overlaps none); returns the labels
    used so far. Most runs meet one run below: they only carry its label on."""
    i = 0  # the first run below that may still overlap a run of this row
    for j in range(n_here):
        lo, hi = runs[here, j, 0], runs[here, j, 1]
        while i < n_below and runs[below, i, 1] < lo:
            i += 1
        k = i
        if k < n_below and runs[below, k, 0] <= hi:  # the run goes on from the first run below it meets
            label = runs[below, k, 2]
            k += 1
            while k < n_below and runs[below, k, 0] <= hi:  # and joins the others' sets to its own
                _unite(parent, label, runs[below, k, 2])
                k += 1
        else:
            label = count
            parent[count] = count
            count += 1
        runs[here, j, 2] = label
        # The last run below that overlaps may reach past this run, under the next one too.
        i = k - 1 if k > i and runs[below, k - 1, 1] > hi else k
    return count


@njit(cache=True, inline="always")
def _unite(parent, a, b):  # pragma: no cover - compiled
    """Join the sets of ``a`` and ``b``."""
    a, b = _root(parent, a), _root(parent, b)
    if a != b:
        parent[b] = a


@njit(cache=True, inline="always")
def _root(parent, a):  # pragma: no cover - compiled
    """The root of ``a``'s set, halving the path on the way."""
    while parent[a] != a:
        parent[a] = parent[parent[a]]
        a = parent[a]
    return a
