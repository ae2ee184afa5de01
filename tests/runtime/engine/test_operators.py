"""Genetic operators: shapes, bounds, selection pressure, reproducibility, and the breeding kernel
against a plain NumPy reference drawing the same random numbers."""

from __future__ import annotations

import numpy as np
import pytest

from mazegen.runtime.engine import _operators as ops
from mazegen.runtime.engine._placement import GENE_MAX


def rng(seed: int = 0) -> np.random.Generator:
    return np.random.default_rng(seed)


def test_random_genomes_respect_their_ranges():
    codons = ops.random_codons(rng(), 500, 16, 7)
    genes = ops.random_genes(rng(), 500, 4)
    assert codons.shape == (500, 16) and codons.min() == 0 and codons.max() == 7
    assert genes.shape == (500, 4, 5) and genes.dtype == np.uint16 and genes.max() > GENE_MAX - 100


def reference_children(rng, codons, genes, parents, rate, mutation, codon_max):
    """Crossover then int-flip mutation in plain NumPy, drawing as the operators module does."""
    codons, genes = codons[parents], genes[parents]
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
    for array, high in ((new_codons, codon_max), (new_genes, GENE_MAX)):
        flat = array.reshape(-1)
        hit = ops.hit_positions(rng, flat.size, mutation)
        flat[hit] = rng.integers(0, high, size=hit.shape[0], dtype=np.min_scalar_type(high), endpoint=True)
    return new_codons, new_genes


def children(rng, codons, genes, parents, rate, mutation, codon_max):
    """The kernel path: draws, then one pass into fresh output arrays."""
    count, length, slots = parents.size, codons.shape[1], genes.shape[1]
    crossover = ops.crossover_draws(rng, count, length, slots, rate)
    flips = ops.mutation_draws(rng, count, length, slots, mutation, codon_max)
    out_codons = np.full((count, length), -1, dtype=codons.dtype)
    out_genes = np.zeros((count, slots, 5), dtype=genes.dtype)
    ops.cross(codons, genes, parents, crossover, out_codons, out_genes)
    ops.mutate(flips, out_codons, out_genes)
    return out_codons, out_genes


def test_truncation_draws_only_from_the_best_fraction():
    fitness = np.arange(100, dtype=float)
    parents = ops.truncation_parents(rng(), fitness, 0.1, 1000)
    assert set(parents.tolist()) == set(range(90, 100))


def test_tournament_prefers_the_fitter():
    fitness = np.arange(1000, dtype=float)
    parents = ops.tournament_parents(rng(), fitness, 5, 5000)
    assert parents.mean() > 700  # E[max of 5 uniform] = 5/6 of the range
    assert ops.tournament_parents(rng(), fitness, 1, 5000).mean() < 600


@pytest.mark.parametrize("size", [1, 2, 3, 7])
def test_tournament_kernel_equals_a_ranking_reference(size):
    """Winner = entrant with the lowest stable rank; fitness has ties, -inf and NaN."""
    fitness = rng(2).integers(0, 6, size=300).astype(float)
    fitness[rng(3).integers(0, 300, size=40)] = -np.inf
    fitness[rng(4).integers(0, 300, size=20)] = np.nan
    entrants = rng(9).integers(0, 300, size=(2000, size))
    rank_of = np.empty(300, dtype=np.int64)
    rank_of[np.argsort(-fitness, kind="stable")] = np.arange(300)
    expected = entrants[np.arange(2000), np.argmin(rank_of[entrants], axis=1)]
    assert (ops.tournament_parents(rng(9), fitness, size, 2000) == expected).all()


def test_ranking_breaks_ties_by_index():
    assert ops.ranking(np.array([1.0, 3.0, 3.0, -np.inf, 1.0])).tolist() == [1, 2, 0, 4, 3]


@pytest.mark.parametrize("count", [0, 1, 2, 37, 299, 300, 500])
def test_partial_ranking_is_a_prefix_of_the_full_ranking(count):
    fitness = rng(2).integers(0, 6, size=300).astype(float)
    fitness[rng(3).integers(0, 300, size=40)] = -np.inf
    fitness[rng(4).integers(0, 300, size=250)] = np.nan  # more NaN than the rest: the fallback path
    for values in (fitness, np.nan_to_num(fitness, nan=2.0)):
        full = np.argsort(-values, kind="stable")
        assert ops.ranking(values, count).tolist() == full[:count].tolist()


@pytest.mark.parametrize("top", [0, 1, 900, 60000])
@pytest.mark.parametrize("count", [1, 7, 600, 6000, 59999])
def test_partial_ranking_of_large_populations_with_ties(top, count):
    """Sampled guesses of the cut: ties at the top, a few distinct values, and the fallback."""
    fitness = rng(top).integers(0, 9, size=60000).astype(float)
    fitness[rng(1).permutation(60000)[:top]] = 99.0
    full = np.argsort(-fitness, kind="stable")
    assert ops.ranking(fitness, count).tolist() == full[:count].tolist()


def test_one_point_crossover_swaps_tails():
    codons = np.array([[1] * 8, [2] * 8], dtype=np.int32)
    genes = np.zeros((2, 3, 5), dtype=np.uint16)
    genes[1] = 9
    new_codons, new_genes = children(rng(3), codons, genes, np.array([0, 1]), 1.0, 0.0, 255)
    cut = int(np.argmax(new_codons[0] == 2))
    assert 1 <= cut <= 7
    assert new_codons[0].tolist() == [1] * cut + [2] * (8 - cut)
    assert new_codons[1].tolist() == [2] * cut + [1] * (8 - cut)
    assert ((new_genes[0] == 0) | (new_genes[0] == 9)).all()
    assert (new_genes[0] + new_genes[1] == 9).all()
    same, _ = children(rng(3), codons, genes, np.array([1, 0]), 0.0, 0.0, 255)
    assert (same == codons[::-1]).all()


@pytest.mark.parametrize(
    ("population", "count", "length", "slots", "rate", "mutation"),
    [(60, 41, 16, 3, 0.9, 0.05), (7, 7, 1, 1, 1.0, 0.5), (30, 30, 32, 8, 0.0, 0.0), (50, 1, 5, 2, 0.5, 1.0)],
)
def test_breeding_kernel_equals_the_numpy_reference(population, count, length, slots, rate, mutation):
    codons = ops.random_codons(rng(5), population, length, 255)
    genes = ops.random_genes(rng(6), population, slots)
    parents = rng(7).integers(0, population, size=count)
    expected = reference_children(rng(8), codons, genes, parents, rate, mutation, 255)
    got = children(rng(8), codons, genes, parents, rate, mutation, 255)
    assert (got[0] == expected[0]).all() and (got[1] == expected[1]).all()
    assert got[0].dtype == np.int32 and got[1].dtype == np.uint16


@pytest.mark.parametrize(("total", "rate"), [(1, 0.5), (100, 0.05), (20000, 0.01), (5000, 0.3), (10, 1e-30)])
def test_hit_positions_equal_a_numpy_reference(total, rate):
    """Batches of exponential draws turned into geometric gaps, accumulated until past ``total``."""
    draws = rng(total)
    batch = int(total * rate * 1.1) + 16
    scale = -1.0 / np.log1p(-rate)
    positions = np.empty(0, dtype=np.int64)
    last = -1
    while last < total:
        gaps = np.minimum(draws.standard_exponential(batch) * scale, float(total)).astype(np.int64) + 1
        more = np.cumsum(gaps) + last
        positions = np.concatenate([positions, more])
        last = int(more[-1])
    assert ops.hit_positions(rng(total), total, rate).tolist() == positions[positions < total].tolist()


@pytest.mark.parametrize("rate", [0.0, 0.01, 0.2, 1.0])
def test_mutation_rate_is_respected(rate):
    codons = np.zeros((400, 50), dtype=np.int32)
    genes = np.zeros((400, 10, 5), dtype=np.uint16)
    new_codons, _ = children(rng(), codons, genes, np.arange(400), 0.0, rate, 255)
    positions = ops.hit_positions(rng(1), 20000, rate)
    assert abs(positions.size / 20000 - rate) < 0.01
    assert np.unique(positions).size == positions.size
    changed = (new_codons != 0).mean()
    assert abs(changed - rate * 255 / 256) < 0.01
    assert new_codons.max() <= 255
    assert (codons == 0).all()  # inputs are not modified


def test_operators_are_reproducible():
    codons = ops.random_codons(rng(5), 50, 10, 255)
    genes = ops.random_genes(rng(5), 50, 3)
    parents = np.arange(50)[::-1]
    first = children(rng(7), codons, genes, parents, 0.9, 0.1, 255)
    second = children(rng(7), codons, genes, parents, 0.9, 0.1, 255)
    assert all((a == b).all() for a, b in zip(first, second))
