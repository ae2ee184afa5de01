"""Metric kernels over a decoded :class:`Population`: the building blocks of fitness terms.

Each function returns one float64 value per individual; invalid individuals
(no elements) score zero on every metric. The drive measures (``drive_*``) are NaN where an
individual is not driven or its floor has no path.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from mazegen.errors import MazeError
from mazegen.metric_plugins import metric_function
from mazegen.runtime import simulation
from mazegen.runtime.engine import SX, SY, Population
from mazegen.runtime.geometry import ZoneArrays, elements_off_zones, elements_on_walls, grid_of
from mazegen.runtime.geometry import elements_outside as elements_outside_of
from mazegen.runtime.geometry import overlapping_pairs as overlapping_pairs_of
from mazegen.runtime.navigation import (
    class_counts_of,
    navigation_of,
    reach_of,
    reachable_of,
    survey_of,
    task_views,
)
from mazegen.runtime.plugin_view import Floors
from mazegen.spec import Robot, Task, robot_for

if TYPE_CHECKING:
    from mazegen.runtime.simulation import Episodes


def element_count(pop: Population) -> np.ndarray:
    """Number of elements (paper eq. 1)."""
    return pop.n_elements.astype(np.float64)


def overlapping_pairs(pop: Population) -> np.ndarray:
    """Pairs of elements whose interiors intersect (paper eq. 2's N_overlapped)."""
    return overlapping_pairs_of(pop.table, pop.element_ids, pop.n_elements, pop.params).astype(np.float64)


def elements_over_size(pop: Population, limit: float) -> np.ndarray:
    """Elements whose size, their longest side, exceeds ``limit`` (paper v1.5)."""
    return _count_over_size(pop.params, pop.n_elements, float(limit))


@njit(cache=True)
def _count_over_size(params, n_elements, limit):  # pragma: no cover - compiled
    out = np.zeros(n_elements.shape[0])
    for i in range(n_elements.shape[0]):
        for k in range(n_elements[i]):
            out[i] += max(params[i, k, SX], params[i, k, SY]) > limit
    return out


def elements_outside(pop: Population) -> np.ndarray:
    """Elements not wholly inside the arena: outside its rectangle, on its base map's walls, or where
    its zones do not let them stand."""
    arena = pop.arena
    arrays = (pop.table, pop.element_ids, pop.n_elements, pop.params)
    size = (arena.width, arena.height)
    outside = elements_outside_of(*arrays, *size).astype(np.float64)
    if arena.base is None and not arena.zones:
        return outside
    misplaced = np.zeros(pop.element_ids.shape, bool)  # inside the rectangle, where they may not stand
    if arena.base is not None:
        misplaced |= elements_on_walls(*arrays, grid_of(arena), size)
    if arena.zones:
        zones = ZoneArrays.of(arena.zones, pop.table.names)
        misplaced |= elements_off_zones(*arrays, zones, size)
    return outside + misplaced.sum(axis=1)


def unsolvable(pop: Population) -> np.ndarray:
    """The share of its tasks a valid scenario has no path for, for the robot: 1 or 0 for one task."""
    views = task_views(pop)
    unsolved = sum((pop.valid & ~reach_of(view).solvable).astype(np.float64) for view in views)
    return np.asarray(unsolved / len(views), dtype=np.float64)


def path_length(pop: Population) -> np.ndarray:
    """Length of the robot's path from start to goal in arena units (the tasks' mean), NaN when there
    is none."""
    return navigation_of(pop).path_length


def tortuosity(pop: Population) -> np.ndarray:
    """Path length over the straight-line distance from start to goal (1 = straight; the tasks' mean),
    NaN when unsolvable."""
    ratios = [nav.path_length / nav.straight for nav in (navigation_of(view) for view in task_views(pop))]
    return np.mean(np.stack(ratios), axis=0)


def difficulty(pop: Population) -> np.ndarray:
    """Difficulty score, 0 (open) to 100 (hard), the tasks' mean, NaN when unsolvable (see
    :mod:`difficulty`)."""
    return survey_of(pop).difficulty


def path_metric(pop: Population, name: str) -> np.ndarray:
    """One difficulty metric of the robot's path (``tortuosity``, ``clearance``…), the tasks' mean, NaN
    when unsolvable."""
    return survey_of(pop).metric(name)


def task_values(pop: Population, name: str) -> np.ndarray:
    """``float64[tasks, N]``: the difficulty (``name`` ``difficulty``) or a path metric of each task of
    every individual, NaN where the task is unsolvable."""
    surveys = [survey_of(view) for view in task_views(pop)]
    return np.stack([s.difficulty if name == "difficulty" else s.metric(name) for s in surveys])


def task_closeness(values: np.ndarray, low: float, high: float, how: str) -> np.ndarray:
    """:func:`closeness` of each task's ``values`` (``float64[tasks, N]``) to ``[low, high]``, the
    worst task's (``worst``) or their mean (``all``); ``mean`` scores the tasks' mean value."""
    if how == "mean":
        return closeness(np.mean(values, axis=0), low, high)
    scores = closeness(values, low, high)
    return scores.min(axis=0) if how == "worst" else scores.mean(axis=0)


def travel(pop: Population, measure: str) -> np.ndarray:
    """How directly the robot travels its tasks, 0..1: the tasks' straight distances over their path
    lengths, summed (``total``), or the least of a task's (``worst``); 0 where a task has no path."""
    navigations = [navigation_of(view) for view in task_views(pop)]
    lengths = np.stack([nav.path_length for nav in navigations])
    straight = np.array([nav.straight for nav in navigations])[:, None]
    ratio = straight.sum() / lengths.sum(axis=0) if measure == "total" else (straight / lengths).min(axis=0)
    return np.nan_to_num(ratio, nan=0.0)


def travel_length(pop: Population, measure: str) -> np.ndarray:
    """The tasks' path lengths summed (``total``) or the longest (``worst``), arena units; NaN where a
    task has no path."""
    lengths = np.stack([navigation_of(view).path_length for view in task_views(pop)])
    return lengths.sum(axis=0) if measure == "total" else lengths.max(axis=0)


def reachable(pop: Population) -> np.ndarray:
    """The share of the floor's free cells the robot can reach from its start (1: no closed pocket)."""
    return reachable_of(pop)


def coverage(pop: Population) -> np.ndarray:
    """Fraction of the arena's grid cells the elements occupy."""
    return reach_of(pop).coverage


def classes(pop: Population, exactly: int | None = None) -> np.ndarray:
    """The number of homotopy classes of each floor's way from start to goal (docs/classes.md: at most
    :data:`~mazegen.spec.MAX_CLASSES`, none longer than :data:`~mazegen.spec.DETOUR` times the shortest;
    the tasks' mean on a floor of several; 0 without a path), or with ``exactly`` its closeness to that
    many: ``exp(-|classes - exactly|)``."""
    counts = class_counts_of(pop)
    return counts if exactly is None else np.exp(-np.abs(counts - exactly))


def closeness(values: np.ndarray, low: float, high: float) -> np.ndarray:
    """1 inside ``[low, high]``, ``exp(-d / (high - low))`` at distance ``d`` outside, 0 for NaN."""
    distance = np.maximum(low - values, 0.0) + np.maximum(values - high, 0.0)
    return np.nan_to_num(np.exp(-distance / (high - low)), nan=0.0)


def distinct_types(pop: Population) -> np.ndarray:
    """Number of distinct element types in each scenario."""
    return _type_counts(pop.element_ids, pop.n_elements, pop.table.n_parts.shape[0])[0]


def type_entropy(pop: Population) -> np.ndarray:
    """Shannon entropy, in bits, of the element types of each scenario (0 for one type)."""
    return _type_counts(pop.element_ids, pop.n_elements, pop.table.n_parts.shape[0])[1]


@njit(cache=True)
def _type_counts(ids, n_elements, n_types):  # pragma: no cover - compiled
    distinct = np.zeros(ids.shape[0])
    entropy = np.zeros(ids.shape[0])
    counts = np.zeros(n_types, np.int64)
    for i in range(ids.shape[0]):
        counts[:] = 0
        n = n_elements[i]
        for k in range(n):
            counts[ids[i, k]] += 1
        for t in range(n_types):
            if counts[t]:
                distinct[i] += 1
                p = counts[t] / n
                entropy[i] -= p * np.log2(p)
    return distinct, entropy


def drive_selection(
    pop: Population, scores: dict[str, np.ndarray], rejected: np.ndarray, fraction: float
) -> np.ndarray:
    """Which individuals to drive: in a search (:attr:`Population.searching`), the best ``fraction`` of
    the population by the sum of the (static) ``scores``, ⌈fraction × size⌉ at most, among the valid
    ones not ``rejected``; every one of those for a fraction of 1, or outside a search (written
    scenarios carry their whole fitness). Ties keep index order; the indices ascend."""
    kept = np.flatnonzero(pop.valid & ~np.asarray(rejected, dtype=bool))
    if fraction >= 1 or not pop.searching:
        return kept
    total = np.zeros(pop.size)
    for values in scores.values():
        total += values
    best = np.argsort(-total[kept], kind="stable")[: min(kept.size, math.ceil(fraction * pop.size))]
    return np.sort(kept[best])


def _robot(pop: Population) -> Robot:
    return pop.robot if pop.robot is not None else robot_for(pop.arena)


def episodes_of(pop: Population, controller: str, driven: np.ndarray, task: Task | None = None) -> Episodes:
    """The episodes of ``controller`` on the ``driven`` individuals (for one of the floor's tasks, ``pop``
    its view, starting at its heading): driven once per population, however many terms read them
    (kept in the population's ``measured``)."""
    key = f"drive {controller}"
    kept = pop.measured.get(key)
    if kept is None or not np.array_equal(kept[0], driven):
        robot = _robot(pop)
        starts = None if task is None else task.start_poses(driven.size)
        episodes = simulation.drive(
            pop, robot=robot, controller=robot.controller(controller), indices=driven, starts=starts
        )
        kept = pop.measured[key] = (driven.copy(), episodes)
    return kept[1]


def _spread(pop: Population, driven: np.ndarray, values: np.ndarray, episodes: Episodes) -> np.ndarray:
    """``values`` of the driven floors in the population's rows, NaN elsewhere and where no path exists."""
    out = np.full(pop.size, np.nan)
    out[driven] = np.where(np.isfinite(episodes.optimal_time), values, np.nan)
    return out


def _over_tasks(
    pop: Population, measure: Callable[[Population, Task | None], np.ndarray], *, worst: bool = False
) -> np.ndarray:
    """``measure`` of each task's episodes (its view, :func:`task_views`, and the task), their mean or,
    with ``worst``, their least: a floor of several tasks drives each."""
    tasks = pop.arena.tasks or (None,)
    values = np.stack([measure(view, task) for task, view in zip(tasks, task_views(pop))])
    return values.min(axis=0) if worst else values.mean(axis=0)


def drive_fails(pop: Population, controller: str, driven: np.ndarray) -> np.ndarray:
    """1 where ``controller``'s robot collides or times out, 0 where it arrives (the share of the tasks
    that fail)."""

    def fails(view: Population, task: Task | None) -> np.ndarray:
        episodes = episodes_of(view, controller, driven, task)
        return _spread(view, driven, episodes.failed.astype(np.float64), episodes)

    return _over_tasks(pop, fails)


def drive_time(pop: Population, controller: str, driven: np.ndarray) -> np.ndarray:
    """Time to the goal over the optimal time (BARN's AT / OT; the tasks' mean); a failure counts as the
    robot's timeout factor, the most an episode may last."""

    def time(view: Population, task: Task | None) -> np.ndarray:
        episodes = episodes_of(view, controller, driven, task)
        return _spread(view, driven, episodes.time_ratio(_robot(view).timeout), episodes)

    return _over_tasks(pop, time)


def drive_clearance(pop: Population, controller: str, driven: np.ndarray) -> np.ndarray:
    """The closest approach of the robot's edge to an obstacle or the arena wall, arena units (on any
    task)."""

    def clearance(view: Population, task: Task | None) -> np.ndarray:
        episodes = episodes_of(view, controller, driven, task)
        return _spread(view, driven, episodes.clearance, episodes)

    return _over_tasks(pop, clearance, worst=True)


def drive_disagree(pop: Population, first: str, second: str, driven: np.ndarray) -> np.ndarray:
    """1 where one controller arrives and the other fails, 0 where they fare alike (the share of the
    tasks where they differ)."""

    def disagree(view: Population, task: Task | None) -> np.ndarray:
        one, other = episodes_of(view, first, driven, task), episodes_of(view, second, driven, task)
        return _spread(view, driven, (one.failed != other.failed).astype(np.float64), one)

    return _over_tasks(pop, disagree)


def plugin_metric(
    pop: Population,
    name: str,
    arguments: dict[str, float],
    *,
    source: str | None,
    package: str | None,
    types: tuple[str, ...],
    where: str,
) -> np.ndarray:
    """A user's metric (a ``metric`` term's plug-in, :mod:`mazegen.metric_plugins`) of every floor:
    one finite value per valid floor, 0 for the invalid ones.

    Raises:
        MazeError: located at the term (``where``, ``file:line:col``) and naming the plug-in, when it
            cannot be loaded, raises, or returns anything but one finite number per floor.
    """
    filename, line, col = where.rsplit(":", 2)

    def failed(problem: str) -> MazeError:
        return MazeError(f"metric {name!r}: {problem}", filename=filename, line=int(line), col=int(col))

    try:
        function = metric_function(name, source, package)
    except MazeError as error:
        raise failed(str(error).removeprefix(f"metric {name!r}: ")) from error
    try:
        values = function(Floors(pop, types), **arguments)
    except MazeError:
        raise
    except (Exception, SystemExit) as error:  # the plug-in's own failure, in one line
        raise failed(f"the plug-in raised {type(error).__name__}: {error}") from error
    wanted = f"the plug-in must return one number per floor, float64[{pop.size}]"
    try:
        array = np.asarray(values)
    except (ValueError, TypeError) as error:  # a ragged list, say
        raise failed(f"{wanted}, got a {type(values).__name__} that is no array") from error
    if array.shape != (pop.size,) or array.dtype.kind not in "biuf":
        raise failed(f"{wanted}, got {array.dtype}{list(array.shape)}")
    out = np.where(pop.valid, array.astype(np.float64), 0.0)
    bad = np.flatnonzero(~np.isfinite(out))
    if bad.size:
        raise failed(f"the plug-in returned {out[bad[0]]} for floor {int(bad[0])} (a value must be finite)")
    return out
