"""Evolution runs: constant population, elitism, caching, reproducibility, every example runs."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import mazegen
from mazegen.runtime.engine._evolution import evolve, generation_stats
from tests.conftest import EXAMPLES
from tests.runtime.rundirs import file_digests

ALL_EXAMPLES = sorted(EXAMPLES.glob("*.maze")) + sorted((EXAMPLES / "table1").glob("exp*.maze"))


def test_population_size_stays_constant_and_best_never_drops(factory):
    settings = factory.spec.evolution.__class__(population=150, generations=6, elitism=2)
    result = evolve(factory, settings, np.random.default_rng(1))
    assert result.codons.shape == (150, settings.genome)
    assert result.genes.shape == (150, factory.slots, 5)
    bests = [row.best for row in result.stats]
    assert len(result.stats) == 7
    assert all(b2 >= b1 for b1, b2 in itertools.pairwise(bests))
    assert bests[-1] > bests[0]
    assert all(row.cache_hits >= 2 for row in result.stats[1:])  # the elites are not evaluated again
    assert all(row.evaluations + row.cache_hits == 150 for row in result.stats)


def test_final_fitness_matches_a_fresh_evaluation(factory):
    settings = factory.spec.evolution.__class__(population=80, generations=3)
    result = evolve(factory, settings, np.random.default_rng(2))
    fresh = factory.evaluate(result.codons, result.genes).fitness
    assert np.array_equal(fresh, result.fitness)


@pytest.mark.parametrize("size", [1, 2, 7, 8, 1000, 1001])
def test_generation_stats_equal_numpy_over_valid_individuals(size):
    """Best, mean and median of the finite fitness values, as NumPy computes them (ties, odd and even
    counts); invalid individuals are counted, not averaged."""
    rng = np.random.default_rng(size)
    fitness = rng.integers(0, 9, size + 3).astype(float) + rng.random(size + 3).round(1)
    fitness[rng.permutation(size + 3)[:3]] = -np.inf
    valid = fitness[np.isfinite(fitness)]
    stats = generation_stats(4, fitness, evaluations=size, unique=size + 1, seconds=0.5)
    assert (stats.best, stats.mean, stats.median) == (valid.max(), valid.mean(), np.median(valid))
    assert (stats.invalid, stats.cache_hits) == (3, 3)


def test_thread_count_does_not_change_results(factory):
    """5,000 individuals run on every thread; forced onto one, the run is identical."""
    from mazegen.runtime.threads import CORES, PARALLEL_FROM, threads

    settings = factory.spec.evolution.__class__(population=PARALLEL_FROM + 904, generations=3)
    with threads(CORES):
        parallel = evolve(factory, settings, np.random.default_rng(9))
    with threads(1):
        serial = evolve(factory, settings, np.random.default_rng(9))
    assert np.array_equal(parallel.codons, serial.codons) and np.array_equal(parallel.genes, serial.genes)
    assert np.array_equal(parallel.fitness, serial.fitness)
    assert [r.best for r in parallel.stats] == [r.best for r in serial.stats]


def test_same_seed_same_bytes_other_seed_other_scenarios(tmp_path):
    spec = EXAMPLES / "factory.maze"
    runs = {}
    for name, seed in (("a", 4), ("b", 4), ("c", 5)):
        mazegen.run(
            spec, seed=seed, runs=2, population=100, generations=4, out_dir=tmp_path / name, catalog=False
        )
        runs[name] = tmp_path / name
    assert file_digests(runs["a"]) == file_digests(runs["b"])
    assert (runs["a"] / "run-01" / "best-01.json").read_bytes() != (
        runs["c"] / "run-01" / "best-01.json"
    ).read_bytes()
    assert (runs["a"] / "run-01" / "best-01.json").read_bytes() != (
        runs["a"] / "run-02" / "best-01.json"
    ).read_bytes()


@pytest.mark.parametrize("example", ALL_EXAMPLES, ids=lambda p: str(p.relative_to(EXAMPLES)))
def test_every_example_runs(example):
    result = mazegen.run(example, runs=1, population=60, generations=2)
    documents = result.best[0]
    assert documents, "no valid scenario"
    top = documents[0]
    assert top["valid"] and top["fitness"] == max(d["fitness"] for d in documents)
    assert len(top["elements"]) >= 1
    names = set(mazegen.load(example).scenario.elements)
    assert {e["type"] for e in top["elements"]} <= names
