"""Genetic operators: shapes, bounds, selection pressure and reproducibility."""

from __future__ import annotations

import numpy as np
import pytest

from mazegen.runtime import operators as ops
from mazegen.runtime.population import GENE_MAX


def rng(seed: int = 0) -> np.random.Generator:
    return np.random.default_rng(seed)


def test_random_genomes_respect_their_ranges():
    codons = ops.random_codons(rng(), 500, 16, 7)
    genes = ops.random_genes(rng(), 500, 4)
    assert codons.shape == (500, 16) and codons.min() == 0 and codons.max() == 7
    assert genes.shape == (500, 4, 5) and genes.dtype == np.uint16 and genes.max() > GENE_MAX - 100


def test_truncation_draws_only_from_the_best_fraction():
    fitness = np.arange(100, dtype=float)
    parents = ops.truncation_parents(rng(), fitness, 0.1, 1000)
    assert set(parents.tolist()) == set(range(90, 100))


def test_tournament_prefers_the_fitter():
    fitness = np.arange(1000, dtype=float)
    parents = ops.tournament_parents(rng(), fitness, 5, 5000)
    assert fitness[parents].mean() > 700  # E[max of 5 uniform] = 5/6 of the range
    assert ops.tournament_parents(rng(), fitness, 1, 5000).mean() < 600


def test_ranking_breaks_ties_by_index():
    assert ops.ranking(np.array([1.0, 3.0, 3.0, -np.inf, 1.0])).tolist() == [1, 2, 0, 4, 3]


def test_one_point_crossover_swaps_tails():
    codons = np.array([[1] * 8, [2] * 8], dtype=np.int32)
    genes = np.zeros((2, 3, 5), dtype=np.uint16)
    genes[1] = 9
    new_codons, new_genes = ops.one_point_crossover(rng(3), codons, genes, 1.0)
    cut = int(np.argmax(new_codons[0] == 2))
    assert 1 <= cut <= 7
    assert new_codons[0].tolist() == [1] * cut + [2] * (8 - cut)
    assert new_codons[1].tolist() == [2] * cut + [1] * (8 - cut)
    assert (new_codons + new_codons[::-1] == 3).all()
    assert ((new_genes[0] == 0) | (new_genes[0] == 9)).all()
    assert (new_genes[0] + new_genes[1] == 9).all()
    same, _ = ops.one_point_crossover(rng(3), codons, genes, 0.0)
    assert (same == codons).all()


@pytest.mark.parametrize("rate", [0.0, 0.01, 0.2, 1.0])
def test_mutation_rate_is_respected(rate):
    codons = np.zeros((400, 50), dtype=np.int32)
    genes = np.zeros((400, 10, 5), dtype=np.uint16)
    new_codons, _new_genes = ops.int_flip_mutation(rng(), codons, genes, rate, 255)
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
    first = ops.int_flip_mutation(rng(7), *ops.one_point_crossover(rng(6), codons, genes, 0.9), 0.1, 255)
    second = ops.int_flip_mutation(rng(7), *ops.one_point_crossover(rng(6), codons, genes, 0.9), 0.1, 255)
    assert all((a == b).all() for a, b in zip(first, second))
