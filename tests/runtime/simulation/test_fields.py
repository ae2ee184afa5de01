"""The navigation function and the clearance field against plain references: a brute-force
distance transform, a heapq Dijkstra over the same free cells, and shapely's exact distances."""

from __future__ import annotations

import heapq
import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from mazegen.runtime.geometry._cspace import grid_of
from mazegen.runtime.geometry._elements import world_parts
from mazegen.runtime.navigation._paths import free_cells
from mazegen.runtime.simulation._fields import CLEAR_ERROR, clearance, field_scratch, floor_fields
from tests.runtime.floors import ARENA, TABLE, ZIGZAG, pack, population, random_floors


def brute_clearance(occupied: np.ndarray, cell: float, width: float, height: float) -> np.ndarray:
    """Distance from each cell centre to the nearest occupied cell centre or the arena's edge."""
    rows, cols = occupied.shape
    ys, xs = (np.arange(rows) + 0.5) * cell, (np.arange(cols) + 0.5) * cell
    out = np.minimum(
        np.minimum(ys[:, None], height - ys[:, None]), np.minimum(xs[None, :], width - xs[None, :])
    ).clip(0)
    for r, c in zip(*np.nonzero(occupied)):
        out = np.minimum(out, np.hypot(ys[:, None] - ys[r], xs[None, :] - xs[c]))
    return out


def heap_dijkstra(free: np.ndarray, goal_cell: tuple[int, int], goal: tuple[float, float], cell: float):
    """8-connected Dijkstra over ``free`` (a diagonal step needs both cells beside it free)."""
    rows, cols = free.shape
    out = np.full(free.shape, np.inf)
    gr, gc = goal_cell
    if not free[gr, gc]:
        return out
    queue = [(math.hypot((gc + 0.5) * cell - goal[0], (gr + 0.5) * cell - goal[1]), gr, gc)]
    while queue:
        d, r, c = heapq.heappop(queue)
        if out[r, c] <= d:
            continue
        out[r, c] = d
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (dr, dc) == (0, 0) or not (0 <= nr < rows and 0 <= nc < cols) or not free[nr, nc]:
                    continue
                if dr and dc and not (free[r, nc] and free[nr, c]):
                    continue
                heapq.heappush(queue, (d + cell * math.hypot(dr, dc), nr, nc))
    return out


def test_clearance_is_the_exact_distance_transform_of_the_raster():
    rng = np.random.default_rng(3)
    for rows, cols, density in ((1, 1, 0.5), (7, 70, 0.05), (40, 23, 0.01), (16, 16, 0.0), (9, 130, 0.3)):
        occupied = rng.random((rows, cols)) < density
        cell, width, height = 0.7, cols * 0.7 - 0.2, rows * 0.7
        out = np.empty((rows, cols), np.float32)
        clearance(pack(occupied), cell, np.array([width, height]), out, field_scratch(rows, cols))
        expected = brute_clearance(occupied, cell, width, height)
        np.testing.assert_allclose(out, expected, rtol=1e-6, atol=1e-5)


def test_navigation_matches_a_plain_dijkstra_on_random_floors():
    rng = np.random.default_rng(11)
    floors = [*random_floors(rng, 12, ARENA), ZIGZAG]
    pop = population(ARENA, floors)
    grid = grid_of(ARENA)
    nav, _, cells = floor_fields(pop, None, np.arange(len(floors)))
    assert cells.tolist() == [0.0, 0.0, grid.cell, grid.rows, grid.cols]
    reached = 0
    for i in range(len(floors)):
        expected = heap_dijkstra(free_cells(pop, grid, i), grid.goal_cell, grid.goal, grid.cell)
        np.testing.assert_allclose(nav[i], expected, rtol=1e-6)
        reached += np.isfinite(nav[i][grid.start_cell])
    assert reached >= 3  # the floors are not all cut in two


def test_navigation_goes_around_walls_and_never_beats_the_straight_line():
    pop = population(ARENA, [[], ZIGZAG])
    grid = grid_of(ARENA)
    nav, _, _ = floor_fields(pop, None, None)
    ys, xs = (np.arange(grid.rows) + 0.5) * grid.cell, (np.arange(grid.cols) + 0.5) * grid.cell
    straight = np.hypot(xs[None, :] - grid.goal[0], ys[:, None] - grid.goal[1])
    for field in nav:
        finite = np.isfinite(field)
        assert (field[finite] >= straight[finite] * (1 - 1e-6)).all()
    # An empty floor: within 8-connectivity's 8.3 % of the straight line everywhere inside the border
    # (plus the goal's offset from its cell's centre, half a diagonal, counted on both sides).
    finite = np.isfinite(nav[0])
    assert finite.sum() > 0.8 * finite.size
    bound = (straight + CLEAR_ERROR * grid.cell) * math.sqrt(4 - 2 * math.sqrt(2)) + CLEAR_ERROR * grid.cell
    assert (nav[0][finite] <= bound[finite] * (1 + 1e-6)).all()
    # The zig-zag: from the start the walls force a detour far longer than the straight line.
    assert nav[1][grid.start_cell] > 1.5 * straight[grid.start_cell]


def test_clear_errs_at_most_half_a_cell_diagonal_against_exact_geometry():
    rng = np.random.default_rng(5)
    floors = [*random_floors(rng, 6, ARENA), ZIGZAG]
    pop = population(ARENA, floors)
    grid = grid_of(ARENA)
    _, clear, _ = floor_fields(pop, None, None)
    ys, xs = (np.arange(grid.rows) + 0.5) * grid.cell, (np.arange(grid.cols) + 0.5) * grid.cell
    points = shapely.points(np.repeat(xs[None, :], grid.rows, 0), np.repeat(ys[:, None], grid.cols, 1))
    walls = shapely.box(0, 0, ARENA.width, ARENA.height).exterior
    for i, elements in enumerate(floors):
        parts = [
            Polygon(p)
            for k in range(len(elements))
            for p in world_parts(TABLE, int(pop.element_ids[i, k]), pop.params[i, k])
        ]
        obstacles = shapely.union_all([walls, *parts])
        exact = shapely.distance(points, obstacles)
        error = np.abs(clear[i] - exact)
        assert error.max() <= CLEAR_ERROR * grid.cell + 1e-4, (i, error.max())
