"""The homotopy classes of a floor's start-to-goal paths, searched over the free rectangles the path
search already walks (:mod:`mazegen.runtime.geometry._rectangles`).

**Obstacle groups.** The blocked cells of each row form runs; runs of neighbouring rows that touch
(8 neighbours) are one group, and a group touching the grid's edge is the edge. Every other group is
a *hole*: an obstacle a path can pass on either side.

**Signatures.** From each hole a ray leaves to the right along the line under its lowest row, from
the middle of that row's leftmost cell. A path's signature counts, per hole, its signed crossings of
that ray (up +1, down -1): paths of different signatures are in different classes (the H-signature
of Bhattacharya et al. 2010). The cell under a ray's first cell is free (a blocked one would belong
to the hole), so a free edge between the two rows a ray runs between lies wholly left or wholly
right of its start, and a rectangle with both rows wholly left or right: whether a move between two
rectangles, or up or down within one, crosses a ray does not depend on where it is made. A state of
the search is a rectangle and the signature a path has on that rectangle's first row.

**Search.** A* over states, a rectangle entered where the line from the previous entry towards the
goal crosses the shared edge (as :mod:`._paths` does), lowest estimate first. A count of two in one
direction (a path winding around a hole) is not followed. Each state of the goal's rectangle that is
settled gives the goal a signature. Its corridor of rectangles is pulled taut at once by the funnel
algorithm into its shortest path, whose side of each hole names its class
(:func:`~mazegen.runtime.navigation._sides.sides`); a class keeps its shortest path. The search ends
after :data:`GOAL_STATES_PER_CLASS` times ``max_classes`` signatures, or at an estimate beyond
:data:`OVERSHOOT` times the length still wanted: ``detour`` times the shortest class, or the
``max_classes``-th shortest once that many are found. The caller keeps the classes within ``detour``
of the shortest, at most ``max_classes``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel
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
    decompose,
    rectangle_arrays,
    row_runs_of,
    runs_per_row,
)
from mazegen.runtime.navigation._paths import aim_across, dequeue, enqueue, funnel
from mazegen.runtime.navigation._sides import sides

MAX_HOLES = 64
"""Holes a signature tells apart (it is two 64-bit masks); holes found beyond them are left out."""
STATES_PER_CLASS = 4
"""States a rectangle may hold per class sought: several signatures reach a rectangle on their way
to fewer classes at the goal."""
COST, X, Y = 0, 1, 2  # columns of the states' float array
RECT, PREVIOUS, NEXT, SETTLED = 0, 1, 2, 3  # columns of their int array
OVERSHOOT = 1.5
"""How much longer than a corridor's shortest path the search's estimate of it may be: its entry points
are chosen greedily, one edge at a time, so a corridor around obstacles is estimated long. The search
settles states up to ``OVERSHOOT`` times the length still wanted (plus ``SLACK``), and the lengths the
funnel gives decide."""
SLACK = 2.0
"""Cells of estimate beyond that bound the search still settles: its queue is bucketed by whole cells."""
LENGTH_TOLERANCE = 1e-9
"""Relative slack of the detour test (a class as long as ``detour`` times the shortest is kept), the
same in every caller."""
GOAL_STATES_PER_CLASS = 4
"""Goal states (signatures) kept per class sought: two signatures may be one class (a loop around an
obstacle both ways), and the funnel's lengths order them."""


@njit(cache=True)
def class_scratch(rows, cols, max_classes):  # pragma: no cover - compiled
    """Scratch of :func:`floor_classes` on a ``rows`` x ``cols`` grid."""
    capacity = rows * runs_per_row(cols)
    states = min(capacity * STATES_PER_CLASS * max_classes, 1 << 16)
    return (
        np.empty((capacity, 3), np.int64),  # blocked runs: row, first and last column
        np.empty(capacity + 1, np.int64),  # their groups' union-find parents (the last: the edge)
        np.empty((MAX_HOLES, 2), np.int64),  # each hole's ray: its row and first column
        np.empty((MAX_HOLES, 6)),  # each hole: mark x, y; its distance off the line; cells' x, y sums, count
        rectangle_arrays(rows, cols),
        np.empty((states, 3)),  # states: cost so far, entry point
        np.empty((states, 4), np.int64),  # states: rectangle, previous state, next of its rectangle, settled
        np.empty((states, 2), np.uint64),  # states: signature, as masks of the +1 and the -1 counts
        np.empty((capacity, 2), np.int64),  # each rectangle's first state (-1: none) and states
        np.full(4 * (rows + cols) + 16, -1, np.int64),  # queue: first entry of each bucket
        np.empty((4 * states, 2), np.int64),  # queue entries: next in the bucket, state
        np.empty(GOAL_STATES_PER_CLASS * max_classes),  # the classes' lengths, sorted
        np.empty(capacity + 2, np.int64),  # a corridor
        np.empty((capacity + 2, 4)),  # its portals
        np.empty((capacity + 2, 2)),  # its path's corners
    )


@njit(cache=True)
def floor_classes(free, cols, cells, points, max_classes, detour, scratch, lengths, keys, paths, turns):
    """The homotopy classes of one floor, written to the caller's arrays.

    Args:
        free: ``uint64[rows, words]`` bit rows of configuration-space free cells.
        cols: Columns of the grid.
        cells: ``int64[4]`` start row and column, goal row and column.
        points: ``float64[4]`` start and goal, in cells.
        max_classes: Classes sought.
        detour: Longest class sought, as a multiple of the shortest.
        scratch: From :func:`class_scratch`.
        lengths: ``float64[S]`` each class's shortest path length, cells (``S`` is
            :data:`GOAL_STATES_PER_CLASS` times ``max_classes``: the classes found on the way to the
            shortest ``max_classes``).
        keys: ``int64[S, MAX_HOLES]`` its side of each hole (+1 left, -1 right).
        paths: ``float64[S, C, 2]`` its shortest path's corners, cells (``C``: ``len(scratch[12])``).
        turns: ``int64[S]`` how many.

    Returns:
        (classes, holes): the classes found, and the holes, whose marks, distances off the start-goal
        line and cells' sums are ``scratch[3][:holes]``.
    """
    holes = _holes(free, cols, points, scratch)
    rectangles = scratch[4]
    count, start, goal = decompose(free, cols, cells, rectangles)
    if start < 0 or goal < 0:
        return 0, holes
    out = (lengths, keys, paths, turns)
    return _search(
        rectangles, count, start, goal, cells, points, holes, max_classes, detour, scratch, out
    ), holes


@inner_kernel
def _holes(free, cols, points, scratch):  # pragma: no cover - compiled
    """Find the holes: their rays, marks and cells' sums (:func:`class_scratch`); returns their number."""
    runs, parent, rays, holes = scratch[0], scratch[1], scratch[2], scratch[3]
    row_runs = scratch[4][2]
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
    for k in range(n):  # rows bottom up: a group's first run is in its lowest row, its leftmost there
        root = _root(parent, k)
        if root == outside:
            continue
        if parent[root] >= 0 and found < MAX_HOLES:  # a root not yet named holds its own index
            rays[found, 0], rays[found, 1] = runs[k, 0], runs[k, 1]
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


@inner_kernel
def _search(
    rectangles, count, start, goal, cells, points, holes, max_classes, detour, scratch, out
):  # pragma: no cover
    """A* over (rectangle, signature) states from the start to the goal (see the module's docstring);
    returns the classes found, written to ``out`` (:func:`floor_classes`' arrays)."""
    rects, edges = rectangles[0], rectangles[1]
    state, links, masks, first_of = scratch[5], scratch[6], scratch[7], scratch[8]
    heads, entries, rays = scratch[9], scratch[10], scratch[2]
    per_rectangle = STATES_PER_CLASS * max_classes
    for q in range(count):
        first_of[q, 0], first_of[q, 1] = -1, 0
    sx, sy, gx, gy = points[0], points[1], points[2], points[3]
    plus, minus, ok = _crossed(np.uint64(0), np.uint64(0), cells[0], rects[start, FIRST_ROW],
                             rects[start, FIRST_COL], rays, holes)  # fmt: skip
    last = heads.shape[0] - 1
    lowest = min(int(math.sqrt((gx - sx) * (gx - sx) + (gy - sy) * (gy - sy))), last)
    first_used = highest = lowest
    n_states = _add_state(start, plus, minus, 0.0, sx, sy, -1, 0, state, links, masks, first_of)
    used = enqueue(heads, entries, 0, lowest, 0)
    bound = math.inf
    classes = goals = 0
    while True:
        lowest, s = dequeue(heads, entries, lowest, highest)
        if s < 0:
            break
        if links[s, SETTLED]:
            continue
        links[s, SETTLED] = 1
        here = links[s, RECT]
        spent, ex, ey = state[s, COST], state[s, X], state[s, Y]
        estimate = spent + math.sqrt((gx - ex) * (gx - ex) + (gy - ey) * (gy - ey))
        if estimate > bound:
            break
        if here == goal:  # each signature of the goal's rectangle: a path, perhaps of another class
            goal_row, goal_col = rects[goal, FIRST_ROW], rects[goal, FIRST_COL]
            _, _, ok = _crossed(masks[s, 0], masks[s, 1], goal_row, cells[2], goal_col, rays, holes)
            if ok:
                classes = _pull(s, classes, rects, points, holes, scratch, out)
                bound = _bound(out[0], classes, max_classes, detour, scratch[11])
                goals += 1
                if goals == scratch[11].shape[0]:
                    break
        for side in range(2):  # the rectangles above, then those below
            up = side == 0
            first = rects[here, UP_FIRST] if up else rects[here, DOWN_FIRST]
            n = rects[here, UP_COUNT] if up else rects[here, DOWN_COUNT]
            y = float(rects[here, LAST_ROW] + 1 if up else rects[here, FIRST_ROW])
            aim = aim_across(ex, ey, gx, gy, y)
            lo_here, hi_here = rects[here, FIRST_COL], rects[here, LAST_COL] + 1
            for e in range(first, first + n):
                q = edges[e, ABOVE] if up else edges[e, BELOW]
                portal = max(lo_here, rects[q, FIRST_COL])
                low, high = rects[here, FIRST_ROW], rects[here, LAST_ROW]
                q_low, q_high = rects[q, FIRST_ROW], rects[q, LAST_ROW]
                if up:  # up through this rectangle, then across the edge
                    p, m, ok = _crossed(masks[s, 0], masks[s, 1], low, high, lo_here, rays, holes)
                    if ok:
                        p, m, ok = _crossed(p, m, high, q_low, portal, rays, holes)
                else:  # across the edge, then down through that rectangle to its first row
                    p, m, ok = _crossed(masks[s, 0], masks[s, 1], low, q_high, portal, rays, holes)
                    if ok:
                        p, m, ok = _crossed(p, m, q_high, q_low, rects[q, FIRST_COL], rays, holes)
                if not ok:
                    continue
                x = min(max(aim, portal), min(hi_here, rects[q, LAST_COL] + 1))
                reached = spent + math.sqrt((x - ex) * (x - ex) + (y - ey) * (y - ey))
                t = first_of[q, 0]
                while t >= 0 and not (masks[t, 0] == p and masks[t, 1] == m):
                    t = links[t, NEXT]
                if t < 0:
                    if first_of[q, 1] >= per_rectangle or n_states == state.shape[0]:
                        continue
                    t = n_states
                    n_states = _add_state(q, p, m, np.inf, x, y, s, n_states, state, links, masks, first_of)
                if links[t, SETTLED] or reached >= state[t, COST]:
                    continue
                state[t, COST], state[t, X], state[t, Y] = reached, x, y
                links[t, PREVIOUS] = s
                if used == entries.shape[0]:
                    continue
                bucket = min(int(reached + math.sqrt((gx - x) * (gx - x) + (gy - y) * (gy - y))), last)
                used = enqueue(heads, entries, used, bucket, t)
                lowest = min(lowest, bucket)
                first_used = min(first_used, bucket)
                highest = max(highest, bucket)
    heads[first_used : highest + 1] = -1  # the queue empty again for the next floor
    return classes


@inner_kernel
def _pull(s, classes, rects, points, holes, scratch, out):  # pragma: no cover - compiled
    """Pull the corridor of goal state ``s`` taut and keep its path as its class's, if its class is new
    or it is shorter; returns the classes kept."""
    links, corridor, portals, corners = scratch[6], scratch[12], scratch[13], scratch[14]
    hops = 0
    while s >= 0 and hops < corridor.shape[0] - 2:
        corridor[hops] = links[s, RECT]
        hops += 1
        s = links[s, PREVIOUS]
    if s >= 0:  # through more rectangles than there are: too winding to keep
        return classes
    length, n = funnel(rects, corridor, hops, points[0], points[1], points[2], points[3], portals, corners)
    side = sides(corners[:n], scratch[3][:holes, :2], points[:2], points[2:])
    lengths, keys, paths, turns = out
    k = 0  # the class of the same sides, or a new one
    while k < classes:
        h = 0
        while h < holes and keys[k, h] == side[h]:
            h += 1
        if h == holes:
            break
        k += 1
    if k < classes and lengths[k] <= length:
        return classes
    lengths[k], turns[k] = length, n
    for h in range(holes):
        keys[k, h] = side[h]
    for t in range(n):
        paths[k, t, 0], paths[k, t, 1] = corners[t, 0], corners[t, 1]
    return max(classes, k + 1)


@inner_kernel
def _bound(lengths, classes, max_classes, detour, ordered):  # pragma: no cover - compiled
    """The largest estimate the search still settles: no class beyond ``detour`` times the shortest,
    nor beyond the ``max_classes``-th shortest, is wanted (:data:`OVERSHOOT`, :data:`SLACK`)."""
    for k in range(classes):
        ordered[k] = lengths[k]
    ordered[:classes].sort()
    wanted = detour * ordered[0]
    if classes >= max_classes:
        wanted = min(wanted, ordered[max_classes - 1])
    return OVERSHOOT * wanted + SLACK


@njit(cache=True, inline="always")
def _add_state(q, plus, minus, cost, x, y, previous, n, state, links, masks, first_of):  # pragma: no cover
    """State ``n``: rectangle ``q`` with a signature, first in ``q``'s list; returns the states now held."""
    state[n, COST], state[n, X], state[n, Y] = cost, x, y
    links[n, RECT], links[n, PREVIOUS], links[n, NEXT], links[n, SETTLED] = q, previous, first_of[q, 0], 0
    masks[n, 0], masks[n, 1] = plus, minus
    first_of[q, 0] = n
    first_of[q, 1] += 1
    return n + 1


@inner_kernel
def _crossed(plus, minus, row, to_row, col, rays, holes):  # pragma: no cover - compiled
    """The signature ``(plus, minus)`` after moving from row ``row`` to row ``to_row`` in columns from
    ``col`` on: each ray between the two (a ray of row ``r`` runs under it) left of ``col`` counts
    +1 upward, -1 downward; ``ok`` False where a count reaches two."""
    up = to_row > row
    ahead, back = (plus, minus) if up else (minus, plus)  # the counts in the move's direction, and against
    lo, hi = min(row, to_row), max(row, to_row)
    for h in range(holes):
        if lo < rays[h, 0] <= hi and col > rays[h, 1]:
            bit = np.uint64(1) << np.uint64(h)
            if ahead & bit:
                return plus, minus, False
            if back & bit:
                back &= ~bit
            else:
                ahead |= bit
    return (ahead, back, True) if up else (back, ahead, True)
