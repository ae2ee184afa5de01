"""Metric kernels over a decoded :class:`Population`: the building blocks of fitness terms.

Each function returns one float64 value per individual; invalid individuals
(no elements) score zero on every metric.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from mazegen.runtime.engine.population import SX, SY, Population
from mazegen.runtime.geometry import overlap
from mazegen.runtime.navigation.measures import navigation_of, reach_of, survey_of


def element_count(pop: Population) -> np.ndarray:
    """Number of elements (paper eq. 1)."""
    return pop.n_elements.astype(np.float64)


def overlapping_pairs(pop: Population) -> np.ndarray:
    """Pairs of elements whose interiors intersect (paper eq. 2's N_overlapped)."""
    return overlap.overlapping_pairs(pop.table, pop.element_ids, pop.n_elements, pop.params).astype(
        np.float64
    )


def elements_over_size(pop: Population, limit: float) -> np.ndarray:
    """Elements whose size, their longest side, exceeds ``limit`` (paper v1.5)."""
    return _count_over_size(pop.params, pop.n_elements, float(limit))


@njit(cache=True, parallel=True)
def _count_over_size(params, n_elements, limit):  # pragma: no cover - compiled
    out = np.zeros(n_elements.shape[0])
    for i in prange(n_elements.shape[0]):
        for k in range(n_elements[i]):
            out[i] += max(params[i, k, SX], params[i, k, SY]) > limit
    return out


def elements_outside(pop: Population) -> np.ndarray:
    """Elements not wholly inside the arena."""
    arena = pop.arena
    return overlap.elements_outside(
        pop.table, pop.element_ids, pop.n_elements, pop.params, arena.width, arena.height
    ).astype(np.float64)


def unsolvable(pop: Population) -> np.ndarray:
    """1 where a valid scenario has no path from start to goal for the robot, else 0."""
    return (pop.valid & ~reach_of(pop).solvable).astype(np.float64)


def path_length(pop: Population) -> np.ndarray:
    """Length of the robot's path from start to goal in arena units, NaN when there is none."""
    return navigation_of(pop).path_length


def tortuosity(pop: Population) -> np.ndarray:
    """Path length over the straight-line distance from start to goal (1 = straight), NaN when unsolvable."""
    nav = navigation_of(pop)
    return nav.path_length / nav.straight


def difficulty(pop: Population) -> np.ndarray:
    """Difficulty score, 0 (open) to 100 (hard), NaN when unsolvable (see :mod:`difficulty`)."""
    return survey_of(pop).difficulty


def path_metric(pop: Population, name: str) -> np.ndarray:
    """One difficulty metric of the robot's path (``tortuosity``, ``clearance``…), NaN when unsolvable."""
    return survey_of(pop).metric(name)


def coverage(pop: Population) -> np.ndarray:
    """Fraction of the arena's grid cells the elements occupy."""
    return reach_of(pop).coverage


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


@njit(cache=True, parallel=True)
def _type_counts(ids, n_elements, n_types):  # pragma: no cover - compiled
    distinct = np.zeros(ids.shape[0])
    entropy = np.zeros(ids.shape[0])
    for i in prange(ids.shape[0]):
        counts = np.zeros(n_types, np.int64)
        n = n_elements[i]
        for k in range(n):
            counts[ids[i, k]] += 1
        for t in range(n_types):
            if counts[t]:
                distinct[i] += 1
                p = counts[t] / n
                entropy[i] -= p * np.log2(p)
    return distinct, entropy
