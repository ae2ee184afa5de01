"""Metric kernels over a decoded :class:`Population`: the building blocks of fitness terms.

Each function returns one float64 value per individual; invalid individuals
(no elements) score zero on every metric.
"""

from __future__ import annotations

import numpy as np

from mazegen.runtime import geometry
from mazegen.runtime.population import SX, SY, Population


def element_count(pop: Population) -> np.ndarray:
    """Number of elements (paper eq. 1)."""
    return pop.n_elements.astype(np.float64)


def overlapping_pairs(pop: Population) -> np.ndarray:
    """Pairs of elements whose interiors intersect (paper eq. 2's N_overlapped)."""
    return geometry.overlapping_pairs(pop.table, pop.element_ids, pop.n_elements, pop.params).astype(
        np.float64
    )


def element_sizes(pop: Population) -> np.ndarray:
    """``float64[N, K]`` size of each element slot: its longest side, 0 where empty."""
    present = np.arange(pop.params.shape[1]) < pop.n_elements[:, None]
    return np.where(present, np.maximum(pop.params[..., SX], pop.params[..., SY]), 0.0)


def elements_over_size(pop: Population, limit: float) -> np.ndarray:
    """Elements whose size exceeds ``limit`` (paper v1.5)."""
    return (element_sizes(pop) > limit).sum(axis=1).astype(np.float64)


def elements_outside(pop: Population) -> np.ndarray:
    """Elements not wholly inside the arena."""
    arena = pop.arena
    return geometry.elements_outside(
        pop.table, pop.element_ids, pop.n_elements, pop.params, arena.width, arena.height
    ).astype(np.float64)
