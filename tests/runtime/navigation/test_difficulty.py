"""Difficulty metrics: each compiled per-cell kernel against a plain reference on random
grids, path cells against their definition, and the score on floors whose answer is known."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from mazegen.runtime import metrics
from mazegen.runtime.geometry._cspace import Grid, unpack
from mazegen.runtime.navigation._difficulty import (
    KING,
    METRICS,
    RAYS16,
    cell_dispersion,
    closest_blocked,
    difficulty_score,
    fill_free_steps,
    path_cells,
    step_arrays,
    survey,
)
from mazegen.runtime.navigation._paths import free_cells, navigate, path_of, paths_of
from mazegen.spec import DIFFICULTY_LEVELS, Arena
from tests.runtime.floors import ARENA, NAMES, ZIGZAG, pack, population, random_floors


def blocked(free: np.ndarray, r: int, c: int) -> bool:
    return not (0 <= r < free.shape[0] and 0 <= c < free.shape[1]) or not free[r, c]


def reference_closest(free: np.ndarray, r: int, c: int) -> float:
    """Squared distance to every blocked cell, and to the ring of cells just outside the grid."""
    rows, cols = free.shape
    best = min((r + 1) ** 2, (rows - r) ** 2, (c + 1) ** 2, (cols - c) ** 2)
    for br, bc in zip(*np.nonzero(~free)):
        best = min(best, (br - r) ** 2 + (bc - c) ** 2)
    return float(best)


def reference_ray(free: np.ndarray, r: int, c: int, dr: int, dc: int) -> float:
    steps = 0
    while not blocked(free, r + (steps + 1) * dr, c + (steps + 1) * dc):
        steps += 1
    return steps * math.hypot(dr, dc)


def reference_dispersion(free: np.ndarray, r: int, c: int, reach: float) -> int:
    hits = []
    for dr, dc in RAYS16:
        k_max = math.floor(reach / math.hypot(dr, dc) + 1e-9)
        hits.append(any(blocked(free, r + k * dr, c + k * dc) for k in range(1, k_max + 1)))
    return sum(hits[d] != hits[(d + 1) % 16] for d in range(16))


@pytest.mark.parametrize(("rows", "cols", "density"), [(23, 40, 0.2), (31, 150, 0.08), (12, 64, 0.4)])
def test_cell_kernels_equal_plain_references_on_random_grids(rows, cols, density):
    rng = np.random.default_rng(rows * cols)
    arrays = step_arrays(rows, cols)
    fill_free_steps(pack(rng.random((rows, cols)) > 0.5), cols, arrays)  # a previous floor's leftovers
    free = rng.random((rows, cols)) > density
    bits = pack(free)
    assert np.array_equal(unpack(bits, cols), free)
    fill_free_steps(bits, cols, arrays)
    steps = arrays[1]
    for r, c in zip(*np.nonzero(free)):
        assert closest_blocked(arrays, r, c) == reference_closest(free, r, c), (r, c)
        for d, (dr, dc) in enumerate(KING):
            ray = steps[d, r + 1, c + 1] * math.hypot(dr, dc)
            assert ray == pytest.approx(reference_ray(free, r, c, dr, dc)), (r, c, d)
        for reach in (1.0, 3.0, 4.5):
            assert cell_dispersion(bits, steps, r, c, reach, cols) == reference_dispersion(free, r, c, reach)


def on_free_cells(free: np.ndarray, cell: float, x: float, y: float) -> bool:
    """Whether the point lies in (the closure of) some free cell."""
    col, row = x / cell, y / cell
    rows = {math.floor(row), math.ceil(row) - 1}
    cols = {math.floor(col), math.ceil(col) - 1}
    return any(0 <= r < free.shape[0] and 0 <= c < free.shape[1] and free[r, c] for r in rows for c in cols)


def test_paths_stay_on_free_cells_and_path_cells_follow_them():
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    grid = Grid.from_arena(arena)
    floors = random_floors(np.random.default_rng(5), 25, arena)
    pop = population(arena, floors)
    nav = navigate(pop, grid)
    bent = 0
    for i in np.flatnonzero(nav.solvable):
        free = free_cells(pop, grid, i)
        corners = path_of(pop, grid, i)
        assert corners is not None
        assert tuple(corners[0]) == arena.start and tuple(corners[-1]) == arena.goal
        lengths = np.hypot(*np.diff(corners, axis=0).T)
        assert lengths.sum() == pytest.approx(nav.path_length[i])
        for (ax, ay), (bx, by) in itertools.pairwise(corners):
            for u in np.linspace(0, 1, 200):
                assert on_free_cells(free, grid.cell, ax + (bx - ax) * u, ay + (by - ay) * u), i
        out = np.zeros((4 * grid.rows * grid.cols, 2), np.int64)
        count = path_cells(corners, len(corners), pack(free), grid.cell, grid.cols, out)
        cells = out[:count]
        assert all(free[r, c] for r, c in cells)
        assert (np.abs(np.diff(cells, axis=0)).max(axis=1) == 1).all()  # 8-neighbours, no repeats
        assert tuple(cells[0]) == grid.start_cell and tuple(cells[-1]) == grid.goal_cell
        bent += len(corners) > 2
    assert bent >= 3
    assert path_of(pop, grid, int(np.flatnonzero(~nav.solvable)[0])) is None


def test_paths_searched_together_equal_each_searched_alone():
    """One scratch serves every floor (and its corners grow past their first room)."""
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    grid = Grid.from_arena(arena)
    pop = population(arena, random_floors(np.random.default_rng(5), 25, arena))
    everyone = paths_of(pop, grid)
    bent = [i for i, corners in enumerate(everyone) if corners is not None and len(corners) > 2]
    rows = np.array([3, 0, 3, 24, 7, *bent, *bent])  # bent paths outgrow the room straight ones need
    together = paths_of(pop, grid, rows)
    alone = [path_of(pop, grid, int(i)) for i in rows]
    assert [c is None for c in together] == [c is None for c in alone]
    assert len(bent) >= 3 and any(c is None for c in everyone)
    assert all(a is None or np.array_equal(a, b) for a, b in zip(alone, together))
    in_order = paths_of(pop, grid, np.arange(25))
    assert all(a is None or np.array_equal(a, b) for a, b in zip(everyone, in_order))
    assert paths_of(pop, grid, np.empty(0, np.int64)) == []


def test_straight_path_cells_on_an_open_floor():
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    grid = Grid.from_arena(arena)
    free = free_cells(population(arena, [[]]), grid, 0)
    out = np.zeros((4 * grid.rows * grid.cols, 2), np.int64)
    corners = np.array([arena.start, arena.goal], float)
    count = path_cells(corners, 2, pack(free), grid.cell, grid.cols, out)
    cells = out[:count]
    assert tuple(cells[0]) == grid.start_cell and tuple(cells[-1]) == grid.goal_cell
    assert (np.abs(np.diff(cells, axis=0)).max(axis=1) == 1).all()
    # Every cell the segment passes through is listed: at least max(|dr|, |dc|) + 1 of them.
    assert count >= max(
        abs(grid.goal_cell[0] - grid.start_cell[0]), abs(grid.goal_cell[1] - grid.start_cell[1])
    )


def test_survey_agrees_with_navigation_and_marks_unsolvable_floors():
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    floors = random_floors(np.random.default_rng(11), 40, arena)
    pop = population(arena, floors)
    nav = navigate(pop, Grid.from_arena(arena))
    found = survey(pop)
    assert np.array_equal(found.navigation.solvable, nav.solvable)
    assert np.allclose(found.navigation.path_length, nav.path_length, equal_nan=True)
    assert np.array_equal(found.navigation.coverage, nav.coverage)
    assert np.isnan(found.table[~nav.solvable]).all()
    solved = found.table[nav.solvable]
    assert np.isfinite(solved).all()
    assert (found.metric("path_ratio")[nav.solvable] >= 1.0).all()
    assert (found.metric("dispersion")[nav.solvable] <= 16).all()
    difficulty = found.difficulty[nav.solvable]
    assert ((difficulty >= 0) & (difficulty <= 100)).all()


def test_open_floor_is_easy_and_straight():
    found = survey(population(ARENA, [[]]))
    row = dict(zip(METRICS, found.table[0]))
    assert row["tortuosity"] == pytest.approx(1.0) and row["path_ratio"] == pytest.approx(1.0)
    assert found.navigation.coverage[0] == 0.0
    assert found.difficulty[0] < DIFFICULTY_LEVELS["easy"][1]
    assert difficulty_score(found.table, ARENA.robot_radius, version=1)[0] < 10


def test_walls_make_a_floor_harder_on_every_metric():
    """Zig-zag walls: a longer, narrower, more broken path than the open floor."""
    found = survey(population(ARENA, [[], ZIGZAG]))
    open_floor, maze = (dict(zip(METRICS, row)) for row in found.table)
    assert maze["tortuosity"] > 1.3 > open_floor["tortuosity"]
    assert maze["clearance"] < open_floor["clearance"]
    assert maze["visibility"] < open_floor["visibility"]
    assert maze["dimension"] < open_floor["dimension"]
    assert maze["dispersion"] > open_floor["dispersion"]
    assert found.difficulty[1] > found.difficulty[0] + 10


def test_path_ratio_counts_the_detour_the_robot_width_forces():
    """A gap 30 wide in a wall: a point goes through, the robot (40 wide) goes round the wall's top."""
    arena = Arena("hall", 1000, 600, "cm", (100, 300), (900, 300), 20, 5)
    walls = [("vwall", 500, 125, 20, 250, 0), ("vwall", 500, 400, 20, 240, 0)]
    found = survey(population(arena, [walls]))
    assert found.navigation.solvable[0]
    robot = found.navigation.path_length[0]
    assert robot > 2 * math.hypot(400, 540 - 300)  # up to y >= 540 and back down
    assert found.metric("path_ratio")[0] == pytest.approx(robot / 800, rel=0.02)


def test_coverage_counts_occupied_cells():
    arena = Arena("hall", 1000, 600, "cm", (50, 50), (950, 550), 20, 10)
    """Cells are half-open squares: x 303..703 meets columns 30..70, y 254..354 rows 25..35."""
    line = ("productionLine", 503, 304, 400, 100, 0)
    nav = navigate(population(arena, [[line]]), Grid.from_arena(arena))
    assert nav.coverage[0] == pytest.approx(41 * 11 / (100 * 60))


def test_closeness_is_one_inside_and_decays_outside():
    values = np.array([1.5, 1.4, 2.0, 2.6, 1.0, np.nan])
    got = metrics.closeness(values, 1.4, 2.0)
    assert got[:3].tolist() == [1.0, 1.0, 1.0]
    assert got[3] == pytest.approx(math.exp(-1.0)) and got[4] == pytest.approx(math.exp(-0.4 / 0.6))
    assert got[5] == 0.0


def test_type_diversity_and_entropy_equal_counting():
    rng = np.random.default_rng(2)
    floors = [
        [(NAMES[t], 100, 100, 50, 50, 0) for t in rng.integers(0, len(NAMES), rng.integers(1, 9))]
        for _ in range(30)
    ]
    pop = population(ARENA, floors)
    for i, elements in enumerate(floors):
        counts = np.unique([name for name, *_ in elements], return_counts=True)[1]
        p = counts / counts.sum()
        assert metrics.distinct_types(pop)[i] == len(counts)
        assert metrics.type_entropy(pop)[i] == pytest.approx(-(p * np.log2(p)).sum() + 0.0)
