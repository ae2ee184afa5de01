"""Decoded populations: what fitness terms and metrics read.

A :class:`Population` is a few arrays over N individuals with K element slots:
which element types they contain, where, how large and how turned. It is built
from genomes (:func:`decode`) or from scenario files, and the metric kernels of
:mod:`mazegen.runtime.metrics` read it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, partial
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit

from mazegen.fitness_terms import reads_survey
from mazegen.runtime.threads import in_blocks
from mazegen.spec import Arena, Robot, Spec

if TYPE_CHECKING:
    from mazegen.runtime.engine._mapping import PopulationMap
    from mazegen.runtime.geometry import ElementTable

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
        placement: Computes :attr:`params`, once, when a metric first reads them
            (a fitness of counts alone never places anything).
        valid: ``bool[N]`` whether the genome mapped to a complete scenario.
        table: Geometry of the element types.
        arena: The floor the scenarios are placed on.
        surveyed: The fitness reads difficulty metrics: search paths once, with them.
        robot: The robot the spec drives through the floors (None: it drives none).
        searching: Scored by a search (an evolution, a suite), whose drive terms drive only the
            robot's ``driven`` fraction of it; otherwise (scenario documents, ``score``) every
            individual kept is driven, so that a written scenario carries its whole fitness.
        measured: What the layers above find from the population (its navigation, say), kept
            with it so that each is found once (see :mod:`mazegen.runtime.navigation._measures`).
    """

    element_ids: np.ndarray
    n_elements: np.ndarray
    placement: Callable[[], np.ndarray]
    valid: np.ndarray
    table: ElementTable
    arena: Arena
    surveyed: bool = False
    robot: Robot | None = None
    searching: bool = False
    measured: dict[str, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    @cached_property
    def params(self) -> np.ndarray:
        """``float64[N, K, 5]`` x, y, sx, sy and rotation (radians) of each element, 0 past the last."""
        return self.placement()

    @property
    def size(self) -> int:
        """Number of individuals."""
        return int(self.n_elements.shape[0])


@dataclass(frozen=True)
class Ranges:
    """Per element type ranges, as arrays indexed by element id."""

    size: np.ndarray  # float64[E, 2]
    depth: np.ndarray  # float64[E, 2] (rect) or the size range again
    uniform: np.ndarray  # bool[E]
    aspect: np.ndarray  # float64[E]: depth / width at mid ranges (grammar placement of rects)
    rot_lo: np.ndarray  # float64[E] degrees (continuous)
    rot_hi: np.ndarray
    rot_free: np.ndarray  # bool[E] continuous rotation
    rotations: np.ndarray  # float64[E, R] discrete angles, padded by repetition
    n_rotations: np.ndarray  # int32[E]
    area: np.ndarray  # float64[E, 4]: (x, y) low and high of positions, the arena or the zones holding it

    @classmethod
    def from_spec(cls, spec: Spec) -> Ranges:
        """Gather the ranges of the scenario's element types."""
        types = spec.scenario_elements
        width = max(len(t.rotations) for t in types)
        rotations = np.array(
            [list(t.rotations) + [t.rotations[0]] * (width - len(t.rotations)) for t in types],
            dtype=np.float64,
        )
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
            area=np.array([_area(spec.arena, t.name) for t in types], dtype=np.float64),
        )


def _area(arena: Arena, name: str) -> tuple[float, float, float, float]:
    """Where elements of type ``name`` are placed: the bounding box of the zones that hold them, or the
    whole arena (positions drawn elsewhere could only be rejected)."""
    corners = [
        point for zone in arena.zones if name in zone.types and zone.rule == "holds" for point in zone.outline
    ]
    if not corners:
        return (0.0, 0.0, arena.width, arena.height)
    xs, ys = [x for x, _ in corners], [y for _, y in corners]
    return (min(xs), min(ys), max(xs), max(ys))


@njit(cache=True, nogil=True)
def _placement_kernel(
    first,
    last,
    ids,
    n_elements,
    genes,
    numbers,
    size,
    depth,
    uniform,
    aspect,
    rot_lo,
    rot_hi,
    rot_free,
    rotations,
    n_rotations,
    area,
    grammar_scale,
    out,
):  # pragma: no cover
    for i in range(first, last):
        for k in range(n_elements[i]):
            e = ids[i, k]
            g = genes[i, k]
            x = area[e, 0] + (area[e, 2] - area[e, 0]) * (g[0] / GENE_MAX)
            y = area[e, 1] + (area[e, 3] - area[e, 1]) * (g[1] / GENE_MAX)
            sx = size[e, 0] + (size[e, 1] - size[e, 0]) * (g[2] / GENE_MAX)
            sy = sx if uniform[e] else depth[e, 0] + (depth[e, 1] - depth[e, 0]) * (g[3] / GENE_MAX)
            if rot_free[e]:
                angle = rot_lo[e] + (rot_hi[e] - rot_lo[e]) * (g[4] / GENE_MAX)
            else:
                angle = rotations[e, g[4] % n_rotations[e]]
            if grammar_scale > 0.0:
                nums = numbers[i, k]
                if not np.isnan(nums[0]):
                    sx = nums[0] * grammar_scale
                    sy = sx if uniform[e] else sx * aspect[e]
                if not np.isnan(nums[1]):
                    x = nums[1]
                if not np.isnan(nums[2]):
                    y = nums[2]
                if not np.isnan(nums[3]):
                    angle = nums[3]
            out[i, k, 0] = x
            out[i, k, 1] = y
            out[i, k, 2] = sx
            out[i, k, 3] = sy
            out[i, k, 4] = np.radians(angle)
        out[i, n_elements[i] :] = 0.0


def placement_params(
    mapped: PopulationMap,
    genes: np.ndarray,
    ranges: Ranges,
    grammar_scale: float | None,
    out: np.ndarray | None = None,
) -> np.ndarray:
    """Element parameters from placement genes, or from grammar numbers where present.

    Slots past an individual's element count are zero.

    Args:
        mapped: Result of mapping the structure codons.
        genes: ``uint16[N, K, 5]`` placement genes.
        ranges: Element ranges (positions span each type's :attr:`Ranges.area`).
        grammar_scale: Multiplier of grammar size numbers, or ``None`` for gene placement.
        out: A C-contiguous ``float64[N, K, 5]`` array to overwrite instead of a new one.
    """
    shape = (*mapped.element_ids.shape, PLACEMENT_GENES)
    params = np.empty(shape, dtype=np.float64) if out is None else out
    if params.shape != shape or params.dtype != np.float64 or not params.flags.c_contiguous:
        raise ValueError("out does not fit the population")
    in_blocks(
        _placement_kernel,
        shape[0],
        mapped.element_ids,
        mapped.n_elements,
        genes,
        mapped.numbers,
        ranges.size,
        ranges.depth,
        ranges.uniform,
        ranges.aspect,
        ranges.rot_lo,
        ranges.rot_hi,
        ranges.rot_free,
        ranges.rotations,
        ranges.n_rotations,
        ranges.area,
        -1.0 if grammar_scale is None else float(grammar_scale),
        params,
    )
    return params


def decode(
    mapped: PopulationMap,
    genes: np.ndarray,
    ranges: Ranges,
    table: ElementTable,
    spec: Spec,
    out: np.ndarray | None = None,
    *,
    searching: bool = False,
) -> Population:
    """Turn mapped structure codons plus placement genes into a :class:`Population`.

    Placements are decoded when first read; ``out`` is as in :func:`placement_params`.
    """
    grammar = spec.scenario.placement
    scale = None if grammar is None else grammar.scale
    placement = partial(placement_params, mapped, genes, ranges, scale, out)
    return Population(
        mapped.element_ids,
        mapped.n_elements,
        placement,
        mapped.valid,
        table,
        spec.arena,
        reads_survey(spec),
        spec.robot,
        searching,
    )
