"""A population's navigation measures, each found once, when first asked for.

A fitness that reads several navigation metrics searches the paths once: what is found is
kept in the population's ``measured``, and the population itself knows nothing of navigation.
A floor of several tasks is measured once per task (:func:`task_views`), and its measures are the
tasks' together: solvable where every task is, the metrics their mean.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import TypeVar, cast

import numpy as np

from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.navigation._class_counts import class_counts
from mazegen.runtime.navigation._connectivity import Reach, reach, reachable
from mazegen.runtime.navigation._difficulty import Survey, survey
from mazegen.runtime.navigation._paths import Navigation, navigate, paths_of

Found = TypeVar("Found")


def _once(pop: Population, name: str, find: Callable[[], Found]) -> Found:
    if name not in pop.measured:
        pop.measured[name] = find()
    return cast(Found, pop.measured[name])


def task_views(pop: Population) -> tuple[Population, ...]:
    """The population once per task of its arena (``Arena.every_task``): the same floors, each view's
    arena with that task alone; ``(pop,)`` for a floor of one task."""
    if not pop.arena.tasks:
        return (pop,)

    def views() -> tuple[Population, ...]:
        placed = lambda: pop.params  # noqa: E731 - the views share the placements, placed once
        return tuple(
            dataclasses.replace(pop, placement=placed, arena=pop.arena.for_task(task))
            for task in pop.arena.tasks
        )

    return _once(pop, "tasks", views)


def navigation_of(pop: Population) -> Navigation:
    """Solvability and path of every individual, searched on the arena's grid."""
    views = task_views(pop)
    if len(views) > 1:
        return _once(pop, "navigation", lambda: Navigation.over_tasks([navigation_of(v) for v in views]))
    return _once(
        pop,
        "navigation",
        lambda: survey_of(pop).navigation if pop.surveyed else navigate(pop, grid_of(pop.arena)),
    )


def reach_of(pop: Population) -> Reach:
    """Solvability and coverage of every individual: the navigation's when its paths are searched
    anyway, else found without searching paths."""

    def find() -> Reach:
        views = task_views(pop)
        if len(views) > 1:
            every = [reach_of(view) for view in views]
            return Reach(np.logical_and.reduce([task.solvable for task in every]), every[0].coverage)
        if pop.surveyed or "navigation" in pop.measured:  # the paths are (being) searched
            navigation = navigation_of(pop)
            return Reach(navigation.solvable, navigation.coverage)
        return reach(pop, grid_of(pop.arena))

    return _once(pop, "reach", find)


def reachable_of(pop: Population) -> np.ndarray:
    """The share of every floor's free cells the robot can reach from its (first task's) start."""
    first = task_views(pop)[0]
    return _once(first, "reachable", lambda: reachable(first, grid_of(first.arena)))


def class_counts_of(pop: Population) -> np.ndarray:
    """``float64[N]``: the number of homotopy classes of every floor (the tasks' mean on a floor of
    several; :func:`~mazegen.runtime.navigation._class_counts.class_counts`)."""

    def counts(view: Population) -> np.ndarray:
        return _once(view, "classes", lambda: class_counts(view, grid_of(view.arena)))

    return np.mean(np.stack([counts(view) for view in task_views(pop)]), axis=0)


def survey_of(pop: Population) -> Survey:
    """Navigation plus the difficulty metrics of every individual."""
    views = task_views(pop)
    if len(views) > 1:
        return _once(pop, "survey", lambda: Survey.over_tasks([survey_of(view) for view in views]))
    return _once(pop, "survey", lambda: survey(pop))


def corner_paths_of(pop: Population) -> list[np.ndarray | None]:
    """The corners of every individual's path, start to goal (None: no path), on the arena's grid: the
    first task's, for a floor of several."""
    first = task_views(pop)[0]
    return _once(first, "paths", lambda: paths_of(first, grid_of(first.arena)))
