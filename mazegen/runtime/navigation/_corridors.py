"""The shortest path along one walk through a floor's rooms, and which side of it each obstacle lies.

A walk (rooms ``R0 … Rm`` and the cuts ``c1 … cm`` crossed between them, from
:mod:`._rooms`) is searched as a stack of layers: layer ``2k`` holds room ``Rk``'s cells and layer
``2k + 1`` cut ``ck+1``'s, and a step from one layer to the next crosses into the next room. The
rooms along a walk, glued at the cuts it crosses, are simply connected, so the path found is the
shortest of its homotopy class within that corridor (8 neighbours; a diagonal step only between
two free cells of its layer, so it never cuts an obstacle's corner).
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel
from mazegen.runtime.navigation._rooms import NOT_CUT, STEPS8


@njit(cache=True)
def goal_distances(free, goal):  # pragma: no cover - compiled
    """``float64[rows, cols]``: each free cell's distance to ``goal`` by 8 neighbours (a diagonal step
    only between two free cells), ``inf`` where none leads: the corridors' estimate, exact where
    the walk's corridor holds the free floor's shortest way."""
    rows, cols = free.shape
    distance = np.full((rows, cols), np.inf)
    distance[goal[0], goal[1]] = 0.0
    heap = [(0.0, goal[0] * cols + goal[1])]
    while heap:
        here, cell = heapq.heappop(heap)
        r, c = cell // cols, cell % cols
        if here > distance[r, c]:
            continue
        for s in range(8):
            rr, cc = r + STEPS8[s, 0], c + STEPS8[s, 1]
            if not (0 <= rr < rows and 0 <= cc < cols and free[rr, cc]):
                continue
            if s % 2 == 1 and not (free[r, cc] and free[rr, c]):
                continue
            step = here + (math.sqrt(2.0) if s % 2 == 1 else 1.0)
            if step < distance[rr, cc] - 1e-12:
                distance[rr, cc] = step
                heapq.heappush(heap, (step, rr * cols + cc))
    return distance


@njit(cache=True)
def corridor_path(room, cut_of, walk_rooms, walk_cuts, start, goal, estimate):  # pragma: no cover - compiled
    """``(cells, length)``: the cells (``int64[n, 2]``, row and column) of the shortest path from
    ``start`` to ``goal`` along the walk, and its length in cells; no cells when there is none
    (A* over cells and layers, ``estimate`` of the distance left from each cell: :func:`goal_distances`)."""
    rows, cols = room.shape
    layers = 2 * walk_rooms.shape[0] - 1
    size = rows * cols
    cost = np.full(layers * size, np.inf)
    parent = np.full(layers * size, -1, np.int64)
    first = start[0] * cols + start[1]
    target = (layers - 1) * size + goal[0] * cols + goal[1]
    cost[first] = 0.0
    heap = [(estimate[start[0], start[1]], first)]
    while heap:
        queued, state = heapq.heappop(heap)
        if state == target:
            break
        here_cost = cost[state]
        if queued > here_cost + estimate[state % size // cols, state % cols] + 1e-9:
            continue  # queued before a shorter way here was found
        layer, cell = state // size, state % size
        r, c = cell // cols, cell % cols
        for s in range(8):
            rr, cc = r + STEPS8[s, 0], c + STEPS8[s, 1]
            if not (0 <= rr < rows and 0 <= cc < cols):
                continue
            diagonal = s % 2 == 1
            if diagonal:
                if not (
                    _holds(room, cut_of, walk_rooms, walk_cuts, layer, r, cc, start, goal)
                    and _holds(room, cut_of, walk_rooms, walk_cuts, layer, rr, c, start, goal)
                ):
                    continue
                choices = (layer, layer, layer)
            else:
                choices = (layer - 1, layer, layer + 1)
            for j in range(3):
                to = choices[j]
                if 0 <= to < layers and _holds(room, cut_of, walk_rooms, walk_cuts, to, rr, cc, start, goal):
                    step = math.sqrt(2.0) if diagonal else 1.0
                    next_state = to * size + rr * cols + cc
                    if here_cost + step < cost[next_state] - 1e-12:
                        cost[next_state] = here_cost + step
                        parent[next_state] = state
                        heapq.heappush(heap, (here_cost + step + estimate[rr, cc], next_state))
                    if diagonal:
                        break
    if cost[target] == np.inf:
        return np.empty((0, 2), np.int64), np.inf
    count, state = 0, target
    while state != -1:
        count += 1
        state = parent[state]
    cells = np.empty((count, 2), np.int64)
    state = target
    for k in range(count - 1, -1, -1):
        cell = state % size
        cells[k, 0], cells[k, 1] = cell // cols, cell % cols
        state = parent[state]
    return cells, cost[target]


@inner_kernel
def _holds(room, cut_of, walk_rooms, walk_cuts, layer, r, c, start, goal):  # pragma: no cover - compiled
    """Whether cell ``(r, c)`` belongs to ``layer``: its room's cells off the cuts (the start and
    goal also when on one), or its cut's cells."""
    if layer % 2 == 1:
        return cut_of[r, c] == walk_cuts[layer // 2]
    if room[r, c] != walk_rooms[layer // 2]:
        return False
    end = (r == start[0] and c == start[1]) or (r == goal[0] and c == goal[1])
    return cut_of[r, c] == NOT_CUT or end


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
def simple(cells, rows, cols):  # pragma: no cover - compiled
    """Whether a path of grid cells never comes back to a cell nor crosses its own diagonal step."""
    seen = np.zeros(rows * cols, np.uint8)  # bit 0: visited; bits 1, 2: a diagonal step rising, falling
    for k in range(cells.shape[0]):
        cell = cells[k, 0] * cols + cells[k, 1]
        if seen[cell] & 1:
            return False
        seen[cell] |= 1
        if k:
            pr, pc = cells[k - 1, 0], cells[k - 1, 1]
            if pr != cells[k, 0] and pc != cells[k, 1]:
                corner = min(pr, cells[k, 0]) * cols + min(pc, cells[k, 1])  # the step's lower-left cell
                rising = (cells[k, 0] - pr) * (cells[k, 1] - pc) > 0
                if seen[corner] & (4 if rising else 2):
                    return False
                seen[corner] |= 2 if rising else 4
    return True


@njit(cache=True)
def narrowest_width(cells, free):  # pragma: no cover - compiled
    """The narrowest free width the path of ``cells`` passes through, in cells: at each of its cells,
    the free cells across the path (both ways along the normal to its direction over a few cells,
    up to the first blocked cell or the edge); ``inf`` for a path of fewer than two cells."""
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
