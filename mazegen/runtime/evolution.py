"""The evolution loop of one run: evaluate, record statistics, breed; the population size stays constant."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from time import perf_counter

import numpy as np

from mazegen.runtime import operators as ops
from mazegen.runtime.cache import EvaluationCache, genome_hashes
from mazegen.runtime.problem import Problem
from mazegen.spec import Evolution


@dataclass(frozen=True)
class GenerationStats:
    """One row of ``stats.csv``. Best, mean and median cover valid individuals only."""

    generation: int
    evaluations: int
    best: float
    mean: float
    median: float
    invalid: int
    unique: int
    cache_hits: int
    seconds: float


@dataclass(frozen=True)
class RunResult:
    """The final population of a run and its per-generation statistics."""

    codons: np.ndarray
    genes: np.ndarray
    fitness: np.ndarray
    stats: tuple[GenerationStats, ...]


def evaluate_cached(
    problem: Problem, codons: np.ndarray, genes: np.ndarray, cache: EvaluationCache
) -> tuple[np.ndarray, int, int]:
    """Fitness of a generation, evaluating each distinct unseen genome once.

    Returns:
        fitness per individual, number of genomes evaluated, number of distinct genomes.
    """
    hashes = genome_hashes(codons, genes)
    unique, first, inverse = np.unique(hashes, return_index=True, return_inverse=True)
    found, cached = cache.lookup(unique)
    fitness_unique = np.where(found, cached, 0.0)
    todo = first[~found]
    if todo.size:
        fitness_unique[~found] = problem.evaluate(codons[todo], genes[todo]).fitness
    cache.remember(unique, fitness_unique)
    return fitness_unique[inverse.reshape(-1)], int(todo.size), int(unique.size)


def breed(
    rng: np.random.Generator, codons: np.ndarray, genes: np.ndarray, fitness: np.ndarray, settings: Evolution
) -> tuple[np.ndarray, np.ndarray]:
    """The next generation: elites unchanged, then selected, crossed and mutated children."""
    elites = ops.ranking(fitness)[: settings.elitism]
    count = fitness.shape[0] - elites.size
    if settings.selection == "tournament":
        parents = ops.tournament_parents(rng, fitness, settings.tournament, count)
    else:
        parents = ops.truncation_parents(rng, fitness, settings.truncation, count)
    children = ops.one_point_crossover(rng, codons[parents], genes[parents], settings.crossover)
    child_codons, child_genes = ops.int_flip_mutation(rng, *children, settings.mutation, settings.codon_max)
    return np.concatenate([codons[elites], child_codons]), np.concatenate([genes[elites], child_genes])


def _summary(
    generation: int, fitness: np.ndarray, evaluations: int, unique: int, seconds: float
) -> GenerationStats:
    valid = fitness[np.isfinite(fitness)]
    best, mean, median = (
        (float(valid.max()), float(valid.mean()), float(np.median(valid)))
        if valid.size
        else (float("nan"),) * 3
    )
    return GenerationStats(
        generation,
        evaluations,
        best,
        mean,
        median,
        int(fitness.size - valid.size),
        unique,
        int(fitness.size - evaluations),
        seconds,
    )


def evolve(
    problem: Problem,
    settings: Evolution,
    rng: np.random.Generator,
    *,
    on_generation: Callable[[GenerationStats], None] | None = None,
) -> RunResult:
    """Run one evolution from a random population.

    Args:
        problem: The experiment to evaluate genomes with.
        settings: Population size, generations, operators and rates.
        rng: The run's only source of randomness.
        on_generation: Called with each generation's statistics (progress reporting).
    """
    codons = ops.random_codons(rng, settings.population, settings.genome, settings.codon_max)
    genes = ops.random_genes(rng, settings.population, problem.slots)
    cache = EvaluationCache()
    stats: list[GenerationStats] = []
    for generation in range(settings.generations + 1):
        started = perf_counter()
        fitness, evaluations, unique = evaluate_cached(problem, codons, genes, cache)
        last = generation == settings.generations
        if not last:
            next_codons, next_genes = breed(rng, codons, genes, fitness, settings)
        row = _summary(generation, fitness, evaluations, unique, perf_counter() - started)
        stats.append(row)
        if on_generation is not None:
            on_generation(row)
        if last:
            break
        codons, genes = next_codons, next_genes
    return RunResult(codons, genes, fitness, tuple(stats))
