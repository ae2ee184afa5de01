"""Free space as rectangles: the nodes the path search walks over.

Each row's free cells form runs. A run with exactly the column extent of a run in
the row below continues it, so a stack of equal runs is one rectangle, and a row
equal to the row below (common between the edges of elements) continues every
rectangle at once. Two rectangles touch when one ends in the row below the other's
first row and their column extents overlap; the robot crosses from one to the
other through the shared edge (a *portal*).

Edges are recorded as one merge of two rows' sorted runs finds them, so the
rectangles above a rectangle, like those below it, are one contiguous slice of the
edge list: no adjacency lists to build.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from mazegen.runtime.compiling import wrapped_leaf_kernel
from mazegen.runtime.geometry._bits import HIGH, ONE, lowest_bit

# Columns of a rectangle's row: its extent, then where its edges up and down are.
FIRST_ROW, LAST_ROW, FIRST_COL, LAST_COL = 0, 1, 2, 3
UP_FIRST, UP_COUNT, DOWN_FIRST, DOWN_COUNT = 4, 5, 6, 7
BELOW, ABOVE = 0, 1


@njit(cache=True, inline="always")
def runs_per_row(cols):  # pragma: no cover - compiled
    """The most free runs a row of ``cols`` cells can hold (free and blocked cells alternating)."""
    return cols // 2 + 1


@njit(cache=True)
def run_arrays(kept, cols):  # pragma: no cover - compiled
    """The runs of ``kept`` rows, as :func:`row_runs_of` writes them: first column, last column, label."""
    return np.zeros((kept, runs_per_row(cols), 3), np.int64)


@njit(cache=True)
def rectangle_arrays(rows, cols):  # pragma: no cover - compiled
    """Scratch of one decomposition of a ``rows`` x ``cols`` grid."""
    capacity = rows * runs_per_row(cols)
    # One row per rectangle and few arrays: the search that reads them keeps more in registers.
    return (
        np.zeros((capacity, 8), np.int64),  # rectangles: extent, then first and count of edges up and down
        np.zeros((2 * capacity + 1, 2), np.int64),  # edges: (rectangle below, rectangle above)
        run_arrays(np.int64(2), cols),  # runs of two rows, labelled with their rectangles
    )


@wrapped_leaf_kernel
def decompose(free, cols, cells, arrays):  # pragma: no cover - compiled
    """Split the free cells of bit rows ``free`` into rectangles and their edges.

    Args:
        free: ``uint64[rows, words]`` bit rows of free cells.
        cols: Columns of the grid (padding bits past it are ignored).
        cells: ``int64[4]``: start row and column, goal row and column.
        arrays: From :func:`rectangle_arrays`.

    Returns:
        (rectangles, start rectangle, goal rectangle); -1 for an end on a blocked cell.
    """
    rects, edges, row_runs = arrays
    rows = free.shape[0]
    count = 0
    n_edges = 0
    last = 0  # which half of row_runs holds the previous row's runs
    n_last = 0
    start = goal = -1
    for r in range(rows):
        if not same_as_below(free, r):
            now = 1 - last
            n_now = row_runs_of(free, r, cols, row_runs, now)
            count, n_edges = _join(row_runs, last, n_last, now, n_now, r, rects, edges, count, n_edges)
            last, n_last = now, n_now
        if r == cells[0]:
            start = run_label_at(row_runs, last, n_last, cells[1])
        if r == cells[2]:
            goal = run_label_at(row_runs, last, n_last, cells[3])
    for i in range(n_last):
        rects[row_runs[last, i, 2], LAST_ROW] = rows - 1
    return count, start, goal


@njit(cache=True, inline="always")
def same_as_below(free, r):  # pragma: no cover - compiled
    """Whether bit row ``r`` equals row ``r - 1`` (False for the first row): its runs are the same."""
    if r == 0:
        return False
    w = 0
    while w < free.shape[1] and free[r, w] == free[r - 1, w]:
        w += 1
    return w == free.shape[1]


@njit(cache=True, inline="always")
def row_runs_of(free, r, cols, out, slot):  # pragma: no cover - compiled
    """Free runs of row ``r`` into ``out[slot, :, :2]``, left to right; returns their number.

    A run starts at a set bit whose left neighbour is clear and ends at a set bit whose
    right neighbour is clear; both sets of bits are read off a few shifts per word, so a
    run costs two bit scans whatever its length.
    """
    words = free.shape[1]
    starts = 0
    ends = 0
    for w in range(words):
        x = free[r, w]
        left = free[r, w - 1] >> HIGH if w > 0 else np.uint64(0)
        right = free[r, w + 1] << HIGH if w + 1 < words else np.uint64(0)
        first = x & ~((x << ONE) | left)
        last = x & ~((x >> ONE) | right)
        while first:
            out[slot, starts, 0] = 64 * w + lowest_bit(first)
            first &= first - ONE
            starts += 1
        while last:
            out[slot, ends, 1] = min(64 * w + lowest_bit(last), cols - 1)  # padding is blocked: stay safe
            last &= last - ONE
            ends += 1
    return starts


@njit(cache=True, inline="always")
def _join(runs, below, n_below, here, n_here, r, rects, edges, count, n_edges):  # pragma: no cover
    """Give each run of row ``r`` (``runs[here]``) its rectangle and record the edges to the
    rectangles of the row below (``runs[below]``).

    A run with the extent of a run below continues that rectangle (and touches nothing else
    below); any other run opens a rectangle, linked to every run below it overlaps. A run
    below that does not go on closes its rectangle at row ``r - 1``.

    Returns:
        (rectangles, edges) so far.
    """
    i = 0  # the first run below that may still overlap a run of this row
    for j in range(n_here):
        lo, hi = runs[here, j, 0], runs[here, j, 1]
        while i < n_below and runs[below, i, 1] < lo:
            rects[runs[below, i, 2], LAST_ROW] = r - 1
            i += 1
        if i < n_below and runs[below, i, 0] == lo and runs[below, i, 1] == hi:
            runs[here, j, 2] = runs[below, i, 2]
            i += 1
            continue
        runs[here, j, 2] = count
        rects[count, FIRST_ROW], rects[count, FIRST_COL], rects[count, LAST_COL] = r, lo, hi
        rects[count, UP_COUNT] = 0
        rects[count, DOWN_FIRST] = n_edges
        k = i
        while k < n_below and runs[below, k, 0] <= hi:
            a = runs[below, k, 2]
            rects[a, LAST_ROW] = r - 1
            edges[n_edges, BELOW], edges[n_edges, ABOVE] = a, count
            if rects[a, UP_COUNT] == 0:
                rects[a, UP_FIRST] = n_edges
            rects[a, UP_COUNT] += 1
            n_edges += 1
            k += 1
        rects[count, DOWN_COUNT] = n_edges - rects[count, DOWN_FIRST]
        count += 1
        while i < n_below and runs[below, i, 1] <= hi:
            i += 1
    while i < n_below:
        rects[runs[below, i, 2], LAST_ROW] = r - 1
        i += 1
    return count, n_edges


@njit(cache=True, inline="always")
def run_label_at(runs, slot, n_runs, c):  # pragma: no cover - compiled
    """The label (``runs[slot, i, 2]``) of the run holding column ``c``, or -1 when ``c`` is blocked."""
    for i in range(n_runs):
        if runs[slot, i, 0] <= c <= runs[slot, i, 1]:
            return runs[slot, i, 2]
    return -1
