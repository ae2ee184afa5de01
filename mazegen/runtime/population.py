"""Decoded populations: what fitness terms and metrics read.

A :class:`Population` is a few arrays over N individuals with K element slots:
which element types they contain, where, how large and how turned. It is built
from genomes (:func:`decode`) or from scenario files, and the metric kernels of
:mod:`mazegen.runtime.metrics` read it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mazegen.spec import Arena, Spec

if TYPE_CHECKING:
    from mazegen.runtime.geometry import ElementTable
    from mazegen.runtime.mapping import PopulationMap

GENE_MAX = 65535
"""Placement genes are integers 0..GENE_MAX, scaled into each element's ranges."""

PLACEMENT_GENES = 5
"""Genes per element slot: x, y, size (width for rect), depth (rect only), rotation."""

X, Y, SX, SY, THETA = range(5)


@dataclass(frozen=True)
class Population:
    """Decoded scenarios of a population.

    Attributes:
        element_ids: ``int32[N, K]`` element type ids (index in the scenario's list), -1 padding.
        n_elements: ``int32[N]`` number of elements (0 for invalid individuals).
        params: ``float64[N, K, 5]`` x, y, sx, sy and rotation (radians) of each element.
        valid: ``bool[N]`` whether the genome mapped to a complete scenario.
        table: Geometry of the element types.
        arena: The floor the scenarios are placed on.
    """

    element_ids: np.ndarray
    n_elements: np.ndarray
    params: np.ndarray
    valid: np.ndarray
    table: ElementTable
    arena: Arena

    @property
    def size(self) -> int:
        """Number of individuals."""
        return int(self.n_elements.shape[0])


@dataclass(frozen=True)
class Ranges:
    """Per element type ranges, as arrays indexed by element id."""

    size: np.ndarray        # float64[E, 2]
    depth: np.ndarray       # float64[E, 2] (rect) or the size range again
    uniform: np.ndarray     # bool[E]
    aspect: np.ndarray      # float64[E]: depth / width at mid ranges (grammar placement of rects)
    rot_lo: np.ndarray      # float64[E] degrees (continuous)
    rot_hi: np.ndarray
    rot_free: np.ndarray    # bool[E] continuous rotation
    rotations: np.ndarray   # float64[E, R] discrete angles, padded by repetition
    n_rotations: np.ndarray  # int32[E]

    @classmethod
    def from_spec(cls, spec: Spec) -> Ranges:
        """Gather the ranges of the scenario's element types."""
        types = spec.scenario_elements
        width = max(len(t.rotations) for t in types)
        rotations = np.array([list(t.rotations) + [t.rotations[0]] * (width - len(t.rotations))
                              for t in types], dtype=np.float64)
        size = np.array([t.size for t in types], dtype=np.float64)
        depth = np.array([t.size2 or t.size for t in types], dtype=np.float64)
        return cls(
            size=size,
            depth=depth,
            uniform=np.array([t.uniform for t in types]),
            aspect=depth.mean(axis=1) / size.mean(axis=1),
            rot_lo=np.array([(t.rotation_range or (0.0, 0.0))[0] for t in types]),
            rot_hi=np.array([(t.rotation_range or (0.0, 0.0))[1] for t in types]),
            rot_free=np.array([t.rotation_range is not None for t in types]),
            rotations=rotations,
            n_rotations=np.array([len(t.rotations) for t in types], dtype=np.int32),
        )


def _scaled(genes: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return lo + (hi - lo) * (genes.astype(np.float64) / GENE_MAX)


def placement_params(mapped: PopulationMap, genes: np.ndarray, ranges: Ranges, arena: Arena,
                     grammar_scale: float | None) -> np.ndarray:
    """Element parameters from placement genes, or from grammar numbers where present.

    Args:
        mapped: Result of mapping the structure codons.
        genes: ``uint16[N, K, 5]`` placement genes.
        ranges: Element ranges.
        arena: Arena (positions span it).
        grammar_scale: Multiplier of grammar size numbers, or ``None`` for gene placement.
    """
    ids = np.maximum(mapped.element_ids, 0)
    params = np.empty(ids.shape + (PLACEMENT_GENES,), dtype=np.float64)
    params[..., X] = _scaled(genes[..., X], 0.0, arena.width)
    params[..., Y] = _scaled(genes[..., Y], 0.0, arena.height)
    size = ranges.size[ids]
    params[..., SX] = _scaled(genes[..., SX], size[..., 0], size[..., 1])
    depth = ranges.depth[ids]
    uniform = ranges.uniform[ids]
    params[..., SY] = np.where(uniform, params[..., SX], _scaled(genes[..., SY], depth[..., 0], depth[..., 1]))
    free = _scaled(genes[..., THETA], ranges.rot_lo[ids], ranges.rot_hi[ids])
    pick = genes[..., THETA].astype(np.int64) % ranges.n_rotations[ids]
    discrete = np.take_along_axis(ranges.rotations[ids], pick[..., None], axis=-1)[..., 0]
    params[..., THETA] = np.radians(np.where(ranges.rot_free[ids], free, discrete))
    if grammar_scale is not None:
        numbers = mapped.numbers
        has = ~np.isnan(numbers)
        size_from_grammar = numbers[..., 0] * grammar_scale
        params[..., SX] = np.where(has[..., 0], size_from_grammar, params[..., SX])
        params[..., SY] = np.where(has[..., 0], size_from_grammar * np.where(uniform, 1.0, ranges.aspect[ids]),
                                   params[..., SY])
        params[..., X] = np.where(has[..., 1], numbers[..., 1], params[..., X])
        params[..., Y] = np.where(has[..., 2], numbers[..., 2], params[..., Y])
        params[..., THETA] = np.where(has[..., 3], np.radians(np.nan_to_num(numbers[..., 3])), params[..., THETA])
    return params


def decode(mapped: PopulationMap, genes: np.ndarray, ranges: Ranges, table: ElementTable, spec: Spec) -> Population:
    """Turn mapped structure codons plus placement genes into a :class:`Population`."""
    placement = spec.scenario.placement
    params = placement_params(mapped, genes, ranges, spec.arena,
                              None if placement is None else placement.scale)
    return Population(mapped.element_ids, mapped.n_elements, params, mapped.valid, table, spec.arena)
