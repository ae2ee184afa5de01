"""A population's navigation measures, each found once, when first asked for.

A fitness that reads several navigation metrics searches the paths once: what is found is
kept in the population's ``measured``, and the population itself knows nothing of navigation.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar, cast

import numpy as np

from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.navigation._connectivity import Reach, reach
from mazegen.runtime.navigation._difficulty import Survey, survey
from mazegen.runtime.navigation._paths import Navigation, navigate, paths_of

Found = TypeVar("Found")


def _once(pop: Population, name: str, find: Callable[[], Found]) -> Found:
    if name not in pop.measured:
        pop.measured[name] = find()
    return cast(Found, pop.measured[name])


def navigation_of(pop: Population) -> Navigation:
    """Solvability and path of every individual, searched on the arena's grid."""
    return _once(
        pop,
        "navigation",
        lambda: survey_of(pop).navigation if pop.surveyed else navigate(pop, grid_of(pop.arena)),
    )


def reach_of(pop: Population) -> Reach:
    """Solvability and coverage of every individual: the navigation's when its paths are searched
    anyway, else found without searching paths."""

    def find() -> Reach:
        if pop.surveyed or "navigation" in pop.measured:  # the paths are (being) searched
            navigation = navigation_of(pop)
            return Reach(navigation.solvable, navigation.coverage)
        return reach(pop, grid_of(pop.arena))

    return _once(pop, "reach", find)


def survey_of(pop: Population) -> Survey:
    """Navigation plus the difficulty metrics of every individual."""
    return _once(pop, "survey", lambda: survey(pop))


def corner_paths_of(pop: Population) -> list[np.ndarray | None]:
    """The corners of every individual's path, start to goal (None: no path), on the arena's grid."""
    return _once(pop, "paths", lambda: paths_of(pop, grid_of(pop.arena)))
