"""A population's class counts in one compiled call (the suite's measure and the ``classes`` fitness
term) are the counts of the classes ``floor_topology`` names floor by floor."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mazegen.runtime import metrics
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.navigation import class_counts, floor_topology, task_views
from mazegen.runtime.threads import threads
from mazegen.spec import Task
from tests.runtime.floors import ARENA, ZIGZAG, population, random_floors

BLOCKED = [("vwall", 500, 300, 20, 600, 0)]
TASKS = (Task("across", (50, 50), (950, 550)), Task("back", (950, 300), (50, 300)))
SEVERAL = dataclasses.replace(ARENA, start=TASKS[0].start, goal=TASKS[0].goal, tasks=TASKS)


@pytest.fixture(scope="module")
def floors() -> list[list[tuple]]:
    return [*random_floors(np.random.default_rng(11), 24, ARENA), ZIGZAG, BLOCKED, []]


def test_the_counts_are_those_of_the_classes_named_floor_by_floor(floors):
    pop = population(ARENA, floors)
    grid = grid_of(ARENA)
    named = [len(floor_topology(pop, grid, i).classes) for i in range(pop.size)]
    counts = class_counts(pop, grid)
    assert counts.tolist() == named
    assert counts[-2] == 0 and counts[-1] == 1  # a wall across: no way; an open floor: one
    assert len(set(named)) >= 4  # the random floors are not all alike
    for limit in (1, 3):
        assert class_counts(pop, grid, max_classes=limit).tolist() == [min(n, limit) for n in named]


def test_the_counts_do_not_depend_on_the_threads(floors):
    pop = population(ARENA, floors)
    with threads(1):
        one = class_counts(pop, grid_of(ARENA))
    with threads(2):
        two = class_counts(pop, grid_of(ARENA))
    assert np.array_equal(one, two)


def test_the_fitness_term_reads_the_tasks_mean_count_or_its_closeness(floors):
    pop = population(SEVERAL, floors[:12])
    per_task = [class_counts(view, grid_of(view.arena)) for view in task_views(pop)]
    assert not np.array_equal(*per_task)  # the two tasks see the floors differently
    expected = np.mean(per_task, axis=0)
    assert np.array_equal(metrics.classes(pop), expected)
    assert np.allclose(metrics.classes(pop, 2), np.exp(-np.abs(expected - 2)))
