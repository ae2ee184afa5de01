"""Genetic operators as pure functions of arrays and a random generator.

Genomes are two chromosomes: structure codons ``int32[N, L]`` and placement genes
``uint16[N, K, 5]``. Every function returns new arrays and draws only from ``rng``.
"""

from __future__ import annotations

import numpy as np

from mazegen.runtime.population import GENE_MAX, PLACEMENT_GENES


def random_codons(rng: np.random.Generator, count: int, length: int, codon_max: int) -> np.ndarray:
    """Uniform random structure codons in ``0..codon_max``."""
    return rng.integers(0, codon_max + 1, size=(count, length), dtype=np.int32)


def random_genes(rng: np.random.Generator, count: int, slots: int) -> np.ndarray:
    """Uniform random placement genes."""
    return rng.integers(0, GENE_MAX + 1, size=(count, slots, PLACEMENT_GENES), dtype=np.uint16)


def ranking(fitness: np.ndarray) -> np.ndarray:
    """Indices from best to worst; ties keep index order so runs are reproducible."""
    return np.argsort(-fitness, kind="stable")


def truncation_parents(
    rng: np.random.Generator, fitness: np.ndarray, fraction: float, count: int
) -> np.ndarray:
    """Parents drawn uniformly from the best ``fraction`` of the population (the paper's selection)."""
    keep = max(1, int(np.ceil(fraction * fitness.shape[0])))
    return ranking(fitness)[:keep][rng.integers(0, keep, size=count)]


def tournament_parents(rng: np.random.Generator, fitness: np.ndarray, size: int, count: int) -> np.ndarray:
    """Winners of ``count`` tournaments of ``size`` individuals drawn with replacement."""
    entrants = rng.integers(0, fitness.shape[0], size=(count, size))
    # Among equal fitness the lowest index wins, as with a stable ranking.
    rank_of = np.empty(fitness.shape[0], dtype=np.int64)
    rank_of[ranking(fitness)] = np.arange(fitness.shape[0])
    best = np.argmin(rank_of[entrants], axis=1)
    return entrants[np.arange(count), best]


def one_point_crossover(
    rng: np.random.Generator, codons: np.ndarray, genes: np.ndarray, rate: float
) -> tuple[np.ndarray, np.ndarray]:
    """Cross consecutive pairs of parents at one point per chromosome.

    Row ``2i`` and ``2i+1`` are a pair; with probability ``rate`` they swap their
    tails (codons after a cut in ``1..L-1``, placement rows after a cut in ``0..K``).
    An odd last row is copied unchanged.
    """
    n, length = codons.shape
    slots = genes.shape[1]
    pairs = n // 2
    first, second = np.arange(pairs) * 2, np.arange(pairs) * 2 + 1
    crossing = rng.random(pairs) < rate
    codon_cut = rng.integers(1, max(length, 2), size=pairs)
    gene_cut = rng.integers(0, slots + 1, size=pairs)
    codon_tail = (np.arange(length)[None, :] >= codon_cut[:, None]) & crossing[:, None]
    gene_tail = (np.arange(slots)[None, :] >= gene_cut[:, None]) & crossing[:, None]
    new_codons, new_genes = codons.copy(), genes.copy()
    new_codons[first] = np.where(codon_tail, codons[second], codons[first])
    new_codons[second] = np.where(codon_tail, codons[first], codons[second])
    new_genes[first] = np.where(gene_tail[..., None], genes[second], genes[first])
    new_genes[second] = np.where(gene_tail[..., None], genes[first], genes[second])
    return new_codons, new_genes


def hit_positions(rng: np.random.Generator, total: int, rate: float) -> np.ndarray:
    """Positions in ``0..total-1`` each hit independently with probability ``rate``.

    Drawn as geometric gaps, so the cost follows the number of hits, not ``total``.
    """
    if rate <= 0 or total == 0:
        return np.empty(0, dtype=np.int64)
    if rate >= 1:
        return np.arange(total, dtype=np.int64)
    expected = int(total * rate * 1.1) + 16
    positions = np.cumsum(rng.geometric(rate, size=expected)) - 1
    while positions[-1] < total:
        more = np.cumsum(rng.geometric(rate, size=expected)) + positions[-1]
        positions = np.concatenate([positions, more])
    return positions[positions < total]


def int_flip_mutation(
    rng: np.random.Generator, codons: np.ndarray, genes: np.ndarray, rate: float, codon_max: int
) -> tuple[np.ndarray, np.ndarray]:
    """Replace each codon and each placement gene by a random value with probability ``rate``."""
    new_codons, new_genes = codons.copy(), genes.copy()
    for array, high in ((new_codons, codon_max), (new_genes, GENE_MAX)):
        flat = array.reshape(-1)
        hits = hit_positions(rng, flat.shape[0], rate)
        flat[hits] = rng.integers(0, high + 1, size=hits.shape[0])
    return new_codons, new_genes
