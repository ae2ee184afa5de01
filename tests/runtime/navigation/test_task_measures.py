"""Floors of several tasks: each task measured as a floor of that task alone, the floor's measures
theirs together, and the fitness's ways of scoring them."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mazegen.runtime import metrics
from mazegen.runtime.navigation import navigation_of, reach_of, survey_of, task_views
from mazegen.spec import Task
from tests.runtime.floors import ARENA, ZIGZAG, population, random_floors

TASKS = (
    Task("a -> b", (50.0, 50.0), (950.0, 550.0)),
    Task("b -> c", (950.0, 550.0), (950.0, 50.0)),
    Task("c -> a", (950.0, 50.0), (50.0, 300.0), 90.0, None),
)
SEVERAL = dataclasses.replace(ARENA, start=TASKS[0].start, goal=TASKS[0].goal, tasks=TASKS)
# A wall sealing the corner of the third task's start: that task alone has no path.
SEALED = [("vwall", 880, 60, 20, 140, 0), ("hwall", 930, 140, 140, 20, 0)]


@pytest.fixture(scope="module")
def floors() -> list[list[tuple]]:
    return [*random_floors(np.random.default_rng(5), 24, ARENA), ZIGZAG, SEALED, []]


def test_each_task_is_measured_as_a_floor_of_that_task_alone(floors):
    several = population(SEVERAL, floors)
    views = task_views(several)
    assert [view.arena for view in views] == [SEVERAL.for_task(task) for task in TASKS]
    alone = [survey_of(population(SEVERAL.for_task(task), floors)) for task in TASKS]
    for view, one in zip(views, alone):
        found = survey_of(view)
        np.testing.assert_array_equal(found.navigation.solvable, one.navigation.solvable)
        np.testing.assert_array_equal(found.table, one.table)
        np.testing.assert_array_equal(found.difficulty, one.difficulty)
    # The floor's measures are theirs together: solvable where every task is, the rest their mean.
    together = survey_of(several)
    solvable = np.logical_and.reduce([one.navigation.solvable for one in alone])
    np.testing.assert_array_equal(together.navigation.solvable, solvable)
    np.testing.assert_array_equal(reach_of(several).solvable, solvable)
    mean = np.mean([one.difficulty for one in alone], axis=0)
    np.testing.assert_allclose(together.difficulty, mean, equal_nan=True)
    np.testing.assert_allclose(
        navigation_of(several).path_length, np.mean([one.navigation.path_length for one in alone], axis=0)
    )
    sealed = len(floors) - 2
    assert [bool(one.navigation.solvable[sealed]) for one in alone] == [True, False, False]
    assert not together.navigation.solvable[sealed] and np.isnan(together.difficulty[sealed])


def test_unsolvable_is_the_share_of_tasks_without_a_path(floors):
    several = population(SEVERAL, floors)
    alone = [reach_of(population(SEVERAL.for_task(task), floors)).solvable for task in TASKS]
    expected = np.mean([~solvable for solvable in alone], axis=0)
    np.testing.assert_allclose(metrics.unsolvable(several), expected)
    assert metrics.unsolvable(several)[len(floors) - 2] == pytest.approx(2 / 3)
    assert metrics.unsolvable(several)[-1] == 0.0


def test_a_floor_of_one_task_measures_as_before(floors):
    one = population(ARENA, floors)
    assert task_views(one) == (one,)
    np.testing.assert_allclose(metrics.unsolvable(one), (~reach_of(one).solvable).astype(float))


def _closeness(value: float, low: float, high: float) -> float:
    if np.isnan(value):
        return 0.0
    distance = max(low - value, 0.0, value - high)
    return float(np.exp(-distance / (high - low)))


@pytest.mark.parametrize("how", ["mean", "worst", "all"])
def test_task_closeness_scores_the_mean_the_worst_task_or_every_task(floors, how):
    several = population(SEVERAL, floors)
    values = metrics.task_values(several, "difficulty")
    assert values.shape == (3, len(floors))
    low, high = 20.0, 40.0
    found = metrics.task_closeness(values, low, high, how)
    for i in range(len(floors)):
        column = values[:, i]
        if how == "mean":
            expected = _closeness(float(np.mean(column)), low, high)
        else:
            scores = [_closeness(float(v), low, high) for v in column]
            expected = min(scores) if how == "worst" else sum(scores) / len(scores)
        assert found[i] == pytest.approx(expected)
    if how == "mean":
        np.testing.assert_allclose(found, metrics.closeness(metrics.difficulty(several), low, high))


def test_travel_is_how_straight_the_tasks_paths_are_and_its_length_their_sum_or_longest(floors):
    several = population(SEVERAL, floors)
    alone = [navigation_of(population(SEVERAL.for_task(task), floors)) for task in TASKS]
    lengths = np.stack([nav.path_length for nav in alone])
    straight = np.array([nav.straight for nav in alone])
    total = np.nan_to_num(straight.sum() / lengths.sum(axis=0), nan=0.0)
    worst = np.nan_to_num(np.min(straight[:, None] / lengths, axis=0), nan=0.0)
    np.testing.assert_allclose(metrics.travel(several, "total"), total)
    np.testing.assert_allclose(metrics.travel(several, "worst"), worst)
    np.testing.assert_allclose(metrics.travel_length(several, "total"), lengths.sum(axis=0))
    np.testing.assert_allclose(metrics.travel_length(several, "worst"), lengths.max(axis=0))
    assert metrics.travel(several, "total")[-1] == pytest.approx(1.0)  # the empty floor: straight paths
    assert metrics.travel(several, "total")[len(floors) - 2] == 0.0  # a task without a path


def _reference_reachable(free: np.ndarray, start: tuple[int, int]) -> float:
    """The share of ``free`` cells a breadth-first search from ``start`` reaches (edges shared)."""
    if not free[start]:
        return 0.0
    seen = np.zeros_like(free)
    seen[start] = True
    queue = [start]
    while queue:
        r, c = queue.pop()
        for n in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if 0 <= n[0] < free.shape[0] and 0 <= n[1] < free.shape[1] and free[n] and not seen[n]:
                seen[n] = True
                queue.append(n)
    return seen.sum() / free.sum()


def test_reachable_is_the_share_of_free_cells_joined_to_the_start(floors):
    from mazegen.runtime.geometry import grid_of
    from mazegen.runtime.navigation import free_cells

    pocket = [("vwall", 500, 300, 20, 200, 0), ("vwall", 700, 300, 20, 200, 0),
              ("hwall", 600, 200, 220, 20, 0), ("hwall", 600, 400, 220, 20, 0)]  # fmt: skip
    every = [*floors, pocket]
    pop = population(ARENA, every)
    found = metrics.reachable(pop)
    grid = grid_of(ARENA)
    for i in range(len(every)):
        free = free_cells(pop, grid, i)
        assert found[i] == pytest.approx(_reference_reachable(free, grid.start_cell)), i
    assert 0.9 < found[-1] < 1.0 and found[-2] == 1.0  # a closed room, and the empty floor
