"""The configuration space: where the robot's centre may be, as bit rows per individual.

1. **Occupancy**: every convex part of every element marks the grid cells it
   touches (conservative: a wall thinner than a cell still blocks its cells).
   Cell ``(i, j)`` is ``[j c, (j+1) c] x [i c, (i+1) c]`` for the arena's cell ``c``.
2. **Configuration space**: a cell is blocked when an occupied cell's centre lies
   within the robot radius of its centre (a disc dilation), or when its centre is
   closer to the arena's edge than the radius.

Rows are bit rows (:mod:`mazegen.runtime.geometry._bits`), so a whole row is dilated or tested
in a few word operations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.maps import base_on_grid, near_cells
from mazegen.runtime.compiling import wrapped_leaf_kernel
from mazegen.runtime.geometry._bits import HIGH, ONE, is_set, popcount, set_block
from mazegen.runtime.geometry._elements import ElementTable, population_arrays, world_element
from mazegen.runtime.threads import in_blocks

if TYPE_CHECKING:
    from mazegen.spec import Arena


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
        base: ``uint64[rows, words]``: the cells an arena's base map blocks (its walls, before the
            robot's disc widens them into ``border``), all clear without a map.
        wall_sums: ``int64[rows + 1, cols + 1]``: wall cells below and left of each cell corner (a
            summed-area table: the wall cells of any rectangle of cells in four reads).
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
    base: np.ndarray
    wall_sums: np.ndarray

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
        walls = np.zeros((rows, cols), dtype=bool)
        if arena.base is not None:  # the map's walls, widened by the robot's disc as elements are
            walls = base_on_grid(arena.base, cell, rows, cols)
            blocked |= near_cells(walls, reach)
        start, goal = arena.start, arena.goal
        ends = tuple(_end_cell(point, cell, blocked) for point in (start, goal))
        return cls(
            cell,
            rows,
            cols,
            words,
            spans,
            _bit_rows(blocked, words, pad=True),
            (start[0], start[1]),
            (goal[0], goal[1]),
            ends[0],
            ends[1],
            _bit_rows(walls, words, pad=False),
            np.pad(walls.cumsum(axis=0).cumsum(axis=1), ((1, 0), (1, 0))),
        )

    def for_task(self, start: tuple[float, float], goal: tuple[float, float]) -> Grid:
        """The same grid (its arrays shared) from ``start`` to ``goal``: one of a floor's tasks."""
        blocked = unpack(self.border, self.cols)
        return replace(
            self,
            start=start,
            goal=goal,
            start_cell=_end_cell(start, self.cell, blocked),
            goal_cell=_end_cell(goal, self.cell, blocked),
        )


def _bit_rows(cells: np.ndarray, words: int, *, pad: bool) -> np.ndarray:
    """``uint64[rows, words]`` of ``bool[rows, cols]``; the bits past ``cols`` set when ``pad``."""
    rows, cols = cells.shape
    padded = np.full((rows, words * 64), pad, dtype=bool)
    padded[:, :cols] = cells
    weights = (ONE << np.arange(64, dtype=np.uint64)).astype(np.uint64)
    return (padded.reshape(rows, words, 64).astype(np.uint64) * weights).sum(axis=2, dtype=np.uint64)


def _end_cell(point: tuple[float, float], cell: float, blocked: np.ndarray) -> tuple[int, int]:
    rows, cols = blocked.shape
    row = min(max(int(point[1] // cell), 0), rows - 1)
    col = min(max(int(point[0] // cell), 0), cols - 1)
    if not blocked[row, col] or blocked.all():
        return row, col
    ys, xs = (np.arange(rows) + 0.5) * cell, (np.arange(cols) + 0.5) * cell
    distance = (ys[:, None] - point[1]) ** 2 + (xs[None, :] - point[0]) ** 2
    nearest = np.unravel_index(np.argmin(np.where(blocked, np.inf, distance)), blocked.shape)
    return int(nearest[0]), int(nearest[1])


@lru_cache(maxsize=512)
def grid_of(arena: Arena) -> Grid:
    """The grid of ``arena``, built once per floor (a drive of many imported maps, each an arena of its
    own, holds each of theirs); the grids of one floor's tasks share its arrays."""
    return _floor_grid(replace(arena, start=(0.0, 0.0), goal=(0.0, 0.0), stations=(), tasks=())).for_task(
        arena.start, arena.goal
    )


@lru_cache(maxsize=64)
def _floor_grid(floor: Arena) -> Grid:
    return Grid.from_arena(floor)


def point_grid_of(arena: Arena) -> Grid:
    """The grid of ``arena``, same cells, for a robot of radius 0 (a point)."""
    return grid_of(replace(arena, robot_radius=0.0, grid=arena.cell))


def grid_args(grid: Grid) -> tuple:
    """The grid as the tuple the compiled kernels take."""
    (sr, sc), (gr, gc) = grid.start_cell, grid.goal_cell
    return (
        grid.cell,
        grid.rows,
        grid.cols,
        grid.spans,
        grid.border,
        np.array([*grid.start, *grid.goal], dtype=np.float64),
        np.array([sr, sc, gr, gc], dtype=np.int64),
        grid.base,
    )


def unpack(bits: np.ndarray, cols: int) -> np.ndarray:
    """``bool[rows, cols]`` from rows of ``uint64`` words."""
    as_bytes = bits.astype("<u8").view(np.uint8).reshape(bits.shape[0], -1)
    return np.unpackbits(as_bytes, axis=1, bitorder="little")[:, :cols].astype(bool)


@njit(cache=True)
def raster_arrays(grid, slots, parts, vertices):  # pragma: no cover - compiled
    """Scratch of one rasterisation on ``grid`` (:func:`grid_args`).

    The dilation works on padded copies of the occupancy: ``reach`` empty rows above and
    below, and guard words after each row wide enough for the widest span, so every shift
    stays inside the array and brings in zeros. Rows are then plain stretches of one flat
    array, and each step of the dilation is a single loop the compiler can vectorise.
    """
    rows, spans, words = grid[1], grid[3], grid[4].shape[1]
    reach = spans.shape[0] - 1
    stride = words + spans[0] // 64 + 1
    slots = max(slots, 1)
    return (
        np.zeros((spans[0] + 1, (rows + 2 * reach) * stride), np.uint64),  # occupancy widened by 0, 1, ...
        np.zeros(rows * stride, np.uint64),  # the dilated occupancy
        np.zeros((slots, parts, vertices, 2)),
        np.zeros((slots, parts, 4)),
        np.zeros((slots, 4)),
    )


@wrapped_leaf_kernel
def cspace(shapes, ids, count, params, grid, raster, free):  # pragma: no cover - compiled
    """Free configuration-space cells of one individual, as bit rows in ``free``; the occupied cells
    (its elements' and the base map's walls) are left in the first rows of ``raster``.

    Returns the number of cells the elements occupy (before the dilation).
    """
    n_parts, n_vertices = shapes[0], shapes[1]
    cell, rows, cols, spans, border = grid[0], grid[1], grid[2], grid[3], grid[4]
    widened, dilated, wv, pbox, ebox = raster
    words = border.shape[1]
    reach = spans.shape[0] - 1
    stride = dilated.shape[0] // rows
    inside = widened[0, reach * stride : (reach + rows) * stride]
    occupied = inside.reshape((rows, stride))
    inside[:] = 0
    for k in range(count):
        e = ids[k]
        world_element(shapes, e, params[k], wv, pbox, ebox, k)
        for p in range(n_parts[e]):
            _mark_part(wv, k, p, n_vertices[e, p], pbox[k, p], cell, rows, cols, occupied)
    occupied_cells = 0
    for i in range(inside.shape[0]):
        occupied_cells += popcount(inside[i])
    # The base map's walls are occupied too (for the fields read off this raster), though not counted.
    base = grid[7]
    for r in range(rows):
        for w in range(words):
            occupied[r, w] |= base[r, w]
    # Disc dilation: the occupancy widened by the disc's half-width dy rows away, shifted dy rows.
    for width in range(1, widened.shape[0]):
        _widen_flat(widened[width - 1], widened[width])
    # (Slices rather than offset indices: indices the compiler knows are not negative
    # spare it the wrap-around test that would keep these loops from being vectorised.)
    size = dilated.shape[0]
    first = widened[spans[reach], :size]
    for i in range(size):
        dilated[i] = first[i]
    for dy in range(1 - reach, reach + 1):
        source = widened[spans[abs(dy)], (reach + dy) * stride : (reach + dy) * stride + size]
        for i in range(size):
            dilated[i] |= source[i]
    rows_of = dilated.reshape((rows, stride))
    for r in range(rows):
        for w in range(words):
            free[r, w] = ~(rows_of[r, w] | border[r, w])
    return occupied_cells


@njit(cache=True, inline="always")
def floor_cells(grid):  # pragma: no cover - compiled
    """Cells of the grid (:func:`grid_args`) that are floor: all but those its base map's walls block."""
    walls = 0
    base = grid[7]
    for r in range(base.shape[0]):
        for w in range(base.shape[1]):
            walls += popcount(base[r, w])
    return grid[1] * grid[2] - walls


@njit(cache=True, inline="always")
def _widen_flat(source, out):  # pragma: no cover - compiled
    """``out`` = ``source`` with every set bit spread one column to each side (one flat bit string)."""
    last = source.shape[0] - 1
    for i in range(1, last):
        x = source[i]
        out[i] = x | (x << ONE) | (x >> ONE) | (source[i - 1] >> HIGH) | (source[i + 1] << HIGH)
    out[0] = source[0] | (source[0] << ONE) | (source[0] >> ONE) | (source[1] << HIGH)
    out[last] = source[last] | (source[last] << ONE) | (source[last] >> ONE) | (source[last - 1] >> HIGH)


@njit(cache=True, inline="always")
def _mark_part(wv, k, p, nv, box, cell, rows, cols, occupied):  # pragma: no cover - compiled
    """Set every cell that convex part ``p`` of element ``k`` touches."""
    if box[2] < 0.0 or box[3] < 0.0 or box[0] > cols * cell or box[1] > rows * cell:
        return
    r0 = max(math.floor(box[1] / cell), 0)
    r1 = min(math.floor(box[3] / cell), rows - 1)
    if nv == 4 and _axis_aligned(wv, k, p, 1e-9 * cell):  # walls and lines: every row spans the box
        if box[2] >= 0.0 and box[0] <= cols * cell:
            c0 = max(math.floor(box[0] / cell), 0)
            c1 = min(math.floor(box[2] / cell), cols - 1)
            set_block(occupied, r0, r1, c0, c1)
        return
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
        set_block(occupied, r, r, c0, c1)


@njit(cache=True, inline="always")
def _axis_aligned(wv, k, p, tolerance):  # pragma: no cover - compiled
    """Whether every edge of the 4-vertex part ``p`` of element ``k`` is horizontal or vertical."""
    for v in range(4):
        u = (v + 1) % 4
        dx = abs(wv[k, p, v, 0] - wv[k, p, u, 0])
        dy = abs(wv[k, p, v, 1] - wv[k, p, u, 1])
        if dx > tolerance and dy > tolerance:
            return False
    return True


@njit(cache=True, inline="always")
def is_free(free, r, c, cols):  # pragma: no cover - compiled
    """Whether cell ``(r, c)`` of the bit rows ``free`` is free; cells outside the grid are not."""
    return 0 <= r < free.shape[0] and 0 <= c < cols and is_set(free[r], c)


@wrapped_leaf_kernel
def straight_free(free, cols, cell, points):  # pragma: no cover - compiled
    """Whether every cell the segment start → goal touches is free (cells walked as in Amanatides and Woo;
    where it passes exactly through a cell corner, both side cells must be free too)."""
    rows = free.shape[0]
    x, y = points[0] / cell, points[1] / cell
    dx, dy = points[2] / cell - x, points[3] / cell - y
    c, r = math.floor(x), math.floor(y)
    end_c, end_r = math.floor(points[2] / cell), math.floor(points[3] / cell)
    step_c = 1 if dx > 0 else -1
    step_r = 1 if dy > 0 else -1
    next_c = ((c + (dx > 0)) - x) / dx if dx != 0 else np.inf
    next_r = ((r + (dy > 0)) - y) / dy if dy != 0 else np.inf
    delta_c = abs(1.0 / dx) if dx != 0 else np.inf
    delta_r = abs(1.0 / dy) if dy != 0 else np.inf
    for _ in range(rows + cols + 2):
        if not is_free(free, r, c, cols):
            return False
        if r == end_r and c == end_c:
            return True
        if next_c < next_r:
            c += step_c
            next_c += delta_c
        elif next_r < next_c:
            r += step_r
            next_r += delta_r
        else:  # through a corner: the two cells beside it as well
            if not is_free(free, r, c + step_c, cols) or not is_free(free, r + step_r, c, cols):
                return False
            c += step_c
            r += step_r
            next_c += delta_c
            next_r += delta_r
    return False


def elements_on_walls(
    table: ElementTable,
    element_ids: np.ndarray,
    n_elements: np.ndarray,
    params: np.ndarray,
    grid: Grid,
    size: tuple[float, float],
) -> np.ndarray:
    """``bool[N, K]``: which elements inside the arena's rectangle touch a cell of its base map's walls
    (``grid.base``; the cells an element touches, as the configuration space marks them).
    ``size`` is the arena's width and height: an element outside it is counted by
    :func:`~mazegen.runtime.geometry._overlap.elements_outside`, not here.
    """
    ids, n_el, prm = population_arrays(table, element_ids, n_elements, params)
    out = np.zeros(ids.shape, np.bool_)
    if ids.shape[0] and grid.wall_sums[-1, -1]:
        width, height = float(size[0]), float(size[1])
        args = (table.shapes, ids, n_el, prm, grid_args(grid), grid.wall_sums, width, height, out)
        in_blocks(_walls_kernel, ids.shape[0], *args)
    return out


@njit(cache=True, nogil=True)
def _walls_kernel(
    first, last, shapes, ids, n_el, params, grid, sums, width, height, out
):  # pragma: no cover - compiled
    n_parts, n_vertices, unit = shapes[0], shapes[1], shapes[2]
    cell, rows, cols, base = grid[0], grid[1], grid[2], grid[7]
    wv = np.empty((1, unit.shape[1], unit.shape[2], 2))
    pbox = np.empty((1, unit.shape[1], 4))
    ebox = np.empty((1, 4))
    marked = np.zeros_like(base)
    for i in range(first, last):
        for k in range(n_el[i]):
            e = ids[i, k]
            world_element(shapes, e, params[i, k], wv, pbox, ebox, 0)
            if ebox[0, 0] < 0.0 or ebox[0, 1] < 0.0 or ebox[0, 2] > width or ebox[0, 3] > height:
                continue  # outside the rectangle: counted as such
            r0, r1 = max(math.floor(ebox[0, 1] / cell), 0), min(math.floor(ebox[0, 3] / cell), rows - 1)
            c0, c1 = max(math.floor(ebox[0, 0] / cell), 0), min(math.floor(ebox[0, 2] / cell), cols - 1)
            if sums[r1 + 1, c1 + 1] - sums[r0, c1 + 1] - sums[r1 + 1, c0] + sums[r0, c0] == 0:
                continue  # no wall cell under its box: not rasterised
            for p in range(n_parts[e]):
                _mark_part(wv, 0, p, n_vertices[e, p], pbox[0, p], cell, rows, cols, marked)
            touches = False
            for r in range(r0, r1 + 1):
                for w in range(c0 >> 6, (c1 >> 6) + 1):
                    touches |= (marked[r, w] & base[r, w]) != 0
                    marked[r, w] = 0
            out[i, k] = touches
