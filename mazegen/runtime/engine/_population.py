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

from mazegen.fitness_terms import reads_survey
from mazegen.runtime.engine._placement import Ranges, placement_params
from mazegen.spec import Arena, Robot, Spec

if TYPE_CHECKING:
    from mazegen.runtime.engine._mapping import PopulationMap
    from mazegen.runtime.geometry import ElementTable


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
        membership: ``int32[N, K, 3]`` of a spec with rows: for each slot, the row it is a member of
            (its index in the scenario's rows, -1 for an element placed alone), its place in that row
            and the row's member count; ``None`` without rows.
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
    membership: np.ndarray | None = None
    measured: dict[str, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    @cached_property
    def params(self) -> np.ndarray:
        """``float64[N, K, 5]`` x, y, sx, sy and rotation (radians) of each element, 0 past the last."""
        return self.placement()

    @property
    def size(self) -> int:
        """Number of individuals."""
        return int(self.n_elements.shape[0])


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
    placement = partial(placement_params, mapped, genes, ranges, table, scale, out)
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
        mapped.membership if mapped.membership.shape[1] else None,
    )
