"""Which side of a path each obstacle lies, and the narrowest gap a path passes through: what names
a homotopy class (:mod:`._homotopy`, :mod:`._classes`) and tells a trajectory's class."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel


@njit(cache=True)
def sides(points, marks, start, goal):  # pragma: no cover - compiled
    """``int64[len(marks)]``: +1 where mark ``k`` lies left of the path ``points`` (start to goal),
    -1 right.

    The path is taken as one with the straight line through start and goal, going on beyond
    either end: a mark is on the straight line's side unless the loop of the path and the segment
    back from goal to start winds around it an odd number of times.
    """
    out = np.empty(marks.shape[0], np.int64)
    dx, dy = goal[0] - start[0], goal[1] - start[1]
    n = points.shape[0]
    for k in range(marks.shape[0]):
        px, py = marks[k, 0], marks[k, 1]
        side = 1 if dx * (py - start[1]) - dy * (px - start[0]) > 0 else -1
        winding = 0
        for j in range(n):
            ax, ay = points[j, 0], points[j, 1]
            bx, by = (points[j + 1, 0], points[j + 1, 1]) if j + 1 < n else (start[0], start[1])
            cross = (bx - ax) * (py - ay) - (px - ax) * (by - ay)
            if ay <= py < by and cross > 0:
                winding += 1
            elif by <= py < ay and cross < 0:
                winding -= 1
        out[k] = side if winding % 2 == 0 else -side
    return out


@njit(cache=True)
def narrowest_width(points, free):  # pragma: no cover - compiled
    """The narrowest free width a polyline of ``points`` (``[n, 2]``, cells) passes through, in cells:
    at each cell it passes (:func:`cells_along`), the free cells across the path (both ways along
    the normal to its direction over a few cells, up to the first blocked cell or the edge); ``inf``
    for a path of fewer than two cells."""
    cells = cells_along(points)
    rows, cols = free.shape
    n = cells.shape[0]
    narrowest = np.inf
    for k in range(n):
        a, b = max(k - 2, 0), min(k + 2, n - 1)
        dr, dc = float(cells[b, 0] - cells[a, 0]), float(cells[b, 1] - cells[a, 1])
        norm = math.hypot(dr, dc)
        if norm == 0.0:
            continue
        nr, nc = -dc / norm, dr / norm  # the normal, one way; the other is its opposite
        width = 0.0
        for way in (1.0, -1.0):
            t = 0.0
            while True:
                t += 0.5
                r = math.floor(cells[k, 0] + 0.5 + way * t * nr)
                c = math.floor(cells[k, 1] + 0.5 + way * t * nc)
                if not (0 <= r < rows and 0 <= c < cols) or not free[r, c]:
                    break
            width += t - 0.5
        narrowest = min(narrowest, width + 1.0)  # the cell itself
    return narrowest


@inner_kernel
def cells_along(points):  # pragma: no cover - compiled
    """``int64[n, 2]``: the cells (row, column) a polyline of ``points`` (cells) passes, in order, each
    once in a row: every segment sampled at ``max(2, ⌊4 · length⌋ + 1)`` evenly spaced points."""
    total = 0
    for j in range(points.shape[0] - 1):
        total += _samples(points[j + 1, 0] - points[j, 0], points[j + 1, 1] - points[j, 1])
    cells = np.empty((total, 2), np.int64)
    n = 0
    for j in range(points.shape[0] - 1):
        sx, sy = points[j, 0], points[j, 1]
        dx, dy = points[j + 1, 0] - sx, points[j + 1, 1] - sy
        samples = _samples(dx, dy)
        for k in range(samples):
            t = k / (samples - 1)
            r, c = math.floor(sy + dy * t), math.floor(sx + dx * t)
            if n == 0 or r != cells[n - 1, 0] or c != cells[n - 1, 1]:
                cells[n, 0], cells[n, 1] = r, c
                n += 1
    return cells[:n]


@njit(cache=True, inline="always")
def _samples(dx, dy):  # pragma: no cover - compiled
    """Points a segment ``(dx, dy)`` cells long is sampled at: four a cell, at least its two ends."""
    return max(2, int(4.0 * math.hypot(dx, dy)) + 1)
