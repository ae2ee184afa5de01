"""Genome hashes against a plain Python reference, and the evaluation cache against direct evaluation."""

from __future__ import annotations

import numpy as np
import pytest

import mazegen
from mazegen.generator.build import build
from mazegen.runtime.engine._cache import EvaluationCache, genome_hashes
from mazegen.runtime.engine._evolution import evaluate_cached
from mazegen.runtime.engine._problem import Problem, Workspace
from mazegen.runtime.engine._used_operators import Usage
from tests.conftest import EXAMPLES

MASK = (1 << 64) - 1
OFFSETS = (0xCBF29CE484222325, 0x84222325CBF29CE4, 0x9E3779B97F4A7C15, 0xD6E8FEB86659FD93)


def mix(h: int) -> int:
    h = ((h ^ (h >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    h = ((h ^ (h >> 27)) * 0x94D049BB133111EB) & MASK
    return h ^ (h >> 31)


def reference_hash(codons: list[int], genes: list[int]) -> int:
    """Four FNV-1a lanes per chromosome (value j to lane j % 4, the tail to lane 0), then mixed."""
    lanes = list(OFFSETS)
    for row in (codons, genes):
        body = len(row) - len(row) % 4
        for j, value in enumerate(row):
            lane = j % 4 if j < body else 0
            lanes[lane] = ((lanes[lane] ^ (value & MASK)) * 0x100000001B3) & MASK
    a, b, c, d = lanes
    return mix(mix(mix(mix(a) ^ b) ^ c) ^ d)


@pytest.mark.parametrize(("length", "slots"), [(0, 1), (1, 1), (7, 2), (32, 3), (33, 5)])
def test_hash_kernel_equals_python_reference(length, slots):
    rng = np.random.default_rng(length)
    codons = rng.integers(-300, 300, size=(40, length), dtype=np.int32)
    genes = rng.integers(0, 65536, size=(40, slots, 5), dtype=np.uint16)
    expected = [reference_hash(c.tolist(), g.reshape(-1).tolist()) for c, g in zip(codons, genes)]
    assert genome_hashes(codons, genes).tolist() == expected


def test_hashes_tell_genomes_apart():
    rng = np.random.default_rng(0)
    codons = rng.integers(0, 256, size=(2000, 16), dtype=np.int32)
    genes = rng.integers(0, 65536, size=(2000, 4, 5), dtype=np.uint16)
    codons[1000:] = codons[:1000]
    genes[1000:] = genes[:1000]
    codons[1000:1500, 3] += 1  # one codon changed
    genes[1500:, 2, 4] ^= 1  # one gene changed
    hashes = genome_hashes(codons, genes)
    assert np.unique(hashes[:1000]).size == 1000
    assert (hashes[1000:] != hashes[:1000]).all()
    assert (genome_hashes(codons[:10], genes[:10]) == hashes[:10]).all()
    assert genome_hashes(codons[:0], genes[:0]).shape == (0,)


@pytest.mark.parametrize("size", [0, 1, 7, 3000])
def test_cache_split_equals_a_dictionary_reference(size):
    """Two generations drawn from a small pool of hashes: duplicates, cache hits and new genomes."""
    rng = np.random.default_rng(size)
    pool = rng.integers(2, 2**63, size=max(size, 1), dtype=np.uint64)
    cache, remembered, remembered_rows = EvaluationCache(), {}, {}
    for generation in range(3):
        hashes = pool[rng.integers(0, pool.size, size=size)]
        lookup = cache.lookup(hashes)
        first_row: dict[int, int] = {}
        for row, value in enumerate(hashes.tolist()):
            first_row.setdefault(value, row)
        expected_first = [first_row[value] for value in hashes.tolist()]
        expected_todo = sorted(row for value, row in first_row.items() if value not in remembered)
        assert lookup.first.tolist() == expected_first
        assert lookup.todo.tolist() == expected_todo and lookup.distinct == len(first_row)
        for value, row in first_row.items():
            if value in remembered:
                assert lookup.fitness[row] == remembered[value]
        expected_cached = sorted(row for value, row in first_row.items() if value in remembered)
        assert lookup.cached.tolist() == expected_cached
        assert lookup.cached_from.tolist() == [remembered_rows[int(hashes[row])] for row in expected_cached]
        if generation:
            # Each row's usage records its generation and row: the cache gives the old ones back.
            recalled = Usage.empty(size, 2)
            recalled.codons[:] = -1
            cache.recall_usage(lookup, recalled)
            expected = np.full(size, -1)
            expected[expected_cached] = [
                1000 * (generation - 1) + remembered_rows[int(hashes[row])] for row in expected_cached
            ]
            assert recalled.codons.tolist() == expected.tolist()
        fitness = lookup.fitness.copy()
        fitness[lookup.todo] = rng.random(lookup.todo.size) + generation  # "evaluated"
        fitness = fitness[lookup.first]
        usage = Usage.empty(size, 2)
        usage.codons[:] = 1000 * generation + lookup.first
        cache.remember(lookup, fitness, usage)
        remembered = {value: fitness[row] for value, row in first_row.items()}
        remembered_rows = {value: row for value, row in first_row.items()}


def test_cached_evaluation_equals_direct_evaluation(tmp_path):
    build(mazegen.load(EXAMPLES / "factory.maze"), tmp_path)
    problem = Problem.from_build_dir(tmp_path)
    rng = np.random.default_rng(3)
    codons = rng.integers(0, 256, size=(600, 32), dtype=np.int32)
    genes = rng.integers(0, 65536, size=(600, problem.slots, 5), dtype=np.uint16)
    codons[300:], genes[300:] = codons[:300], genes[:300]  # every genome twice
    cache, workspace = EvaluationCache(), Workspace()
    direct = problem.evaluate(codons, genes).fitness
    first = evaluate_cached(problem, codons, genes, cache, workspace)
    assert np.array_equal(first.fitness, direct) and (first.evaluations, first.unique) == (300, 300)
    assert_same_usage(first.usage, problem.usage(codons))
    codons[:100] = rng.integers(0, 256, size=(100, 32))  # a next generation: 100 new genomes
    second = evaluate_cached(problem, codons, genes, cache, workspace)
    assert np.array_equal(second.fitness, problem.evaluate(codons, genes).fitness)
    assert (second.evaluations, second.unique) == (100, 400) and np.isfinite(second.fitness).any()
    assert_same_usage(second.usage, problem.usage(codons))  # the 300 old ones from the cache


def assert_same_usage(got: Usage, expected: Usage) -> None:
    assert np.array_equal(got.codons, expected.codons) and np.array_equal(got.rows, expected.rows)
    assert np.array_equal(got.element_codons, expected.element_codons)
