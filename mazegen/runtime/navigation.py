"""Can the robot get from start to goal, and how far must it go: solvability kernels.

Per individual, in one compiled pass:

1. **Occupancy**: every convex part of every element marks the grid cells it
   touches (conservative: a wall thinner than a cell still blocks its cells).
   Cell ``(i, j)`` is ``[j c, (j+1) c] x [i c, (i+1) c]`` for the arena's cell ``c``.
2. **Configuration space**: a cell is blocked when an occupied cell's centre lies
   within the robot radius of its centre (a disc dilation), or when its centre is
   closer to the arena's edge than the radius.
3. **Runs**: each row's free cells form runs; two runs in neighbouring rows that
   share a column are connected. The scenario is solvable when the runs holding
   the start and goal cells are connected.
4. **Path**: an A* search over runs (a run is entered where the straight
   crossing from the previous entry point allows; the straight line to the goal
   guides the search; the queue is bucketed by whole cells), then the shortest path through
   the chosen corridor of runs by the funnel algorithm (string pulling through the
   portals between runs). In an open arena it is the straight segment.

Rows are bit sets of ``uint64`` words (bit ``j % 64`` of word ``j // 64`` is column ``j``),
so a whole row is dilated or tested in a few word operations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
from numba import njit, prange

from mazegen.runtime.geometry import _world_element

if TYPE_CHECKING:
    from mazegen.runtime.population import Population
    from mazegen.spec import Arena

_ONE = np.uint64(1)
_ALL = np.uint64(0xFFFFFFFFFFFFFFFF)
_DEBRUIJN = np.uint64(0x03F79D71B4CB0A89)
_DEBRUIJN_INDEX = np.zeros(64, np.int64)
for _bit in range(64):
    _DEBRUIJN_INDEX[((1 << _bit) * 0x03F79D71B4CB0A89 & 0xFFFFFFFFFFFFFFFF) >> 58] = _bit


@dataclass(frozen=True)
class Grid:
    """The occupancy grid of an arena and what every individual shares on it.

    Attributes:
        cell: Cell size in arena units.
        rows: Cells along y.
        cols: Cells along x.
        words: ``uint64`` words per row.
        spans: ``int64[R + 1]``: half-width in cells of the robot's disc ``dy`` rows away.
        border: ``uint64[rows, words]``: cells the robot's centre cannot occupy
            near the arena's edge, and the padding bits past ``cols``.
        start: ``(x, y)`` of the start, arena units.
        goal: ``(x, y)`` of the goal, arena units.
        start_cell: ``(row, col)`` the search starts from: the start's cell or, when the
            edge rule blocks it (a coarse grid puts its centre too near a wall), the
            nearest cell the edge rule leaves free.
        goal_cell: The same for the goal.
    """

    cell: float
    rows: int
    cols: int
    words: int
    spans: np.ndarray
    border: np.ndarray
    start: tuple[float, float]
    goal: tuple[float, float]
    start_cell: tuple[int, int]
    goal_cell: tuple[int, int]

    @classmethod
    def from_arena(cls, arena: Arena) -> Grid:
        """The grid of ``arena`` at its cell size (:attr:`Arena.cell`)."""
        cell = arena.cell
        cols = max(1, math.ceil(arena.width / cell - 1e-9))
        rows = max(1, math.ceil(arena.height / cell - 1e-9))
        words = (cols + 63) // 64
        reach = arena.robot_radius / cell
        spans = np.array(
            [math.floor(math.sqrt(max(reach * reach - dy * dy, 0.0)) + 1e-9) for dy in range(int(reach) + 1)],
            dtype=np.int64,
        )
        centres_x = (np.arange(cols) + 0.5) * cell
        centres_y = (np.arange(rows) + 0.5) * cell
        r = arena.robot_radius
        bad_col = (centres_x < r) | (centres_x > arena.width - r)
        bad_row = (centres_y < r) | (centres_y > arena.height - r)
        blocked = bad_row[:, None] | bad_col[None, :]
        padded = np.ones((rows, words * 64), dtype=bool)
        padded[:, :cols] = blocked
        weights = (_ONE << np.arange(64, dtype=np.uint64)).astype(np.uint64)
        border = (padded.reshape(rows, words, 64).astype(np.uint64) * weights).sum(axis=2, dtype=np.uint64)
        start, goal = arena.start, arena.goal
        ends = tuple(_end_cell(point, cell, centres_x, centres_y, blocked) for point in (start, goal))
        return cls(
            cell, rows, cols, words, spans, border, (start[0], start[1]), (goal[0], goal[1]), ends[0], ends[1]
        )


def _end_cell(
    point: tuple[float, float], cell: float, xs: np.ndarray, ys: np.ndarray, blocked: np.ndarray
) -> tuple[int, int]:
    row = min(max(int(point[1] // cell), 0), len(ys) - 1)
    col = min(max(int(point[0] // cell), 0), len(xs) - 1)
    if not blocked[row, col] or blocked.all():
        return row, col
    distance = (ys[:, None] - point[1]) ** 2 + (xs[None, :] - point[0]) ** 2
    nearest = np.unravel_index(np.argmin(np.where(blocked, np.inf, distance)), blocked.shape)
    return int(nearest[0]), int(nearest[1])


@lru_cache(maxsize=16)
def grid_of(arena: Arena) -> Grid:
    """The grid of ``arena``, built once per arena."""
    return Grid.from_arena(arena)


@dataclass(frozen=True)
class Navigation:
    """Solvability and path of every individual of a population.

    Attributes:
        solvable: ``bool[N]``: a path joins start and goal (False for invalid individuals).
        path_length: ``float64[N]``: its length in arena units, NaN when unsolvable.
        straight: Straight-line distance from start to goal.
        cell: The grid's cell size (path length in cells = ``path_length / cell``).
    """

    solvable: np.ndarray
    path_length: np.ndarray
    straight: float
    cell: float


def navigate(pop: Population, grid: Grid) -> Navigation:
    """Solvability and path length of every individual of ``pop`` on ``grid``."""
    n = pop.size
    solvable = np.zeros(n, dtype=np.bool_)
    length = np.full(n, np.nan)
    if n:
        _navigate_all(
            pop.table.shapes,
            np.ascontiguousarray(pop.element_ids, np.int32),
            np.ascontiguousarray(pop.n_elements, np.int32),
            np.ascontiguousarray(pop.params, np.float64),
            np.ascontiguousarray(pop.valid, np.bool_),
            _grid_args(grid),
            min(n, 32),
            solvable,
            length,
        )
    straight = math.dist(grid.start, grid.goal)
    return Navigation(solvable, length, straight, grid.cell)


def _grid_args(grid: Grid) -> tuple:
    (sr, sc), (gr, gc) = grid.start_cell, grid.goal_cell
    return (
        grid.cell,
        grid.rows,
        grid.cols,
        grid.spans,
        grid.border,
        np.array([*grid.start, *grid.goal], dtype=np.float64),
        np.array([sr, sc, gr, gc], dtype=np.int64),
    )


def free_cells(pop: Population, grid: Grid, index: int) -> np.ndarray:
    """``bool[rows, cols]`` configuration-space free cells of one individual (to inspect or test a floor)."""
    table = pop.table
    free = np.zeros((grid.rows, grid.words), np.uint64)
    parts, vertices = table.unit.shape[1:3]
    raster = _raster_arrays(grid.rows, grid.words, pop.element_ids.shape[1], parts, vertices)
    _cspace(
        table.shapes,
        np.ascontiguousarray(pop.element_ids[index], np.int32),
        int(pop.n_elements[index]),
        np.ascontiguousarray(pop.params[index], np.float64),
        _grid_args(grid),
        raster,
        free,
    )
    return unpack(free, grid.cols)


def unpack(bits: np.ndarray, cols: int) -> np.ndarray:
    """``bool[rows, cols]`` from rows of ``uint64`` words."""
    as_bytes = bits.astype("<u8").view(np.uint8).reshape(bits.shape[0], -1)
    return np.unpackbits(as_bytes, axis=1, bitorder="little")[:, :cols].astype(bool)


@njit(cache=True)
def _raster_arrays(rows, words, slots, parts, vertices):  # pragma: no cover - compiled
    """Scratch of one rasterisation: occupied rows, a widened row, world vertices and boxes."""
    slots = max(slots, 1)
    return (
        np.zeros((rows, words), np.uint64),
        np.zeros(words, np.uint64),
        np.zeros((slots, parts, vertices, 2)),
        np.zeros((slots, parts, 4)),
        np.zeros((slots, 4)),
    )


@njit(cache=True, parallel=True)
def _navigate_all(shapes, ids, n_el, params, valid, grid, blocks, solvable, length):  # pragma: no cover
    n = ids.shape[0]
    rows, cols, border = grid[1], grid[2], grid[4]
    words = border.shape[1]
    for block in prange(blocks):
        raster = _raster_arrays(rows, words, ids.shape[1], shapes[2].shape[1], shapes[2].shape[2])
        free = np.zeros((rows, words), np.uint64)
        capacity = rows * (cols // 2 + 1)
        runs = np.zeros((capacity, 3), np.int64)  # row, first column, last column
        row_first = np.zeros(rows + 1, np.int64)
        search = _search_arrays(capacity, 4 * (rows + cols) + 16)
        portals = np.zeros((capacity + 2, 4))
        for i in range(block * n // blocks, (block + 1) * n // blocks):
            if not valid[i]:
                continue
            _cspace(shapes, ids[i], n_el[i], params[i], grid, raster, free)
            count = _runs(free, cols, runs, row_first)
            found, total = _shortest(runs, row_first, count, grid, search, portals)
            solvable[i] = found
            if found:
                length[i] = total


@njit(cache=True)
def _cspace(shapes, ids, count, params, grid, raster, free):  # pragma: no cover - compiled
    """Free configuration-space cells of one individual, as bit rows in ``free``."""
    n_parts, n_vertices = shapes[0], shapes[1]
    cell, rows, cols, spans, border = grid[0], grid[1], grid[2], grid[3], grid[4]
    occupied, wide, wv, pbox, ebox = raster
    words = border.shape[1]
    occupied[:, :] = 0
    for k in range(count):
        e = ids[k]
        _world_element(shapes, e, params[k], wv, pbox, ebox, k)
        for p in range(n_parts[e]):
            _mark_part(wv, k, p, n_vertices[e, p], pbox[k, p], cell, rows, cols, occupied)
    # Disc dilation: an occupied row blocks the rows dy away, widened by the disc's half-width there.
    free[:, :] = border
    for source in range(rows):
        empty = True
        for w in range(words):
            empty &= occupied[source, w] == 0
        if empty:
            continue
        for dy in range(spans.shape[0]):
            _widen(occupied[source], spans[dy], wide)
            for r in (source - dy, source + dy):
                if 0 <= r < rows:
                    for w in range(words):
                        free[r, w] |= wide[w]
    for r in range(rows):
        for w in range(words):
            free[r, w] = ~free[r, w]


@njit(cache=True, inline="always")
def _mark_part(wv, k, p, nv, box, cell, rows, cols, occupied):  # pragma: no cover - compiled
    """Set every cell that convex part ``p`` of element ``k`` touches."""
    if box[2] < 0.0 or box[3] < 0.0 or box[0] > cols * cell or box[1] > rows * cell:
        return
    r0 = max(math.floor(box[1] / cell), 0)
    r1 = min(math.floor(box[3] / cell), rows - 1)
    for r in range(r0, r1 + 1):
        y0 = max(r * cell, box[1])
        y1 = min((r + 1) * cell, box[3])
        lo = np.inf
        hi = -np.inf
        for v in range(nv):
            u = v + 1 if v + 1 < nv else 0
            ax, ay, bx, by = wv[k, p, v, 0], wv[k, p, v, 1], wv[k, p, u, 0], wv[k, p, u, 1]
            # The edge clipped to the band [y0, y1]: its x-extent there.
            if ay > by:
                ax, ay, bx, by = bx, by, ax, ay
            if by < y0 or ay > y1:
                continue
            if by - ay > 0.0:
                ta = max((y0 - ay) / (by - ay), 0.0)
                tb = min((y1 - ay) / (by - ay), 1.0)
                xa = ax + (bx - ax) * ta
                xb = ax + (bx - ax) * tb
            else:
                xa, xb = ax, bx
            lo = min(lo, xa, xb)
            hi = max(hi, xa, xb)
        if hi < 0.0 or lo > cols * cell or hi < lo:
            continue
        c0 = max(math.floor(lo / cell), 0)
        c1 = min(math.floor(hi / cell), cols - 1)
        _set_span(occupied[r], c0, c1)


@njit(cache=True, inline="always")
def _set_span(row, first, last):  # pragma: no cover - compiled
    """Set columns ``first..last`` of a bit row."""
    for w in range(first >> 6, (last >> 6) + 1):
        lo = first - 64 * w if w == first >> 6 else 0
        hi = last - 64 * w if w == last >> 6 else 63
        width = hi - lo + 1
        mask = _ALL if width == 64 else ((_ONE << np.uint64(width)) - _ONE) << np.uint64(lo)
        row[w] |= mask


@njit(cache=True, inline="always")
def _widen(row, span, out):  # pragma: no cover - compiled
    """``out`` = ``row`` with every set bit spread ``span`` columns to each side."""
    words = row.shape[0]
    for w in range(words):
        out[w] = row[w]
    for t in range(1, span + 1):
        shift = np.uint64(t % 64)
        back = np.uint64(64 - t % 64)
        whole = t // 64
        for w in range(words):
            up = np.uint64(0)
            down = np.uint64(0)
            src = w - whole
            if 0 <= src < words:
                up = row[src] << shift if shift else row[src]
                if shift and src - 1 >= 0:
                    up |= row[src - 1] >> back
            src = w + whole
            if 0 <= src < words:
                down = row[src] >> shift if shift else row[src]
                if shift and src + 1 < words:
                    down |= row[src + 1] << back
            out[w] |= up | down


@njit(cache=True, inline="always")
def _lowest_bit(x):  # pragma: no cover - compiled
    """Index of the lowest set bit of a non-zero ``uint64`` (de Bruijn multiplication)."""
    return _DEBRUIJN_INDEX[((x & (~x + _ONE)) * _DEBRUIJN) >> np.uint64(58)]


@njit(cache=True)
def _runs(free, cols, runs, row_first):  # pragma: no cover - compiled
    """Free runs of every row, in row then column order; ``row_first[r]`` is row ``r``'s first run."""
    rows, words = free.shape
    count = 0
    for r in range(rows):
        row_first[r] = count
        open_start = -1
        for w in range(words):
            x = free[r, w]
            base = 64 * w
            if open_start >= 0 and not (x & _ONE):
                runs[count, 0], runs[count, 1], runs[count, 2] = r, open_start, base - 1
                count += 1
                open_start = -1
            while x:
                start = _lowest_bit(x)
                rest = ~x & (_ALL << np.uint64(start))
                stop = 64 if rest == 0 else _lowest_bit(rest)
                if open_start < 0:
                    open_start = base + start
                if stop == 64:
                    break  # the run may go on in the next word
                runs[count, 0], runs[count, 1], runs[count, 2] = r, open_start, base + stop - 1
                count += 1
                open_start = -1
                x &= _ALL << np.uint64(stop)
        if open_start >= 0:
            runs[count, 0], runs[count, 1], runs[count, 2] = r, open_start, 64 * words - 1
            count += 1
        for q in range(row_first[r], count):  # padding columns are blocked, but stay safe
            runs[q, 2] = min(runs[q, 2], cols - 1)
    row_first[rows] = count
    return count


@njit(cache=True)
def _search_arrays(capacity, buckets):  # pragma: no cover - compiled
    """Scratch arrays of one search over at most ``capacity`` runs."""
    return (
        np.zeros(capacity),  # cost
        np.zeros(capacity, np.int64),  # previous run
        np.zeros((capacity, 2)),  # entry point
        np.zeros(capacity, np.bool_),  # settled
        np.zeros(buckets, np.int64),  # queue: first entry of each bucket
        np.zeros(4 * capacity + 8, np.int64),  # queue: next entry in the same bucket
        np.zeros(4 * capacity + 8, np.int64),  # queue: the run of each entry
        np.zeros(capacity + 2, np.int64),  # corridor
    )


@njit(cache=True, inline="always")
def _run_at(runs, row_first, r, c):  # pragma: no cover - compiled
    for q in range(row_first[r], row_first[r + 1]):
        if runs[q, 1] <= c <= runs[q, 2]:
            return q
    return -1


@njit(cache=True)
def _shortest(runs, row_first, count, grid, search, portals):  # pragma: no cover - compiled
    """Search start run → goal run; returns (found, path length through the corridor)."""
    cell = grid[0]
    points, cells = grid[5], grid[6]
    cost, previous, entry, settled, heads, links, members, corridor = search
    start = _run_at(runs, row_first, cells[0], cells[1])
    goal = _run_at(runs, row_first, cells[2], cells[3])
    if start < 0 or goal < 0:
        return False, 0.0
    for q in range(count):
        cost[q] = np.inf
        settled[q] = False
    heads[:] = -1
    cost[start] = 0.0
    previous[start] = -1
    entry[start, 0], entry[start, 1] = points[0], points[1]
    gx, gy = points[2], points[3]
    # A bucket queue ordered by (cost so far + straight line still to go) in cells:
    # constant-time pushes and pops; within a bucket the order is last in, first out.
    last = heads.shape[0] - 1
    lowest = min(int(math.hypot(gx - points[0], gy - points[1]) / cell), last)
    used = _enqueue(heads, links, members, 0, lowest, start)
    while True:
        while lowest <= last and heads[lowest] < 0:
            lowest += 1
        if lowest > last:
            break
        taken = heads[lowest]
        heads[lowest] = links[taken]
        here = members[taken]
        if settled[here]:
            continue
        settled[here] = True
        if here == goal:
            break
        r = runs[here, 0]
        for side in range(2):
            other = r - 1 if side == 0 else r + 1
            if other < 0 or other >= row_first.shape[0] - 1:
                continue
            for q in range(row_first[other], row_first[other + 1]):
                lo = max(runs[here, 1], runs[q, 1])
                hi = min(runs[here, 2], runs[q, 2])
                if lo > hi or settled[q]:
                    continue
                # Cross the shared edge where the straight line from the entry point allows.
                y = max(r, other) * cell
                x = min(max(entry[here, 0], lo * cell), (hi + 1) * cell)
                dx, dy = x - entry[here, 0], y - entry[here, 1]
                step = math.sqrt(dx * dx + dy * dy)  # hypot's overflow care costs more than it saves here
                if cost[here] + step < cost[q]:
                    cost[q] = cost[here] + step
                    previous[q] = here
                    entry[q, 0], entry[q, 1] = x, y
                    rest = math.sqrt((gx - x) * (gx - x) + (gy - y) * (gy - y))
                    bucket = min(int((cost[q] + rest) / cell), last)
                    used = _enqueue(heads, links, members, used, bucket, q)
                    lowest = min(lowest, bucket)
    if not settled[goal]:
        return False, 0.0
    hops = 0
    q = goal
    while q >= 0:
        corridor[hops] = q
        hops += 1
        q = previous[q]
    return True, _funnel_length(runs, corridor, hops, cell, points, portals)


@njit(cache=True, inline="always")
def _enqueue(heads, links, members, used, bucket, run):  # pragma: no cover - compiled
    members[used] = run
    links[used] = heads[bucket]
    heads[bucket] = used
    return used + 1


@njit(cache=True)
def _funnel_length(runs, corridor, hops, cell, points, portals):  # pragma: no cover - compiled
    """Length of the shortest path from start to goal through the corridor's portals.

    ``corridor[hops - 1] .. corridor[0]`` are the runs from start to goal. Each
    portal is the edge two consecutive runs share, written (left, right) as seen
    when walking through it; the funnel algorithm pulls the path taut.
    """
    _portal(portals, 0, points[0], points[1], points[0], points[1])
    n = 1
    for h in range(hops - 1, 0, -1):
        a, b = corridor[h], corridor[h - 1]
        lo = max(runs[a, 1], runs[b, 1]) * cell
        hi = (min(runs[a, 2], runs[b, 2]) + 1) * cell
        y = max(runs[a, 0], runs[b, 0]) * cell
        if runs[b, 0] > runs[a, 0]:  # walking up (+y): left is smaller x
            _portal(portals, n, lo, y, hi, y)
        else:
            _portal(portals, n, hi, y, lo, y)
        n += 1
    _portal(portals, n, points[2], points[3], points[2], points[3])
    n += 1
    total = 0.0
    ax, ay = points[0], points[1]
    lx, ly, rx, ry = portals[0, 0], portals[0, 1], portals[0, 2], portals[0, 3]
    left_at = 0
    right_at = 0
    i = 1
    while i < n:
        plx, ply, prx, pry = portals[i, 0], portals[i, 1], portals[i, 2], portals[i, 3]
        corner = -1  # set when one side crosses the other: that side's far corner is on the path
        # Tighten the right side.
        if _cross(ax, ay, rx, ry, prx, pry) >= 0.0:
            if (ax == rx and ay == ry) or _cross(ax, ay, lx, ly, prx, pry) < 0.0:
                rx, ry, right_at = prx, pry, i
            else:
                corner, cx, cy = left_at, lx, ly
        # Tighten the left side.
        if corner < 0 and _cross(ax, ay, lx, ly, plx, ply) <= 0.0:
            if (ax == lx and ay == ly) or _cross(ax, ay, rx, ry, plx, ply) > 0.0:
                lx, ly, left_at = plx, ply, i
            else:
                corner, cx, cy = right_at, rx, ry
        if corner >= 0:  # walk to the corner and restart the funnel there
            total += math.hypot(cx - ax, cy - ay)
            ax, ay = cx, cy
            lx, ly, rx, ry = ax, ay, ax, ay
            left_at = right_at = i = corner
        i += 1
    return total + math.hypot(points[2] - ax, points[3] - ay)


@njit(cache=True, inline="always")
def _portal(portals, n, lx, ly, rx, ry):  # pragma: no cover - compiled
    portals[n, 0], portals[n, 1], portals[n, 2], portals[n, 3] = lx, ly, rx, ry


@njit(cache=True, inline="always")
def _cross(ax, ay, bx, by, cx, cy):  # pragma: no cover - compiled
    """Twice the signed area of triangle a, b, c: positive when c lies left of a → b."""
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
