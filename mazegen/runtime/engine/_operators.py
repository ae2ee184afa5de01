"""Genetic operators as pure functions of arrays and a random generator.

Genomes are two chromosomes: structure codons ``int32[N, L]`` and placement genes
``uint16[N, K, 5]``. Random choices are drawn from ``rng`` first, as plain arrays;
:func:`cross` then applies them in one parallel pass that writes straight into
the next generation's arrays, so breeding a population of 50,000 copies each genome once.

Each draw is a compiled function of the run's ``numpy.random.Generator`` (numba draws from it
exactly as NumPy does), so that :mod:`~mazegen.runtime.engine._breeding` makes a generation's
draws in one compiled call; the functions here are the operators one at a time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from mazegen.runtime.compiling import inner_kernel
from mazegen.runtime.engine._placement import GENE_MAX, PLACEMENT_GENES


def random_codons(rng: np.random.Generator, count: int, length: int, codon_max: int) -> np.ndarray:
    """Uniform random structure codons in ``0..codon_max``."""
    return rng.integers(0, codon_max + 1, size=(count, length), dtype=np.int32)


def random_genes(rng: np.random.Generator, count: int, slots: int) -> np.ndarray:
    """Uniform random placement genes."""
    return rng.integers(0, GENE_MAX + 1, size=(count, slots, PLACEMENT_GENES), dtype=np.uint16)


def ranking(fitness: np.ndarray, count: int | None = None) -> np.ndarray:
    """Indices from best to worst; ties keep index order so runs are reproducible.

    Args:
        fitness: One value per individual; NaN ranks last.
        count: Return only the best ``count``, without sorting the rest.
    """
    n = fitness.shape[0]
    key = -fitness
    if count is None or count >= n:
        return np.argsort(key, kind="stable")
    if count <= 0:
        return np.empty(0, dtype=np.int64)
    # A guess of the count-th best key from a strided sample narrows the sort to a few
    # candidates (np.partition crawls when many individuals tie at the top). The result is
    # exact whatever the guess: a guess that leaves too few candidates falls back to a full sort.
    sample = np.sort(key[:: max(1, n // 1024)])
    guess = sample[min(sample.size - 1, int(1.25 * count * sample.size / n) + 8)]
    candidates = np.flatnonzero(key <= guess)  # NaN keys never qualify
    if candidates.size < count:
        return np.argsort(key, kind="stable")[:count]
    return candidates[np.argsort(key[candidates], kind="stable")][:count]


def truncation_parents(
    rng: np.random.Generator, fitness: np.ndarray, fraction: float, count: int
) -> np.ndarray:
    """Parents drawn uniformly from the best ``fraction`` of the population (the paper's selection)."""
    return draw_from_pool(rng, truncation_pool(fitness, fraction), count)


def truncation_pool(fitness: np.ndarray, fraction: float) -> np.ndarray:
    """The best ``fraction`` of the population (at least one), best first: truncation's parents."""
    return ranking(fitness, max(1, int(np.ceil(fraction * fitness.shape[0]))))


@njit(cache=True)
def draw_from_pool(rng, pool, count):  # pragma: no cover - compiled
    """``count`` rows drawn uniformly, with replacement, from ``pool``."""
    return pool[rng.integers(0, pool.shape[0], size=count)]


def tournament_parents(rng: np.random.Generator, fitness: np.ndarray, size: int, count: int) -> np.ndarray:
    """Winners of ``count`` tournaments of ``size`` individuals drawn with replacement.

    The fittest entrant wins; among equal fitness the lowest index, as in :func:`ranking`.
    """
    return draw_tournaments(rng, fitness, size, count)


@njit(cache=True)
def draw_tournaments(rng, fitness, size, count):  # pragma: no cover - compiled
    """The compiled :func:`tournament_parents`."""
    entrants = rng.integers(0, fitness.shape[0], size=count * size)
    return _tournament_winners(fitness, entrants.reshape(count, size))


@inner_kernel
def _tournament_winners(fitness, entrants):  # pragma: no cover - compiled
    winners = np.empty(entrants.shape[0], np.int64)
    for t in range(entrants.shape[0]):
        best = entrants[t, 0]
        for j in range(1, entrants.shape[1]):
            e = entrants[t, j]
            f, b = fitness[e], fitness[best]
            if f > b or (f == b and e < best) or (np.isnan(b) and (not np.isnan(f) or e < best)):
                best = e
        winners[t] = best
    return winners


@dataclass(frozen=True)
class CrossoverDraws:
    """One-point crossover choices for consecutive pairs of parents."""

    crossing: np.ndarray  # bool[P]: the pair swaps tails
    codon_cut: np.ndarray  # int64[P] in 1..L-1: first codon of the tail
    gene_cut: np.ndarray  # int64[P] in 0..K: first placement row of the tail


def crossover_draws(
    rng: np.random.Generator, children: int, length: int, slots: int, rate: float
) -> CrossoverDraws:
    """Draw the crossover of ``children`` parents taken two by two (an odd last one is copied).

    Each pair crosses with probability ``rate``, at one cut per chromosome.
    """
    return CrossoverDraws(*draw_crossover(rng, children // 2, length, slots, rate))


@njit(cache=True)
def draw_crossover(rng, pairs, length, slots, rate):  # pragma: no cover - compiled
    """The compiled :func:`crossover_draws` of ``pairs`` pairs: crossing, codon cut, gene cut."""
    crossing = rng.random(pairs) < rate
    codon_cut = rng.integers(1, max(length, 2), size=pairs)
    return crossing, codon_cut, rng.integers(0, slots + 1, size=pairs)


def hit_positions(rng: np.random.Generator, total: int, rate: float) -> np.ndarray:
    """Positions in ``0..total-1`` each hit independently with probability ``rate``.

    Drawn as geometric gaps, so the cost follows the number of hits, not ``total``; a gap
    is ``1 + floor(E / -log(1 - rate))`` with ``E`` standard exponential, which is exactly
    geometric and about twice as fast to draw as ``Generator.geometric``.
    """
    return draw_hits(rng, total, rate, gap_scale(rate))


def gap_scale(rate: float) -> float:
    """``-1 / log(1 - rate)``: what :func:`draw_hits` scales exponentials by (NumPy's ``log1p``, so
    that every caller scales alike)."""
    return float(-1.0 / np.log1p(-rate)) if 0 < rate < 1 else 0.0


@njit(cache=True)
def draw_hits(rng, total, rate, scale):  # pragma: no cover - compiled
    """The compiled :func:`hit_positions`; ``scale`` from :func:`gap_scale`.

    Exponentials are drawn in batches of a fixed size (about 1.1 times the hits expected),
    so the draws, and what the generator is left at, depend on ``total`` and ``rate`` alone.
    """
    if rate <= 0 or total == 0:
        return np.empty(0, dtype=np.int64)
    if rate >= 1:  # every position (a loop: numba's arange compiles for a third of a second)
        every = np.empty(total, dtype=np.int64)
        for k in range(total):
            every[k] = k
        return every
    batch = int(total * rate * 1.1) + 16
    hits = np.empty(batch, dtype=np.int64)
    found, position = 0, -1
    while position < total:
        if hits.shape[0] < found + batch:
            grown = np.empty(found + batch, dtype=np.int64)
            for k in range(found):
                grown[k] = hits[k]
            hits = grown
        found, position = _add_gaps(rng.standard_exponential(batch), scale, total, hits, found, position)
    return hits[:found]


@inner_kernel
def _add_gaps(exponentials, scale, total, hits, found, position):  # pragma: no cover - compiled
    """Step from ``position`` by geometric gaps, recording positions below ``total`` in ``hits``."""
    for e in exponentials:
        position += np.int64(min(e * scale, float(total))) + 1  # min: no overflow at tiny rates
        if position >= total:
            break
        hits[found] = position
        found += 1
    return found, position


@dataclass(frozen=True)
class MutationDraws:
    """Int-flip mutation choices: flat positions in the children's chromosomes and new values."""

    codon_hits: np.ndarray
    codon_values: np.ndarray
    gene_hits: np.ndarray
    gene_values: np.ndarray


def mutation_draws(
    rng: np.random.Generator, children: int, length: int, slots: int, rate: float, codon_max: int
) -> MutationDraws:
    """Draw an int-flip mutation: each codon and each placement gene is replaced with probability ``rate``.

    New values are uniform in ``0..codon_max`` for codons and ``0..GENE_MAX`` for genes,
    drawn in the narrowest integer type that holds them (narrow draws are several times faster).
    """
    codons = (codon_max, codon_type(codon_max))
    return MutationDraws(
        *draw_mutation(rng, children, length, slots, rate, gap_scale(rate), *codons, None, None)
    )


def codon_type(codon_max: int) -> type:
    """The narrowest unsigned type that holds ``codon_max`` (NumPy's ``min_scalar_type``), in which
    mutation draws new codons: narrow draws are several times faster. Given to the kernels as an
    argument, so that they compile the draw of this one type only."""
    return np.min_scalar_type(codon_max).type


@njit(cache=True)
def draw_mutation(
    rng, children, length, slots, rate, scale, codon_max, drawn_as, used_codons, used_rows
):  # pragma: no cover - compiled
    """The compiled :func:`mutation_draws`, or, given each child's used codons and element rows
    (``used_codons``, ``used_rows``; None for whole genomes, which compiles without them), the
    mutation within them.

    Hits are drawn over whole rows and those past the used part dropped before the values are
    drawn: each used position is still hit with probability ``rate``, independently.
    """
    codon_hits = draw_hits(rng, children * length, rate, scale)
    if used_codons is not None:
        codon_hits = codon_hits[codon_hits % length < used_codons[codon_hits // length]]
    codon_values = rng.integers(0, codon_max, size=codon_hits.shape[0], dtype=drawn_as, endpoint=True)
    row = slots * PLACEMENT_GENES
    gene_hits = draw_hits(rng, children * row, rate, scale)
    if used_rows is not None:
        gene_hits = gene_hits[gene_hits % row // PLACEMENT_GENES < used_rows[gene_hits // row]]
    gene_values = rng.integers(0, GENE_MAX, size=gene_hits.shape[0], dtype=np.uint16, endpoint=True)
    return codon_hits, codon_values.astype(np.int32), gene_hits, gene_values


def cross(
    codons: np.ndarray,
    genes: np.ndarray,
    parents: np.ndarray,
    crossover: CrossoverDraws,
    out_codons: np.ndarray,
    out_genes: np.ndarray,
) -> None:
    """Write the crossed children of ``parents`` into ``out_codons`` and ``out_genes``, one row per parent.

    Rows ``2i`` and ``2i+1`` are the children of the pair ``parents[2i], parents[2i+1]``:
    copies of their parents, with tails swapped where the pair crosses (:func:`mutate` follows).

    Args:
        codons: ``int32[N, L]`` structure codons of the population.
        genes: ``uint16[N, K, 5]`` placement genes of the population.
        parents: Row indices into the population, one per child.
        crossover: From :func:`crossover_draws` for ``len(parents)`` children.
        out_codons: ``int32[len(parents), L]``, C-contiguous, overwritten.
        out_genes: ``uint16[len(parents), K, 5]``, C-contiguous, overwritten.
    """
    children, row = parents.shape[0], genes.shape[1] * PLACEMENT_GENES
    flat_genes = genes.reshape(genes.shape[0], row)
    flat_out = out_genes.reshape(children, row)
    cross_pairs(
        codons, flat_genes, parents, crossover.crossing, crossover.codon_cut, crossover.gene_cut,
        out_codons, flat_out,
    )  # fmt: skip


def mutate(mutation: MutationDraws, codons: np.ndarray, genes: np.ndarray) -> None:
    """Write the new values of ``mutation`` into C-contiguous ``codons`` and ``genes``, in place."""
    apply_mutation(
        mutation.codon_hits, mutation.codon_values, mutation.gene_hits, mutation.gene_values,
        codons.reshape(codons.shape[0], -1), genes.reshape(genes.shape[0], -1),
    )  # fmt: skip


@njit(cache=True)
def apply_mutation(codon_hits, codon_values, gene_hits, gene_values, codons, genes):  # pragma: no cover
    """The compiled :func:`mutate`: hits are flat positions in the rows of ``codons`` and ``genes``."""
    length, row = codons.shape[1], genes.shape[1]
    for j in range(codon_hits.shape[0]):
        codons[codon_hits[j] // length, codon_hits[j] % length] = codon_values[j]
    for j in range(gene_hits.shape[0]):
        genes[gene_hits[j] // row, gene_hits[j] % row] = gene_values[j]


@njit(cache=True)
def cross_pairs(
    codons, genes, parents, crossing, codon_cut, gene_cut, out_codons, out_genes
):  # pragma: no cover - compiled
    """The compiled :func:`cross`: ``genes`` one flat row per genome, ``gene_cut`` in placement rows."""
    children = parents.shape[0]
    for p in range(children // 2):
        first, second = parents[2 * p], parents[2 * p + 1]
        gene_cut_p = gene_cut[p] * PLACEMENT_GENES if crossing[p] else genes.shape[1]
        _copy_crossed(codons, first, second, codon_cut[p] if crossing[p] else codons.shape[1], out_codons, p)
        _copy_crossed(genes, first, second, gene_cut_p, out_genes, p)
    if children % 2:
        copy_span(
            codons, parents[children - 1], np.int64(0), out_codons, children - 1, np.int64(0), codons.shape[1]
        )
        copy_span(
            genes, parents[children - 1], np.int64(0), out_genes, children - 1, np.int64(0), genes.shape[1]
        )


@njit(cache=True, inline="always")
def _copy_crossed(source, first, second, cut, out, pair):  # pragma: no cover - compiled
    width = source.shape[1]
    copy_span(source, first, np.int64(0), out, 2 * pair, np.int64(0), cut)
    copy_span(source, second, cut, out, 2 * pair, cut, width - cut)
    copy_span(source, second, np.int64(0), out, 2 * pair + 1, np.int64(0), cut)
    copy_span(source, first, cut, out, 2 * pair + 1, cut, width - cut)


@njit(cache=True, inline="always")
def copy_span(source, row, start, out, out_row, out_start, count):  # pragma: no cover - compiled
    """``out[out_row, out_start:][:count] = source[row, start:][:count]``, as a loop: numba compiles
    each slice assignment with a shape check and its message, seconds of a first run apiece."""
    # Row slices, then indices from range(): the compiler knows they are not negative, so the copy
    # has no wrap-around test per element and is vectorised.
    taken, put = source[row, start : start + count], out[out_row, out_start : out_start + count]
    for k in range(count):
        put[k] = taken[k]
