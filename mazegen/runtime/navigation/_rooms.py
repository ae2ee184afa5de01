"""The free space of one floor cut into rooms: the raster half of the homotopy classes.

On the configuration-space grid of one floor (``free``: where the robot's centre may be):

1. **Obstacle groups**: blocked cells joined by any of their 8 neighbours are one group, and
   groups that touch the grid's edge are one with the outside (group 0, the boundary). Obstacles
   that touch in the configuration space are therefore one group: no robot passes between them.
2. **Voronoi regions**: every free cell of the start's component is labelled with its nearest
   group (a brushfire from the groups, each cell keeping the nearest blocked cell it has seen).
3. **Gaps**: where the regions of two groups meet (or a cell of one group's region touches the
   other group) lie the passages between those two groups; each connected stretch of such cells
   is one gap, with its narrowest point, where the two groups are nearest.
4. **Cuts**: a line of cells across each gap at its narrowest point, from one group to the other
   (a gap around a group that borders nothing else gets a second cut, opposite the first). A cut
   ends on blocked cells, so no path passes it without crossing it.
5. **Rooms**: the free cells left between the cuts, joined by their 4 neighbours. Each cut joins
   the two rooms on its sides: a path from start to goal is a walk through rooms across cuts.

Free cells are joined by 4 neighbours and blocked ones by 8, so that one cannot pass between two
cells the other joins diagonally (the rooms are what the walk search, :mod:`._classes`, reads).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel

BOUNDARY = 0
"""The group of the grid's edge and of every obstacle that touches it."""
NO_GROUP = -1
NOT_CUT = -1
PROMINENCE = 1.5
"""Cells by which a gap's narrow point must be narrower than the gap between it and a narrower
one to be a passage of its own (a cut of its own), rather than the raster's noise."""

STEPS4 = np.array([[0, 1], [1, 0], [0, -1], [-1, 0]], dtype=np.int64)
STEPS8 = np.array([[0, 1], [1, 1], [1, 0], [1, -1], [0, -1], [-1, -1], [-1, 0], [-1, 1]], dtype=np.int64)

# Columns of a cut row (``cuts``): its gap, the two groups, the cell it crosses at, the gap's width
# there (cells, between the two obstacles' cells) and the cell across (-1: an obstacle's).
CUT_GAP, CUT_FIRST, CUT_SECOND, CUT_ROW, CUT_COL, CUT_WIDTH, CUT_ACROSS = 0, 1, 2, 3, 4, 5, 6


@njit(cache=True)
def cut_rooms(free, start, goal):  # pragma: no cover - compiled
    """The rooms of ``free`` (``bool[rows, cols]``) around the start's component.

    Returns ``(group, component, label, nearest, cut_of, room, cuts, joins)``: each blocked cell's
    group (-1 on free cells), the start's component, each component cell's nearest group and its
    distance to that group's nearest cell (cell centres, in cells), each cell's cut (-1: none) and
    room (-1: none), one row per cut (columns ``CUT_*``) and the two rooms each cut joins.
    """
    rows, cols = free.shape
    group, groups = obstacle_groups(free)
    component = _component(free, start)
    label, nearest, source = _brushfire(free, group, component)
    entries = _gap_entries(free, group, groups, component, label)
    gap_of, gaps = _gap_stretches(entries, groups, rows, cols)
    cuts = _cut_rows(entries, gap_of, gaps, nearest, groups, rows, cols)
    cut_of = np.full((rows, cols), NOT_CUT, np.int64)
    for k in range(cuts.shape[0]):
        _draw_cut(cuts, k, free, source, cut_of)
    room = _label_rooms(component, cut_of)
    joins = _cut_joins(cut_of, room, cuts.shape[0])
    _end_room(start, cut_of, room, component)
    _end_room(goal, cut_of, room, component)
    return group, component, label, nearest, cut_of, room, cuts, joins


@inner_kernel
def obstacle_groups(free):  # pragma: no cover - compiled
    """Each blocked cell's group (8 neighbours; :data:`BOUNDARY` for those joined to the edge) and
    the number of groups."""
    rows, cols = free.shape
    group = np.full((rows, cols), NO_GROUP, np.int64)
    stack = np.empty(rows * cols, np.int64)
    for r in range(rows):  # the boundary first: every blocked cell on the edge
        for c in range(cols):
            edge = r == 0 or c == 0 or r == rows - 1 or c == cols - 1
            if edge and not free[r, c] and group[r, c] == NO_GROUP:
                _flood_blocked(free, group, stack, r, c, BOUNDARY)
    count = 1
    for r in range(rows):
        for c in range(cols):
            if not free[r, c] and group[r, c] == NO_GROUP:
                _flood_blocked(free, group, stack, r, c, count)
                count += 1
    return group, count


@inner_kernel
def _flood_blocked(free, group, stack, r0, c0, name):  # pragma: no cover - compiled
    rows, cols = free.shape
    group[r0, c0] = name
    stack[0], top = r0 * cols + c0, 1
    while top > 0:
        top -= 1
        r, c = stack[top] // cols, stack[top] % cols
        for s in range(8):
            rr, cc = r + STEPS8[s, 0], c + STEPS8[s, 1]
            if 0 <= rr < rows and 0 <= cc < cols and not free[rr, cc] and group[rr, cc] == NO_GROUP:
                group[rr, cc] = name
                stack[top] = rr * cols + cc
                top += 1


@inner_kernel
def _component(free, start):  # pragma: no cover - compiled
    """The free cells joined to ``start`` by 4 neighbours."""
    rows, cols = free.shape
    inside = np.zeros((rows, cols), np.bool_)
    if not free[start[0], start[1]]:
        return inside
    stack = np.empty(rows * cols, np.int64)
    inside[start[0], start[1]] = True
    stack[0], top = start[0] * cols + start[1], 1
    while top > 0:
        top -= 1
        r, c = stack[top] // cols, stack[top] % cols
        for s in range(4):
            rr, cc = r + STEPS4[s, 0], c + STEPS4[s, 1]
            if 0 <= rr < rows and 0 <= cc < cols and free[rr, cc] and not inside[rr, cc]:
                inside[rr, cc] = True
                stack[top] = rr * cols + cc
                top += 1
    return inside


@inner_kernel
def _brushfire(free, group, component):  # pragma: no cover - compiled
    """Each component cell's nearest group, its distance (cell centres, in cells) and that blocked
    cell (``source``; off the grid for the edge), propagated from the cells next to obstacles,
    each cell taking a neighbour's source when it is nearer than its own."""
    rows, cols = free.shape
    label = np.full((rows, cols), NO_GROUP, np.int64)
    nearest = np.full((rows, cols), np.inf)
    source = np.zeros((rows, cols, 2), np.int64)
    queue = np.empty(8 * rows * cols + 1, np.int64)
    head, tail = 0, 0
    for r in range(rows):
        for c in range(cols):
            if not component[r, c]:
                continue
            for s in range(8):
                rr, cc = r + STEPS8[s, 0], c + STEPS8[s, 1]
                outside = not (0 <= rr < rows and 0 <= cc < cols)
                if outside or not free[rr, cc]:
                    d = np.hypot(rr - r, cc - c)
                    if d < nearest[r, c]:
                        nearest[r, c] = d
                        label[r, c] = BOUNDARY if outside else group[rr, cc]
                        source[r, c, 0], source[r, c, 1] = rr, cc
            if label[r, c] != NO_GROUP:
                queue[tail] = r * cols + c
                tail += 1
    while head < tail:
        r, c = queue[head] // cols, queue[head] % cols
        head += 1
        sr, sc = source[r, c, 0], source[r, c, 1]
        for s in range(4):
            rr, cc = r + STEPS4[s, 0], c + STEPS4[s, 1]
            if 0 <= rr < rows and 0 <= cc < cols and component[rr, cc]:
                d = np.hypot(rr - sr, cc - sc)
                if d < nearest[rr, cc] - 1e-9 and tail < queue.shape[0]:
                    nearest[rr, cc], label[rr, cc] = d, label[r, c]
                    source[rr, cc, 0], source[rr, cc, 1] = sr, sc
                    queue[tail] = rr * cols + cc
                    tail += 1
    return label, nearest, source


@inner_kernel
def _gap_entries(free, group, groups, component, label):  # pragma: no cover - compiled
    """``int64[n, 3]`` rows ``(pair, cell, cell across or -1)``: a component cell of one group's
    region beside a cell of another group's region (4 neighbours) or beside another group's
    obstacle (8 neighbours), ``pair`` = smaller group × groups + larger, sorted by pair and cell."""
    rows, cols = free.shape
    out = np.empty((8 * int(component.sum()) + 1, 3), np.int64)
    n = 0
    for r in range(rows):
        for c in range(cols):
            if not component[r, c]:
                continue
            a = label[r, c]
            for s in range(8):
                rr, cc = r + STEPS8[s, 0], c + STEPS8[s, 1]
                inside = 0 <= rr < rows and 0 <= cc < cols
                if inside and component[rr, cc]:
                    if s % 2 == 1 or label[rr, cc] == a:
                        continue
                    b, other = label[rr, cc], rr * cols + cc
                else:
                    b = BOUNDARY if not inside else group[rr, cc]
                    other = -1
                    if b in (a, NO_GROUP):
                        continue
                out[n, 0] = min(a, b) * groups + max(a, b)
                out[n, 1], out[n, 2] = r * cols + c, other
                n += 1
    counts = np.zeros(groups * groups + 1, np.int64)  # a counting sort by pair; cells stay in order
    for e in range(n):
        counts[out[e, 0] + 1] += 1
    counts = np.cumsum(counts)
    ordered = np.empty((n, 3), np.int64)
    for e in range(n):
        at = counts[out[e, 0]]
        ordered[at, 0], ordered[at, 1], ordered[at, 2] = out[e, 0], out[e, 1], out[e, 2]
        counts[out[e, 0]] += 1
    return ordered


@inner_kernel
def _gap_stretches(entries, groups, rows, cols):  # pragma: no cover - compiled
    """Each entry's gap: the entries of one pair joined through cells that are the same or 8
    neighbours; and the number of gaps."""
    n = entries.shape[0]
    gap_of = np.full(n, -1, np.int64)
    at = np.full(rows * cols, -1, np.int64)  # an entry of the pair being split, per cell
    stack = np.empty(n + 1, np.int64)
    gaps, first = 0, 0
    while first < n:
        last = first
        while last < n and entries[last, 0] == entries[first, 0]:
            last += 1
        for e in range(first, last):
            cell = entries[e, 1]
            if at[cell] == -1:
                at[cell] = e
        for e in range(first, last):
            if gap_of[e] != -1:
                continue
            gap_of[e] = gaps
            stack[0], top = e, 1
            while top > 0:
                top -= 1
                cell = entries[stack[top], 1]
                _join_same_cell(entries, gap_of, at, cell, first, last, gaps)
                r, c = cell // cols, cell % cols
                for s in range(8):
                    rr, cc = r + STEPS8[s, 0], c + STEPS8[s, 1]
                    if 0 <= rr < rows and 0 <= cc < cols:
                        f = at[rr * cols + cc]
                        if f != -1 and gap_of[f] == -1:
                            gap_of[f] = gaps
                            stack[top] = f
                            top += 1
            gaps += 1
        for e in range(first, last):
            at[entries[e, 1]] = -1
        first = last
    return gap_of, gaps


@inner_kernel
def _join_same_cell(entries, gap_of, at, cell, first, last, gap):  # pragma: no cover - compiled
    """Entries of one cell (sorted together) share its gap."""
    e = at[cell]
    while e < last and entries[e, 1] == cell:
        gap_of[e] = gap
        e += 1


@inner_kernel
def _cut_rows(entries, gap_of, gaps, nearest, groups, rows, cols):  # pragma: no cover - compiled
    """A cut at each narrow point of each gap: its narrowest entry, and every other entry narrower
    than everything between it and a narrower one by :data:`PROMINENCE` cells (a second passage
    between the same two obstacles); and a second cut, at the entry farthest from the first, around
    a hole whose one gap has one cut. Rows: ``CUT_*`` columns."""
    n = entries.shape[0]
    width = np.empty(n)
    for e in range(n):
        cell, other = entries[e, 1], entries[e, 2]
        width[e] = nearest[cell // cols, cell % cols] + (
            0.0 if other < 0 else nearest[other // cols, other % cols]
        )
    keep = _narrow_points(entries, width, rows, cols)
    cuts_of_gap = np.zeros(gaps, np.int64)
    first_cut = np.full(gaps, -1, np.int64)
    for e in range(n):
        if keep[e]:
            cuts_of_gap[gap_of[e]] += 1
            if first_cut[gap_of[e]] < 0 or width[e] < width[first_cut[gap_of[e]]]:
                first_cut[gap_of[e]] = e
    borders = np.zeros(groups, np.int64)
    for g in range(gaps):
        pair = entries[first_cut[g], 0]
        borders[pair // groups] += 1
        borders[pair % groups] += 1
    far, far_d = np.full(gaps, -1, np.int64), np.full(gaps, -1.0)
    for e in range(n):
        a, b = entries[first_cut[gap_of[e]], 1], entries[e, 1]
        d = np.hypot(a // cols - b // cols, a % cols - b % cols)
        if d > far_d[gap_of[e]]:
            far_d[gap_of[e]], far[gap_of[e]] = d, e
    for g in range(gaps):
        pair = entries[first_cut[g], 0]
        lone = (pair // groups != BOUNDARY and borders[pair // groups] == 1) or borders[pair % groups] == 1
        if lone and cuts_of_gap[g] == 1:
            keep[far[g]] = True
    cuts = np.empty((int(keep.sum()), 7), np.float64)
    k = 0
    for e in range(n):
        if keep[e]:
            pair, cell = entries[e, 0], entries[e, 1]
            cuts[k, CUT_GAP], cuts[k, CUT_FIRST], cuts[k, CUT_SECOND] = (
                gap_of[e],
                pair // groups,
                pair % groups,
            )
            cuts[k, CUT_ROW], cuts[k, CUT_COL] = cell // cols, cell % cols
            cuts[k, CUT_WIDTH], cuts[k, CUT_ACROSS] = width[e], entries[e, 2]
            k += 1
    return cuts


@inner_kernel
def _narrow_points(entries, width, rows, cols):  # pragma: no cover - compiled
    """The entries that are a gap's narrow points: taken narrowest first, entries joined through
    cells that are the same or 8 neighbours grow stretches, each remembering its narrowest entry;
    where two stretches meet, the one whose narrowest is within :data:`PROMINENCE` of the meeting
    width is no passage of its own."""
    n = entries.shape[0]
    keep = np.zeros(n, np.bool_)
    parent = np.arange(n)
    lowest = np.arange(n)  # per root: its narrowest entry
    done = np.zeros(n, np.bool_)
    at = np.full(rows * cols, -1, np.int64)
    order = _sorted_order(entries[:, 0] * (width.max() + 1.0) + width if n else width)
    first = 0
    while first < n:
        last = first
        while last < n and entries[last, 0] == entries[first, 0]:
            last += 1
        for e in range(last - 1, first - 1, -1):
            at[entries[e, 1]] = e  # the first entry of each cell
        for e in order[first:last]:  # by pair, then narrowest first
            done[e] = True
            r, c = entries[e, 1] // cols, entries[e, 1] % cols
            for s in range(9):
                rr, cc = (r, c) if s == 8 else (r + STEPS8[s, 0], c + STEPS8[s, 1])
                if not (0 <= rr < rows and 0 <= cc < cols):
                    continue
                f = at[rr * cols + cc]
                while f >= 0 and f < last and entries[f, 1] == rr * cols + cc:
                    if done[f] and f != e:
                        _merge(parent, lowest, keep, width, e, f)
                    f += 1
        for e in range(first, last):
            if _root(parent, e) == e:
                keep[lowest[e]] = True
            at[entries[e, 1]] = -1
        first = last
    return keep


@inner_kernel
def _sorted_order(keys):  # pragma: no cover - compiled
    """The indices that sort ``keys``, equal keys in their order: a bottom-up merge sort (numba's
    own argsort takes seconds more to compile, and this is all the rooms sort)."""
    n = keys.shape[0]
    order, spare = np.arange(n), np.empty(n, np.int64)
    width = 1
    while width < n:
        for low in range(0, n, 2 * width):
            middle, high = min(low + width, n), min(low + 2 * width, n)
            i, j = low, middle
            for k in range(low, high):
                if i < middle and (j >= high or keys[order[i]] <= keys[order[j]]):
                    spare[k] = order[i]
                    i += 1
                else:
                    spare[k] = order[j]
                    j += 1
        order, spare = spare, order
        width *= 2
    return order


@inner_kernel
def _merge(parent, lowest, keep, width, e, f):  # pragma: no cover - compiled
    """Join the stretches of ``e`` (being added, at its width) and ``f``; a stretch's narrowest
    entry that is :data:`PROMINENCE` narrower than the meeting point is a passage of its own."""
    a, b = _root(parent, e), _root(parent, f)
    if a == b:
        return
    if width[lowest[a]] > width[lowest[b]]:
        a, b = b, a
    if width[e] - width[lowest[b]] >= PROMINENCE:
        keep[lowest[b]] = True
    parent[b] = a


@inner_kernel
def _root(parent, e):  # pragma: no cover - compiled
    while parent[e] != e:
        parent[e] = parent[parent[e]]
        e = parent[e]
    return e


@inner_kernel
def _draw_cut(cuts, k, free, source, cut_of):  # pragma: no cover - compiled
    """Mark cut ``k``'s cells: from its cell straight to its nearest obstacle cell and, when the cell
    across the gap is free, from that one straight to its own."""
    cols = free.shape[1]
    r, c = np.int64(cuts[k, CUT_ROW]), np.int64(cuts[k, CUT_COL])
    _draw_line(r, c, source[r, c, 0], source[r, c, 1], free, cut_of, k)
    across = np.int64(cuts[k, CUT_ACROSS])
    if across >= 0:
        ar, ac = across // cols, across % cols
        _draw_line(ar, ac, source[ar, ac, 0], source[ar, ac, 1], free, cut_of, k)


@inner_kernel
def _draw_line(r0, c0, r1, c1, free, cut_of, k):  # pragma: no cover - compiled
    """Bresenham's line from ``(r0, c0)`` towards ``(r1, c1)``: its free cells, up to the first
    blocked one or the edge."""
    rows, cols = free.shape
    dr, dc = abs(r1 - r0), abs(c1 - c0)
    sr, sc = (1 if r1 > r0 else -1), (1 if c1 > c0 else -1)
    err = dc - dr
    r, c = r0, c0
    while 0 <= r < rows and 0 <= c < cols and free[r, c]:
        cut_of[r, c] = k
        if r == r1 and c == c1:
            break
        e2 = 2 * err
        if e2 > -dr:
            err -= dr
            c += sc
        if e2 < dc:
            err += dc
            r += sr


@inner_kernel
def _label_rooms(component, cut_of):  # pragma: no cover - compiled
    """The component's cells off the cuts, joined by 4 neighbours, numbered."""
    rows, cols = component.shape
    room = np.full((rows, cols), -1, np.int64)
    stack = np.empty(rows * cols, np.int64)
    count = 0
    for r0 in range(rows):
        for c0 in range(cols):
            if not component[r0, c0] or cut_of[r0, c0] != NOT_CUT or room[r0, c0] != -1:
                continue
            room[r0, c0] = count
            stack[0], top = r0 * cols + c0, 1
            while top > 0:
                top -= 1
                r, c = stack[top] // cols, stack[top] % cols
                for s in range(4):
                    rr, cc = r + STEPS4[s, 0], c + STEPS4[s, 1]
                    if (
                        0 <= rr < rows and 0 <= cc < cols and component[rr, cc]
                        and cut_of[rr, cc] == NOT_CUT and room[rr, cc] == -1
                    ):  # fmt: skip
                        room[rr, cc] = count
                        stack[top] = rr * cols + cc
                        top += 1
            count += 1
    return room


@inner_kernel
def _cut_joins(cut_of, room, cuts):  # pragma: no cover - compiled
    """``int64[cuts, 2]``: the two rooms most of each cut's cells touch (the same twice when its
    cells touch only one)."""
    rows, cols = cut_of.shape
    seen = np.zeros((cuts, 4, 2), np.int64)  # up to 4 rooms per cut and how often each is touched
    seen[:, :, 0] = -1
    for r in range(rows):
        for c in range(cols):
            k = cut_of[r, c]
            if k == NOT_CUT:
                continue
            for s in range(4):
                rr, cc = r + STEPS4[s, 0], c + STEPS4[s, 1]
                if 0 <= rr < rows and 0 <= cc < cols and room[rr, cc] >= 0:
                    for j in range(4):
                        if seen[k, j, 0] == room[rr, cc] or seen[k, j, 0] == -1:
                            seen[k, j, 0] = room[rr, cc]
                            seen[k, j, 1] += 1
                            break
    joins = np.full((cuts, 2), -1, np.int64)
    for k in range(cuts):
        first, second = -1, -1
        for j in range(4):
            if seen[k, j, 0] >= 0 and (first < 0 or seen[k, j, 1] > seen[k, first, 1]):
                first = j
        for j in range(4):
            if seen[k, j, 0] >= 0 and j != first and (second < 0 or seen[k, j, 1] > seen[k, second, 1]):
                second = j
        if first >= 0:
            joins[k, 0] = seen[k, first, 0]
            joins[k, 1] = seen[k, second, 0] if second >= 0 else seen[k, first, 0]
    return joins


@inner_kernel
def _end_room(end, cut_of, room, component):  # pragma: no cover - compiled
    """A start or goal on a cut takes the room of the nearest cell off the cuts (4 neighbours)."""
    rows, cols = room.shape
    r0, c0 = end[0], end[1]
    if not component[r0, c0] or room[r0, c0] >= 0:
        return
    seen = np.zeros((rows, cols), np.bool_)
    queue = np.empty(rows * cols, np.int64)
    queue[0], head, tail = r0 * cols + c0, 0, 1
    seen[r0, c0] = True
    while head < tail:
        r, c = queue[head] // cols, queue[head] % cols
        head += 1
        for s in range(4):
            rr, cc = r + STEPS4[s, 0], c + STEPS4[s, 1]
            if 0 <= rr < rows and 0 <= cc < cols and component[rr, cc] and not seen[rr, cc]:
                if room[rr, cc] >= 0:
                    room[r0, c0] = room[rr, cc]
                    return
                seen[rr, cc] = True
                queue[tail] = rr * cols + cc
                tail += 1
