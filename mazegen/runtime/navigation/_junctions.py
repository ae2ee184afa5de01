"""The free rectangles' graph cut down to the places where a path has a choice: junctions, and the
chains of rectangles between them.

The rectangles of the path search (:mod:`mazegen.runtime.geometry._rectangles`) touch others above
and below. **Dead ends** go first: a rectangle with one neighbour left (none of the start's and the
goal's) is pruned, and so on inwards; a path that enters a dead end leaves it the way it came, so no
class's shortest path does. What is left are **junctions** (three neighbours or more, and the
start's and the goal's rectangles) joined by **chains** of rectangles with two neighbours each,
found breadth first from the start's junction. A floor's rectangles number in the tens to hundreds;
its junctions are about two per obstacle a path can pass on either side.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.geometry import ABOVE, BELOW, DOWN_COUNT, DOWN_FIRST, UP_COUNT, UP_FIRST

FROM, TO, FIRST, COUNT = 0, 1, 2, 3  # columns of a chain: its junctions, and where its interior is
INTERIOR = -2
"""``junction_of`` of a rectangle inside a chain already recorded."""


@njit(cache=True)
def junction_arrays(capacity):  # pragma: no cover - compiled
    """Scratch of :func:`junctions` for a decomposition of at most ``capacity`` rectangles."""
    chains = 2 * capacity + 1  # at most one per edge
    return (
        np.empty(capacity, np.int64),  # each rectangle's neighbours left (-1: pruned)
        np.empty(capacity, np.int64),  # rectangles to prune
        np.empty(capacity, np.int64),  # each rectangle's junction (-1: none, INTERIOR: in a chain)
        np.empty(capacity, np.int64),  # each junction's rectangle
        np.empty((chains, 4), np.int64),  # chains: FROM, TO, FIRST, COUNT
        np.empty(capacity, np.int64),  # the chains' rectangles, FROM end first, one chain after another
        np.empty(capacity + 1, np.int64),  # where each junction's chains begin in the next array
        np.empty((2 * chains, 2), np.int64),  # each junction's chains: chain, 0 walked FROM→TO or 1 back
    )


@wrapped_leaf_kernel
def junctions(rects, edges, count, start, goal, arrays):  # pragma: no cover - compiled
    """Prune the dead ends of a decomposition of ``count`` rectangles and join the junctions reachable
    from ``start`` by their chains.

    Returns:
        (junctions, chains): junction 0 is ``start``'s rectangle; the goal's is ``arrays[2][goal]``,
        -1 when the goal cannot be reached.
    """
    left, stack, junction_of, rectangle, chains, interior, offsets, incident = arrays
    _prune(rects, edges, count, start, goal, left, stack)
    for r in range(count):
        junction_of[r] = -1
    junction_of[start], rectangle[0] = 0, start
    found, n_chains, n_interior = 1, 0, 0
    done = 0
    while done < found:  # breadth first: ``done`` junctions have had their chains walked
        u = rectangle[done]
        for k in range(rects[u, UP_COUNT] + rects[u, DOWN_COUNT]):
            q = neighbour(rects, edges, u, k)
            if left[q] < 0 or junction_of[q] == INTERIOR:  # pruned, or a chain walked from its other end
                continue
            if _is_junction(left, q, start, goal) and 0 <= junction_of[q] < done:
                continue  # a chain of no interior, recorded when q's chains were walked
            first, previous = n_interior, u
            while not _is_junction(left, q, start, goal):
                junction_of[q] = INTERIOR
                interior[n_interior] = q
                n_interior += 1
                q, previous = _onwards(rects, edges, left, q, previous), q
            v = junction_of[q]
            if v < 0:  # a junction not seen yet
                v = found
                junction_of[q], rectangle[found] = v, q
                found += 1
            row = chains[n_chains]
            row[FROM], row[TO], row[FIRST], row[COUNT] = done, v, first, n_interior - first
            n_chains += 1
        done += 1
    _incidence(chains, n_chains, found, offsets, incident)
    return found, n_chains


@leaf_kernel
def _prune(rects, edges, count, start, goal, left, stack):  # pragma: no cover - compiled
    """``left``: each rectangle's neighbours once the dead ends are pruned, -1 for a pruned one."""
    top = 0
    for r in range(count):
        left[r] = rects[r, UP_COUNT] + rects[r, DOWN_COUNT]
        if left[r] <= 1 and r != start and r != goal:
            left[r] = -1
            stack[top] = r
            top += 1
    while top > 0:
        top -= 1
        r = stack[top]
        for k in range(rects[r, UP_COUNT] + rects[r, DOWN_COUNT]):
            q = neighbour(rects, edges, r, k)
            if left[q] < 0:
                continue
            left[q] -= 1
            if left[q] <= 1 and q != start and q != goal:
                left[q] = -1
                stack[top] = q
                top += 1


@leaf_kernel
def _incidence(chains, n_chains, found, offsets, incident):  # pragma: no cover - compiled
    """Each junction's chains, both ends of a chain that returns to its junction: ``incident[offsets[j]:
    offsets[j + 1]]``, as (chain, direction)."""
    for j in range(found + 1):
        offsets[j] = 0
    for c in range(n_chains):
        offsets[chains[c, FROM] + 1] += 1
        offsets[chains[c, TO] + 1] += 1
    for j in range(found):
        offsets[j + 1] += offsets[j]
    for c in range(n_chains):
        for direction in range(2):
            j = chains[c, FROM] if direction == 0 else chains[c, TO]
            slot = offsets[j]
            incident[slot, 0], incident[slot, 1] = c, direction
            offsets[j] += 1
    for j in range(found, 0, -1):  # each offset moved on by its junction's chains: move them back
        offsets[j] = offsets[j - 1]
    offsets[0] = 0


@njit(cache=True, inline="always")
def neighbour(rects, edges, r, k):  # pragma: no cover - compiled
    """The ``k``-th rectangle touching ``r``: those above first, then those below."""
    up = rects[r, UP_COUNT]
    if k < up:
        return edges[rects[r, UP_FIRST] + k, ABOVE]
    return edges[rects[r, DOWN_FIRST] + k - up, BELOW]


@njit(cache=True, inline="always")
def _is_junction(left, r, start, goal):  # pragma: no cover - compiled
    return left[r] != 2 or r in (start, goal)


@njit(cache=True, inline="always")
def _onwards(rects, edges, left, r, previous):  # pragma: no cover - compiled
    """The neighbour of chain rectangle ``r`` that is not pruned and not ``previous``."""
    for k in range(rects[r, UP_COUNT] + rects[r, DOWN_COUNT]):
        q = neighbour(rects, edges, r, k)
        if q != previous and left[q] >= 0:
            return q
    return -1
