"""The obstacle groups a path can pass on either side, a point of each, and a ray from each: what tells
and names a floor's homotopy classes (:mod:`._homotopy`, :mod:`._classes`).

The blocked cells of each row form runs; runs of neighbouring rows that touch (8 neighbours) are one
group, and a group touching the grid's edge is the edge. Every other group is a *hole*. Each hole's
mark is its cell farthest from the start-goal line, the point :func:`~._sides.sides` tells a path's
side of; its cells' sums give its centre, which orders the holes canonically.

From each hole a ray leaves to the right along the line under its lowest row, from the middle of that
row's leftmost cell. A path's H-signature counts, per hole, its signed crossings of that ray (up +1,
down -1; Bhattacharya et al. 2010). The cell under a ray's first cell is free (a blocked one would
belong to the hole), so a free edge between the two rows a ray runs between lies wholly left or
wholly right of its start, and a rectangle holding both rows too: whether a move between two
rectangles, or up or down within one, crosses a ray does not depend on where it is made
(:mod:`._homotopy` counts them).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.geometry import row_runs_of, run_arrays, runs_per_row

MAX_HOLES = 64
"""Holes a signature tells apart (it is two 64-bit masks); any found beyond them are left out."""


@njit(cache=True)
def hole_arrays(rows, cols):  # pragma: no cover - compiled
    """Scratch of :func:`holes_of` on a ``rows`` x ``cols`` grid."""
    capacity = rows * runs_per_row(cols)
    return (
        np.empty((capacity, 3), np.int64),  # blocked runs: row, first and last column
        np.empty(capacity + 1, np.int64),  # their groups' union-find parents (the last: the edge)
        np.empty((MAX_HOLES, 2), np.int64),  # each hole's ray: its row and first column
        np.empty((MAX_HOLES, 6)),  # each hole: mark x, y; its distance off the line; cells' x, y sums, count
        run_arrays(np.int64(1), cols),  # one row's free runs
    )


@wrapped_leaf_kernel
def holes_of(free, cols, points, arrays):  # pragma: no cover - compiled
    """Find the holes of bit rows ``free`` (``points``: start and goal, cells): their rays
    (``arrays[2]``) and marks, distances off the start-goal line and cells' sums (``arrays[3]``);
    returns their number."""
    return _find_holes(free, cols, points, arrays[0], arrays[1], arrays[3], arrays[4], arrays[2])


@leaf_kernel
def _find_holes(free, cols, points, runs, parent, holes, row_runs, rays):  # pragma: no cover - compiled
    """:func:`holes_of`, the scratch unpacked."""
    rows = free.shape[0]
    edge = runs.shape[0]
    parent[edge] = edge
    n = 0
    below_first = below_count = 0
    for r in range(rows):
        first = n
        free_runs = row_runs_of(free, r, cols, row_runs, 0)
        c = 0
        for i in range(free_runs + 1):
            end = row_runs[0, i, 0] - 1 if i < free_runs else cols - 1
            if end >= c:  # the blocked run before this free run (or after the last)
                runs[n, 0], runs[n, 1], runs[n, 2] = r, c, end
                parent[n] = n
                if r == 0 or r == rows - 1 or c == 0 or end == cols - 1:
                    _union(parent, n, edge)
                n += 1
            if i < free_runs:
                c = row_runs[0, i, 1] + 1
        # Runs of this row touching runs of the row below (diagonal neighbours too) are one group.
        i, j = below_first, first
        while i < below_first + below_count and j < n:
            if runs[i, 2] + 1 < runs[j, 1]:
                i += 1
            elif runs[j, 2] + 1 < runs[i, 1]:
                j += 1
            else:
                _union(parent, i, j)
                if runs[i, 2] <= runs[j, 2]:
                    i += 1
                else:
                    j += 1
        below_first, below_count = first, n - first
    sx, sy, gx, gy = points[0], points[1], points[2], points[3]
    norm = math.sqrt((gx - sx) * (gx - sx) + (gy - sy) * (gy - sy))
    norm = norm if norm > 0.0 else 1.0
    outside = _root(parent, edge)
    found = 0
    for k in range(n):
        root = _root(parent, k)
        if root == outside:
            continue
        if parent[root] >= 0 and found < MAX_HOLES:  # a root not yet named holds its own index
            rays[found, 0], rays[found, 1] = runs[k, 0], runs[k, 1]  # rows bottom up: its lowest, leftmost
            holes[found, 2] = -1.0
            holes[found, 3] = holes[found, 4] = holes[found, 5] = 0.0
            parent[root] = -1 - found  # roots named: -1 - hole
            found += 1
        h = -1 - parent[root]
        if h < 0 or h >= found:
            continue
        r, lo, hi = runs[k, 0], runs[k, 1], runs[k, 2]
        y = r + 0.5
        cells = hi - lo + 1.0
        holes[h, 3] += cells * (lo + hi + 1) / 2
        holes[h, 4] += cells * y
        holes[h, 5] += cells
        for x in (lo + 0.5, hi + 0.5):  # the distance off the line is linear along a run
            away = abs((gx - sx) * (y - sy) - (gy - sy) * (x - sx)) / norm
            if away > holes[h, 2]:
                holes[h, 0], holes[h, 1], holes[h, 2] = x, y, away
    return found


@njit(cache=True, inline="always")
def _root(parent, k):  # pragma: no cover - compiled
    """The root of ``k``'s group: a node whose parent is itself, or a named root (negative parent)."""
    while parent[k] >= 0 and parent[k] != k:
        parent[k] = parent[parent[k]] if parent[parent[k]] >= 0 else parent[k]
        k = parent[k]
    return k


@njit(cache=True, inline="always")
def _union(parent, a, b):  # pragma: no cover - compiled
    a, b = _root(parent, a), _root(parent, b)
    if a != b:
        parent[max(a, b)] = min(a, b)
