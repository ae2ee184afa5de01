"""Crossover and mutation within the used codons, as PonyGE2 defines them (``WITHIN_USED``).

One-point crossover cuts both parents at one point drawn in ``1..min(used)``; variable one-point
crossover (PonyGE2's default) cuts each parent at its own point in ``1..used``, so that in PonyGE2
a child's genome grows or shrinks. Genomes here are rows of a fixed width ``L``: a variable child,
the first parent's head then the second parent's tail, is cut at ``L`` when longer, and when
shorter the positions left over keep the first parent's codons. Those positions lie past the
child's own genome: PonyGE2's child would be invalid (or wrap) where ours reads them, and any
child that maps within its own genome maps exactly as PonyGE2's. A separate length per row would
make every mapping, hash and checkpoint carry it, for children that differ only in that case.

A child keeps whole elements: the element slots its head derived (the elements whose names were
complete once the head's codons were read) take the head parent's placement rows, the next slots
the tail parent's rows from its first element past its cut, spliced as the codons are.

Int-flip mutation within the used codons replaces each of a child's used codons (all of an
invalid child's) with probability ``rate``, and each gene of the placement rows of the child's
elements (every row of an invalid child's). PonyGE2 maps a child before mutating it; so do we.
An individual that is invalid counts its whole genome as used, as in PonyGE2.

Draws are plain NumPy from the run's generator; the kernels are pure functions of arrays.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from numba.np.random.random_methods import buffered_bounded_lemire_uint32 as lemire_uint32

from mazegen.runtime.compiling import inner_kernel
from mazegen.runtime.engine._mapping import PopulationMap
from mazegen.runtime.engine._operators import MutationDraws, codon_type, copy_span, draw_mutation, gap_scale
from mazegen.runtime.engine._placement import PLACEMENT_GENES


@dataclass(frozen=True)
class Usage:
    """How much of each genome its mapping reads.

    Attributes:
        codons: ``int64[N]``: codons used (at most the width ``L``), ``L`` for invalid individuals.
        rows: ``int64[N]``: placement rows of the individual's elements, all ``K`` if invalid.
        element_codons: ``int32[N, K]``: codons read when each element was complete, as
            :attr:`PopulationMap.element_codons`.
    """

    codons: np.ndarray
    rows: np.ndarray
    element_codons: np.ndarray

    @classmethod
    def empty(cls, count: int, slots: int) -> Usage:
        """Room for the usage of ``count`` genomes of ``slots`` element slots, for the ``put`` methods."""
        return cls(np.empty(count, np.int64), np.empty(count, np.int64), np.empty((count, slots), np.int32))

    def put(self, rows: np.ndarray, source: Usage, source_rows: np.ndarray) -> None:
        """Write rows ``source_rows`` of ``source`` into rows ``rows``."""
        _put_rows(rows, source_rows, *source.arrays, *self.arrays)

    def put_mapped(self, rows: np.ndarray, mapped: PopulationMap, length: int) -> None:
        """Write the usage of genomes of width ``length`` (one per row of ``mapped``) into rows ``rows``."""
        arrays = (mapped.valid, mapped.used_codons, mapped.n_elements, mapped.element_codons)
        _put_mapped(rows, *arrays, length, *self.arrays)

    def spread(self, first: np.ndarray) -> None:
        """Copy row ``first[i]`` into each row ``i`` whose ``first[i]`` (an earlier row) differs."""
        _spread(first, *self.arrays)

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The three arrays, in field order (as the compiled copies take them)."""
        return self.codons, self.rows, self.element_codons


def usage_of(mapped: PopulationMap, length: int) -> Usage:
    """The :class:`Usage` of genomes of width ``length`` from their mapping."""
    count, slots = mapped.element_ids.shape
    usage = Usage.empty(count, slots)
    usage.put_mapped(np.arange(count), mapped, length)
    return usage


# Small copies in compiled loops: as NumPy fancy indexing they cost a generation of 1,000 about
# as much as mapping its parents again.
@njit(cache=True)
def _put_rows(
    rows, source_rows, codons, used_rows, elements, out_codons, out_rows, out_elements
):  # pragma: no cover - compiled
    for j in range(rows.shape[0]):
        i, s = rows[j], source_rows[j]
        out_codons[i], out_rows[i] = codons[s], used_rows[s]
        copy_span(elements, s, np.int64(0), out_elements, i, np.int64(0), elements.shape[1])


@njit(cache=True)
def _put_mapped(
    rows, valid, used_codons, n_elements, elements, length, out_codons, out_rows, out_elements
):  # pragma: no cover - compiled
    slots = out_elements.shape[1]
    for j in range(rows.shape[0]):
        i = rows[j]
        if valid[j]:
            out_codons[i], out_rows[i] = min(used_codons[j], length), n_elements[j]
        else:
            out_codons[i], out_rows[i] = length, slots
        copy_span(elements, j, np.int64(0), out_elements, i, np.int64(0), slots)


@njit(cache=True)
def _spread(first, codons, used_rows, elements):  # pragma: no cover - compiled
    for i in range(first.shape[0]):
        f = first[i]
        if f != i:
            codons[i], used_rows[i] = codons[f], used_rows[f]
            copy_span(elements, f, np.int64(0), elements, i, np.int64(0), elements.shape[1])


@dataclass(frozen=True)
class CutDraws:
    """Crossover choices for consecutive pairs of parents.

    Attributes:
        crossing: ``bool[P]``: the pair crosses.
        first_cut: ``int64[P]``: the first parent's cut, in ``1..used``.
        second_cut: ``int64[P]``: the second parent's cut (the first's, for one-point crossover).
    """

    crossing: np.ndarray
    first_cut: np.ndarray
    second_cut: np.ndarray


def cut_draws(rng: np.random.Generator, *, used: np.ndarray, rate: float, variable: bool) -> CutDraws:
    """Draw the crossover of parents taken two by two (an odd last one is copied).

    Each pair crosses with probability ``rate``; cuts are uniform within the used codons (at least
    1, where an individual used none), as PonyGE2's ``randint(1, used)``.

    Args:
        used: The codons each parent used (:attr:`Usage.codons`), in the order they pair.
    """
    return CutDraws(*draw_cuts(rng, used, rate, variable))


@njit(cache=True)
def draw_cuts(rng, used, rate, variable):  # pragma: no cover - compiled
    """The compiled :func:`cut_draws`: crossing, first cut, second cut."""
    pairs = used.shape[0] // 2
    crossing = rng.random(pairs) < rate
    first = np.empty(pairs, dtype=np.int64)
    if not variable:
        for p in range(pairs):
            first[p] = _one_to(rng, min(used[2 * p], used[2 * p + 1]))
        return crossing, first, first
    second = np.empty(pairs, dtype=np.int64)
    for p in range(pairs):
        first[p] = _one_to(rng, used[2 * p])
    for p in range(pairs):
        second[p] = _one_to(rng, used[2 * p + 1])
    return crossing, first, second


@njit(cache=True, inline="always")
def _one_to(rng, high):  # pragma: no cover - compiled
    """An integer uniform in ``1..max(high, 1)``, drawn as NumPy's ``integers(1, high + 1)`` draws it:
    numba's own port of NumPy's Lemire draw, called directly because numba's ``integers`` allocates
    an array for each value (50 ns). The port is numba's internals: the tests hold it to NumPy."""
    if high <= 1:
        return np.int64(1)  # a range of one value: NumPy draws nothing
    return np.int64(1 + lemire_uint32(rng.bit_generator, np.uint32(high - 1)))


def splice_children(
    codons: np.ndarray,
    genes: np.ndarray,
    parents: np.ndarray,
    cuts: CutDraws,
    usage: Usage,
    out: tuple[np.ndarray, np.ndarray],
) -> None:
    """Write the crossed children of ``parents`` into ``out`` (codons, genes), one row per parent.

    Row ``2i`` is parent ``2i``'s head up to its cut, then parent ``2i+1``'s tail from its cut;
    row ``2i+1`` the other way round; pairs that do not cross are copied. ``usage`` is that of the
    rows of ``codons``, for the element slots each head keeps.
    """
    out_codons, out_genes = out
    children, row = parents.shape[0], genes.shape[1] * PLACEMENT_GENES
    splice_pairs(
        codons,
        genes.reshape(genes.shape[0], row),
        parents,
        cuts.crossing,
        cuts.first_cut,
        cuts.second_cut,
        usage.element_codons,
        out_codons,
        out_genes.reshape(children, row),
    )


@njit(cache=True)
def splice_pairs(
    codons, genes, parents, crossing, first_cut, second_cut, element_codons, out_codons, out_genes
):  # pragma: no cover - compiled
    children, length, slots = parents.shape[0], codons.shape[1], element_codons.shape[1]
    for p in range(children // 2):
        a, b = parents[2 * p], parents[2 * p + 1]
        cut_a, cut_b, rows_a, rows_b = length, length, slots, slots  # a pair that does not cross
        if crossing[p]:
            cut_a, cut_b = first_cut[p], second_cut[p]
            rows_a = _elements_within(element_codons[a], cut_a)
            rows_b = _elements_within(element_codons[b], cut_b)
        _splice_rows(codons, a, b, cut_a, cut_b, out_codons, 2 * p)
        _splice_rows(codons, b, a, cut_b, cut_a, out_codons, 2 * p + 1)
        _splice_rows(genes, a, b, rows_a * PLACEMENT_GENES, rows_b * PLACEMENT_GENES, out_genes, 2 * p)
        _splice_rows(genes, b, a, rows_b * PLACEMENT_GENES, rows_a * PLACEMENT_GENES, out_genes, 2 * p + 1)
    if children % 2:
        last = parents[children - 1]
        _splice_rows(codons, last, last, length, length, out_codons, children - 1)
        _splice_rows(genes, last, last, genes.shape[1], genes.shape[1], out_genes, children - 1)


@njit(cache=True, inline="always")
def _elements_within(element_codons, cut):  # pragma: no cover - compiled
    """Elements complete once the first ``cut`` codons are read (they are in codon order)."""
    count = 0
    while count < element_codons.shape[0] and element_codons[count] <= cut:
        count += 1
    return count


@inner_kernel  # not inlined: six copies of its three loops compiled for seconds
def _splice_rows(source, head, tail, head_cut, tail_cut, out, row):  # pragma: no cover - compiled
    """``out[row]``: ``source[head]`` up to ``head_cut``, ``source[tail]`` from ``tail_cut`` for as
    long as both fit the width, and ``source[head]``'s own values in what is left."""
    width = source.shape[1]
    taken = width - max(head_cut, tail_cut)
    copy_span(source, head, np.int64(0), out, row, np.int64(0), head_cut)
    copy_span(source, tail, tail_cut, out, row, head_cut, taken)
    copy_span(source, head, head_cut + taken, out, row, head_cut + taken, width - head_cut - taken)


def used_mutation_draws(
    rng: np.random.Generator, *, usage: Usage, length: int, slots: int, rate: float, codon_max: int
) -> MutationDraws:
    """Int-flip mutation within what the children (of ``usage``) use: each used codon and each gene of
    an element's placement row is replaced with probability ``rate``.

    Hits are drawn over whole rows, as :func:`~mazegen.runtime.engine._operators.mutation_draws`
    does, and those past the used part dropped before their values are drawn: each used position
    is still hit with probability ``rate``, independently.
    """
    children = usage.codons.shape[0]
    draws = draw_mutation(
        rng,
        children,
        length,
        slots,
        rate,
        gap_scale(rate),
        codon_max,
        codon_type(codon_max),
        usage.codons,
        usage.rows,
    )
    return MutationDraws(*draws)
