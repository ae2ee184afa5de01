"""Solvability without paths: the union-find over runs against a plain breadth-first search,
against the path search, and only when no term reads the path."""

from __future__ import annotations

import numpy as np
import pytest

from mazegen.runtime import metrics
from mazegen.runtime.geometry._cspace import Grid
from mazegen.runtime.navigation._connectivity import component_arrays, connected, reach
from mazegen.runtime.navigation._measures import navigation_of, reach_of
from mazegen.runtime.navigation._paths import navigate
from mazegen.spec import Arena
from tests.runtime.floors import pack, population, random_floors, reachable


def random_grid(rng: np.random.Generator, rows: int, cols: int) -> np.ndarray:
    """Free cells with blocked bars and blots: runs that split, merge and close."""
    free = rng.random((rows, cols)) > rng.uniform(0.05, 0.45)
    for _ in range(rng.integers(0, 6)):
        r, c = rng.integers(0, rows), rng.integers(0, cols)
        if rng.random() < 0.5:
            free[r, c : c + rng.integers(3, cols)] = False
        else:
            free[r : r + rng.integers(3, rows), c] = False
    return free


@pytest.mark.parametrize(("rows", "cols"), [(12, 20), (30, 70), (9, 130)])
def test_connected_equals_a_breadth_first_search_on_random_grids(rows, cols):
    rng = np.random.default_rng(rows * cols)
    runs, parent = component_arrays(rows, cols)
    answers = []
    for _ in range(300):
        free = random_grid(rng, rows, cols)
        start = (int(rng.integers(0, rows)), int(rng.integers(0, cols)))
        goal = (int(rng.integers(0, rows)), int(rng.integers(0, cols)))
        cells = np.array([*start, *goal], np.int64)
        expected = reachable(free, start, goal)
        assert connected(pack(free), cols, cells, runs, parent) == expected, (free, start, goal)
        answers.append(expected)
    assert 30 < sum(answers) < 270  # both outcomes, often


def test_reach_equals_the_path_search_on_random_floors():
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    grid = Grid.from_arena(arena)
    pop = population(arena, random_floors(np.random.default_rng(5), 200, arena))
    found, nav = reach(pop, grid), navigate(pop, grid)
    assert np.array_equal(found.solvable, nav.solvable)
    assert np.array_equal(found.coverage, nav.coverage)
    assert 0 < found.solvable.sum() < pop.size


def test_solvability_alone_searches_no_path_and_a_searched_path_is_reused():
    arena = Arena("hall", 800, 500, "cm", (40, 40), (760, 460), 25, 10)
    floors = random_floors(np.random.default_rng(6), 20, arena)
    alone = population(arena, floors)
    unsolvable = metrics.unsolvable(alone)
    assert "navigation" not in alone.measured  # no path searched for a term that reads none
    searched = population(arena, floors)
    lengths = metrics.path_length(searched)
    assert reach_of(searched).solvable is navigation_of(searched).solvable  # not found twice
    assert np.array_equal(unsolvable, (~reach_of(searched).solvable).astype(float))
    assert np.array_equal(np.isnan(lengths), unsolvable > 0)
