"""The homotopy classes of a floor's start-to-goal paths, searched over the junctions of the free
rectangles the path search already walks (:mod:`._junctions`).

**States.** A state of the search is a junction and the H-signature a walk has on its rectangle's first
row: per hole, the signed count of the walk's crossings of the hole's ray (:mod:`._holes`). Each chain
between two junctions crosses the rays the same way whoever walks it, so its counts are found once, and
a walk along it adds them (subtracts them, walked back). A count of two, a walk winding round a hole,
is not followed; a walk with the signature of one already at a junction goes no further unless it is
shorter.

**Search.** A* over states from the start's junction. A chain is walked rectangle by rectangle, each
one entered where the line from the previous entry towards the goal crosses the shared edge (as
:mod:`._paths` does), and its far junction reached with that cost; lowest estimate first, the queue
bucketed by whole cells. Each state of the goal's junction that is settled is a walk: its corridor
of rectangles is pulled taut at once by the funnel algorithm into its shortest path, whose side of each
hole names its class (:func:`~._sides.sides`, as a mask: the holes on its left); a class keeps its
shortest path. The search ends after :data:`GOAL_STATES_PER_CLASS` times ``max_classes`` walks have
reached the goal, or at an estimate beyond :data:`OVERSHOOT` times the length still wanted: ``detour``
times the shortest class, or the ``max_classes``-th shortest once that many are found. The caller keeps
the classes within ``detour`` of the shortest, at most ``max_classes``. When only their number is
wanted, the search ends as soon as ``max_classes`` classes are no longer than ``detour`` times the
straight line: the whole search would keep them, so the count is the same.

Two walks that reach a junction with one signature are one state, though they may wind round
obstacles in different orders (homologous, not homotopic): a class whose shortest path loops round one
obstacle before passing the others can be found longer than it is, or missed.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel, leaf_kernel
from mazegen.runtime.geometry import (
    FIRST_COL,
    FIRST_ROW,
    LAST_COL,
    LAST_ROW,
    decompose,
    rectangle_arrays,
    runs_per_row,
)
from mazegen.runtime.navigation._holes import hole_arrays, holes_of
from mazegen.runtime.navigation._junctions import COUNT, FIRST, FROM, TO, junction_arrays, junctions
from mazegen.runtime.navigation._paths import aim_across, dequeue, enqueue, funnel
from mazegen.runtime.navigation._sides import sides

STATES_PER_CLASS = 4
"""States a junction may hold per class sought: several signatures reach a junction on their way to
fewer classes at the goal."""
COST, X, Y = 0, 1, 2  # columns of the states' float array
JUNCTION, PREVIOUS, NEXT, SETTLED, CAME = 0, 1, 2, 3, 4  # columns of their int array
PLUS, MINUS = 0, 1  # columns of a signature: masks of the holes counted +1 and -1
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
"""Walks to the goal kept per class sought: two signatures may be one class (a loop round an obstacle
either way), and the funnel's lengths order them."""


@njit(cache=True)
def class_scratch(rows, cols, max_classes):  # pragma: no cover - compiled
    """Scratch of :func:`floor_classes` on a ``rows`` x ``cols`` grid."""
    capacity = rows * runs_per_row(cols)
    states = min(capacity * STATES_PER_CLASS * max_classes, 1 << 16)
    corridor = 2 * capacity + 2  # a walk may pass a rectangle twice, round an obstacle beside it
    joined = junction_arrays(capacity)
    chains = joined[4].shape[0]
    return (
        rectangle_arrays(rows, cols),
        joined,
        hole_arrays(rows, cols),
        np.empty((chains, 2), np.uint64),  # each chain's signature, walked forwards
        np.empty(chains, np.bool_),  # whether it winds (a count of two): not walked
        np.empty((states, 3)),  # states: cost so far, entry point
        np.empty((states, 5), np.int64),  # states: junction, previous state, next of its junction,
        # settled, the chain it came by (2 x chain + 1 when walked back; -1 for the start)
        np.empty((states, 2), np.uint64),  # states: signature
        np.empty((capacity, 2), np.int64),  # each junction's first state (-1: none) and states
        np.full(4 * (rows + cols) + 16, -1, np.int64),  # queue: first entry of each bucket
        np.empty((4 * states, 2), np.int64),  # queue entries: next in the bucket, state
        np.empty(GOAL_STATES_PER_CLASS * max_classes),  # the classes' lengths, sorted
        np.empty(corridor, np.int64),  # a corridor
        np.empty((corridor, 4)),  # its portals
        np.empty((corridor, 2)),  # its path's corners
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
        keys: ``uint64[S]`` its key: the holes on its left.
        paths: ``float64[S, C, 2]`` its shortest path's corners, cells (``C``: ``len(scratch[12])``);
            ``float64[0, 0, 2]`` when only the number of classes is wanted: the search then stops once
            ``max_classes`` are found within ``detour`` times the straight line, so of the shortest
            whatever is found later, all of which the whole search would keep.
        turns: ``int64[S]`` how many.

    Returns:
        (classes, holes): the classes found, and the holes, whose marks, distances off the start-goal
        line and cells' sums are ``scratch[2][3][:holes]``.
    """
    holes = holes_of(free, cols, points, scratch[2])
    rectangles = scratch[0]
    count, start, goal = decompose(free, cols, cells, rectangles)
    if start < 0 or goal < 0:
        return 0, holes
    rects = rectangles[0]
    found, n_chains = junctions(rects, rectangles[1], count, start, goal, scratch[1])
    goal_junction = scratch[1][2][goal]
    if goal_junction < 0:
        return 0, holes
    _chain_signatures(rects, n_chains, holes, scratch)
    out = (lengths, keys, paths, turns)
    args = (cells, points, holes, max_classes, detour, paths.shape[0] == 0)
    return _search(rects, found, goal_junction, args, scratch, out), holes


@leaf_kernel
def _chain_signatures(rects, n_chains, holes, scratch):  # pragma: no cover - compiled
    """Each chain's signature walked forwards, from its first junction's first row to its last's, and
    whether a count of two stops it."""
    rectangle, chains, interior = scratch[1][3], scratch[1][4], scratch[1][5]
    rays, signatures, winds = scratch[2][2], scratch[3], scratch[4]
    for c in range(n_chains):
        plus, minus, ok = np.uint64(0), np.uint64(0), True
        here = rectangle[chains[c, FROM]]
        n = chains[c, COUNT]
        for k in range(n + 1):
            there = rectangle[chains[c, TO]] if k == n else interior[chains[c, FIRST] + k]
            if ok:
                plus, minus, ok = _move(plus, minus, rects, here, there, rays, holes)
            here = there
        signatures[c, PLUS], signatures[c, MINUS], winds[c] = plus, minus, not ok


@leaf_kernel
def _move(plus, minus, rects, here, there, rays, holes):  # pragma: no cover - compiled
    """The signature after moving from ``here``'s first row to the touching ``there``'s."""
    low, high = rects[here, FIRST_ROW], rects[here, LAST_ROW]
    portal = max(rects[here, FIRST_COL], rects[there, FIRST_COL])
    if rects[there, FIRST_ROW] > high:  # up through this rectangle, then across the edge
        plus, minus, ok = crossed(plus, minus, low, high, rects[here, FIRST_COL], rays, holes)
        if ok:
            plus, minus, ok = crossed(plus, minus, high, rects[there, FIRST_ROW], portal, rays, holes)
        return plus, minus, ok
    there_high = rects[there, LAST_ROW]  # across the edge, then down through that one to its first row
    plus, minus, ok = crossed(plus, minus, low, there_high, portal, rays, holes)
    if ok:
        plus, minus, ok = crossed(
            plus, minus, there_high, rects[there, FIRST_ROW], rects[there, FIRST_COL], rays, holes
        )
    return plus, minus, ok


@inner_kernel
def _search(rects, found, goal, args, scratch, out):  # pragma: no cover - compiled
    """A* over (junction, signature) states from junction 0 to junction ``goal`` (see the module's
    docstring); returns the classes found, written to ``out`` (:func:`floor_classes`' arrays and
    arguments ``args``)."""
    cells, points, holes, max_classes, detour, counting = args
    rectangle, chains, interior = scratch[1][3], scratch[1][4], scratch[1][5]
    offsets, incident, rays = scratch[1][6], scratch[1][7], scratch[2][2]
    signatures, winds = scratch[3], scratch[4]
    state, links, masks, first_of = scratch[5], scratch[6], scratch[7], scratch[8]
    heads, entries = scratch[9], scratch[10]
    per_junction = STATES_PER_CLASS * max_classes
    for j in range(found):
        first_of[j, 0], first_of[j, 1] = -1, 0
    sx, sy, gx, gy = points[0], points[1], points[2], points[3]
    surely_kept = detour * math.sqrt((gx - sx) * (gx - sx) + (gy - sy) * (gy - sy)) * (1.0 + LENGTH_TOLERANCE)
    start = rectangle[0]
    plus, minus, _ = crossed(np.uint64(0), np.uint64(0), cells[0], rects[start, FIRST_ROW],
                             rects[start, FIRST_COL], rays, holes)  # fmt: skip
    last = heads.shape[0] - 1
    lowest = min(int(math.sqrt((gx - sx) * (gx - sx) + (gy - sy) * (gy - sy))), last)
    first_used = highest = lowest
    n_states = _add_state(0, plus, minus, 0.0, sx, sy, -1, -1, 0, state, links, masks, first_of)
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
        u = links[s, JUNCTION]
        spent, ex, ey = state[s, COST], state[s, X], state[s, Y]
        if spent + math.sqrt((gx - ex) * (gx - ex) + (gy - ey) * (gy - ey)) > bound:
            break
        if u == goal:  # a walk to the goal, perhaps of a class not seen yet
            here = rectangle[u]
            _, _, ok = crossed(masks[s, PLUS], masks[s, MINUS], rects[here, FIRST_ROW], cells[2],
                               rects[here, FIRST_COL], rays, holes)  # fmt: skip
            if ok:
                classes = _pull(s, classes, rects, points, holes, scratch, out)
                bound = _bound(out[0], classes, max_classes, detour, scratch[11])
                goals += 1
                if goals == scratch[11].shape[0] or (
                    counting and _sure(out[0], classes, surely_kept) >= max_classes
                ):
                    break
        for slot in range(offsets[u], offsets[u + 1]):
            c, back = incident[slot, 0], incident[slot, 1]
            if winds[c]:
                continue
            # Forwards a chain adds its counts; walked back, it takes them away.
            add, take = (PLUS, MINUS) if back == 0 else (MINUS, PLUS)
            plus, minus = masks[s, PLUS], masks[s, MINUS]
            up, down = signatures[c, add], signatures[c, take]
            if (plus & up) or (minus & down):  # round a hole the same way twice
                continue
            plus, minus = (plus & ~down) | (up & ~minus), (minus & ~up) | (down & ~plus)
            v = chains[c, TO] if back == 0 else chains[c, FROM]
            # Walk the chain's rectangles to v's, each entered greedily towards the goal.
            here, x, y, reached = rectangle[u], ex, ey, spent
            n = chains[c, COUNT]
            for k in range(n + 1):
                there = (
                    rectangle[v] if k == n else interior[chains[c, FIRST] + (k if back == 0 else n - 1 - k)]
                )
                x, y, reached = _enter(rects, here, there, x, y, gx, gy, reached)
                here = there
            t = first_of[v, 0]
            while t >= 0 and not (masks[t, PLUS] == plus and masks[t, MINUS] == minus):
                t = links[t, NEXT]
            if t < 0:
                if first_of[v, 1] >= per_junction or n_states == state.shape[0]:
                    continue
                t = n_states
                n_states = _add_state(
                    v, plus, minus, np.inf, x, y, s, 2 * c + back, n_states, state, links, masks, first_of
                )
            if links[t, SETTLED] or reached >= state[t, COST]:
                continue
            state[t, COST], state[t, X], state[t, Y] = reached, x, y
            links[t, PREVIOUS], links[t, CAME] = s, 2 * c + back
            if used == entries.shape[0]:
                continue
            bucket = min(int(reached + math.sqrt((gx - x) * (gx - x) + (gy - y) * (gy - y))), last)
            used = enqueue(heads, entries, used, bucket, t)
            lowest = min(lowest, bucket)
            first_used = min(first_used, bucket)
            highest = max(highest, bucket)
    heads[first_used : highest + 1] = -1  # the queue empty again for the next floor
    return classes


@njit(cache=True, inline="always")
def _enter(rects, here, there, x, y, gx, gy, reached):  # pragma: no cover - compiled
    """From ``(x, y)`` in rectangle ``here`` into the touching rectangle ``there``: where the line
    towards the goal crosses their shared edge, or as near as the edge allows; (x, y, cost so far)."""
    up = rects[there, FIRST_ROW] > rects[here, LAST_ROW]
    edge_y = float(rects[here, LAST_ROW] + 1 if up else rects[here, FIRST_ROW])
    lo = max(rects[here, FIRST_COL], rects[there, FIRST_COL])
    hi = min(rects[here, LAST_COL], rects[there, LAST_COL]) + 1
    edge_x = min(max(aim_across(x, y, gx, gy, edge_y), lo), hi)
    return edge_x, edge_y, reached + math.sqrt((edge_x - x) * (edge_x - x) + (edge_y - y) * (edge_y - y))


@inner_kernel
def _pull(s, classes, rects, points, holes, scratch, out):  # pragma: no cover - compiled
    """Pull the corridor of goal state ``s`` taut and keep its path as its class's, if its class is new
    or it is shorter; returns the classes kept."""
    rectangle, chains, interior = scratch[1][3], scratch[1][4], scratch[1][5]
    links = scratch[6]
    corridor, portals, corners = scratch[12], scratch[13], scratch[14]
    room = corridor.shape[0] - 2
    hops = 0
    while True:  # the goal's rectangle first, back to the start's
        corridor[hops] = rectangle[links[s, JUNCTION]]
        hops += 1
        came = links[s, CAME]
        if came < 0:
            break
        c, back = came >> 1, came & 1
        n = chains[c, COUNT]
        if hops + n + 1 > room:  # a walk too winding to keep
            return classes
        for k in range(n):  # the chain's rectangles from its far end back
            corridor[hops] = interior[chains[c, FIRST] + (n - 1 - k if back == 0 else k)]
            hops += 1
        s = links[s, PREVIOUS]
    length, n = funnel(rects, corridor, hops, points[0], points[1], points[2], points[3], portals, corners)
    side = sides(corners[:n], scratch[2][3][:holes, :2], points[:2], points[2:])
    key = np.uint64(0)
    for h in range(holes):
        if side[h] > 0:
            key |= np.uint64(1) << np.uint64(h)
    lengths, keys, paths, turns = out
    k = 0  # the class of the same key, or a new one
    while k < classes and keys[k] != key:
        k += 1
    if k < classes and lengths[k] <= length:
        return classes
    lengths[k], keys[k], turns[k] = length, key, n
    if paths.shape[0] > 0:
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
def _sure(lengths, classes, longest):  # pragma: no cover - compiled
    """How many of the classes found are no longer than ``longest``."""
    sure = 0
    for k in range(classes):
        if lengths[k] <= longest:
            sure += 1
    return sure


@njit(cache=True, inline="always")
def _add_state(
    j, plus, minus, cost, x, y, previous, came, n, state, links, masks, first_of
):  # pragma: no cover
    """State ``n``: junction ``j`` with a signature, first in ``j``'s list; returns the states now held."""
    state[n, COST], state[n, X], state[n, Y] = cost, x, y
    links[n, JUNCTION], links[n, PREVIOUS], links[n, NEXT] = j, previous, first_of[j, 0]
    links[n, SETTLED], links[n, CAME] = 0, came
    masks[n, PLUS], masks[n, MINUS] = plus, minus
    first_of[j, 0] = n
    first_of[j, 1] += 1
    return n + 1


@leaf_kernel
def crossed(plus, minus, row, to_row, col, rays, holes):  # pragma: no cover - compiled
    """The signature ``(plus, minus)`` (masks of the holes counted +1 and -1) after moving from row
    ``row`` to row ``to_row`` in columns from ``col`` on: each ray between the two (a ray of row ``r``
    runs under it) left of ``col`` counts +1 upward, -1 downward; ``ok`` False where a count reaches
    two."""
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
