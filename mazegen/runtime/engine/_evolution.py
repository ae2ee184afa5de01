"""The evolution loop of one run: evaluate, record statistics, breed; the population size stays constant."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from time import perf_counter
from typing import Any

import numpy as np

import mazegen.runtime.engine._operators as ops
from mazegen.runtime.engine._breeding import breed
from mazegen.runtime.engine._cache import EvaluationCache, genome_hashes
from mazegen.runtime.engine._problem import Problem, Workspace
from mazegen.runtime.engine._used_operators import Usage
from mazegen.runtime.threads import threads_for
from mazegen.spec import Evolution

EVALUATION_CHUNK = 8192
"""Genomes evaluated per call: bounds the memory of the mapping and placement arrays
(which grow with the element slots) whatever the population, and keeps them in cache."""


@dataclass(frozen=True)
class GenerationStats:
    """Statistics of one generation. Best, mean and median cover valid individuals only.

    ``seconds`` is the wall-clock time to breed and evaluate the generation; it goes to
    ``timing.csv``, the other fields to ``stats.csv``.
    """

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
class RunState:
    """Where a run stands once generation ``generation`` is evaluated: what a checkpoint holds.

    Attributes:
        generation: The last generation evaluated (0 is the random population).
        codons: That generation's structure codons.
        genes: That generation's placement genes.
        fitness: That generation's fitness.
        rng_state: The run's bit-generator state, from which the next generation is bred.
        stats: Statistics of generations 0 .. ``generation``.
    """

    generation: int
    codons: np.ndarray
    genes: np.ndarray
    fitness: np.ndarray
    rng_state: Mapping[str, Any]
    stats: tuple[GenerationStats, ...]


@dataclass(frozen=True)
class RunResult:
    """The final population of a run and its per-generation statistics."""

    codons: np.ndarray
    genes: np.ndarray
    fitness: np.ndarray
    stats: tuple[GenerationStats, ...]


@dataclass(frozen=True)
class CachedEvaluation:
    """What evaluating a generation through the cache gives, per individual and in all.

    Attributes:
        fitness: ``float64[N]``.
        usage: How much of each genome its mapping read (the operators within it breed from this).
        evaluations: Genomes evaluated (neither cached nor repeated in the generation).
        unique: Distinct genomes in the generation.
    """

    fitness: np.ndarray
    usage: Usage
    evaluations: int
    unique: int


def evaluate_cached(
    problem: Problem,
    codons: np.ndarray,
    genes: np.ndarray,
    cache: EvaluationCache,
    workspace: Workspace | None = None,
) -> CachedEvaluation:
    """Fitness and usage of a generation, evaluating each distinct unseen genome once (into ``workspace``)."""
    lookup = cache.lookup(genome_hashes(codons, genes))
    fitness = lookup.fitness
    usage = Usage.empty(codons.shape[0], problem.slots)
    cache.recall_usage(lookup, usage)
    for start in range(0, lookup.todo.size, EVALUATION_CHUNK):
        rows = lookup.todo[start : start + EVALUATION_CHUNK]
        evaluation = problem.evaluate(*_rows_of(codons, genes, rows), workspace, searching=True)
        fitness[rows] = evaluation.fitness
        usage.put_mapped(rows, evaluation.mapped, codons.shape[1])
    fitness = fitness[lookup.first]
    usage.spread(lookup.first)
    cache.remember(lookup, fitness, usage)
    return CachedEvaluation(fitness, usage, int(lookup.todo.size), lookup.distinct)


def _rows_of(codons: np.ndarray, genes: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows ``rows`` (ascending) of both chromosomes: the arrays themselves when they are every row."""
    if rows.size == codons.shape[0]:
        return codons, genes
    return np.take(codons, rows, axis=0), np.take(genes, rows, axis=0)


def _median(values: np.ndarray) -> float:
    """``np.median`` of finite ``values``, without its checks and copies (a tenth of its time at 1,000)."""
    middle = values.size // 2
    if values.size % 2:
        return float(np.partition(values, middle)[middle])
    low, high = np.partition(values, [middle - 1, middle])[middle - 1 : middle + 1]
    return float((low + high) / 2)


def generation_stats(
    generation: int, fitness: np.ndarray, evaluations: int, unique: int, seconds: float
) -> GenerationStats:
    """Statistics of one generation's fitness (valid individuals only) and evaluation counts."""
    valid = fitness[np.isfinite(fitness)]
    best, mean, median = (
        (float(valid.max()), float(valid.mean()), _median(valid)) if valid.size else (float("nan"),) * 3
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


def primed_cache(codons: np.ndarray, genes: np.ndarray, fitness: np.ndarray, usage: Usage) -> EvaluationCache:
    """The evaluation cache as it stands after evaluating a generation.

    The cache holds only the last generation: its table depends on that generation's
    genome hashes alone, so a resumed run rebuilt this way counts the same evaluations
    and cache hits as one that never stopped.
    """
    cache = EvaluationCache()
    cache.remember(cache.lookup(genome_hashes(codons, genes)), fitness, usage)
    return cache


def evolve(
    problem: Problem,
    settings: Evolution,
    rng: np.random.Generator,
    *,
    resume: RunState | None = None,
    on_generation: Callable[[RunState], None] | None = None,
    waited: float = 0.0,
) -> RunResult:
    """Run one evolution from a random population, or on from a saved state.

    Args:
        problem: The experiment to evaluate genomes with.
        settings: Population size, generations, operators and rates.
        rng: The run's only source of randomness; a resumed run restores its state.
        resume: Where an earlier, interrupted evolution stood (from a checkpoint).
        on_generation: Called with the state after each generation is evaluated, before
            the next is bred (progress, checkpoints). Its arrays are valid during the call
            only; an exception it raises stops the run.
        waited: Seconds spent for the run before it started (its kernels compiled ahead), which the
            time of generation 0 counts.
    """
    with threads_for(settings.population):
        return _evolve(problem, settings, rng, resume, on_generation or (lambda state: None), waited)


def _evolve(
    problem: Problem,
    settings: Evolution,
    rng: np.random.Generator,
    resume: RunState | None,
    on_generation: Callable[[RunState], None],
    waited: float,
) -> RunResult:
    workspace = Workspace()
    started = perf_counter() - waited
    if resume is None:
        codons = ops.random_codons(rng, settings.population, settings.genome, settings.codon_max)
        genes = ops.random_genes(rng, settings.population, problem.slots)
        cache = EvaluationCache()
        evaluated = evaluate_cached(problem, codons, genes, cache, workspace)
        fitness, usage = evaluated.fitness, evaluated.usage
        stats = [_stats(0, evaluated, started)]
        on_generation(RunState(0, codons, genes, fitness, rng.bit_generator.state, tuple(stats)))
    else:
        rng.bit_generator.state = resume.rng_state
        codons, genes, fitness = resume.codons.copy(), resume.genes.copy(), resume.fitness.copy()
        usage = problem.usage(codons)
        cache = primed_cache(codons, genes, fitness, usage)
        stats = list(resume.stats)
    spare = (np.empty_like(codons), np.empty_like(genes))  # the next generation is bred into these
    for generation in range(len(stats), settings.generations + 1):
        started = perf_counter()
        breed(rng, codons, genes, fitness, settings, spare, usage, problem.usage)
        spare, (codons, genes) = (codons, genes), spare
        evaluated = evaluate_cached(problem, codons, genes, cache, workspace)
        fitness, usage = evaluated.fitness, evaluated.usage
        stats.append(_stats(generation, evaluated, started))
        on_generation(RunState(generation, codons, genes, fitness, rng.bit_generator.state, tuple(stats)))
    return RunResult(codons, genes, fitness, tuple(stats))


def _stats(generation: int, evaluated: CachedEvaluation, started: float) -> GenerationStats:
    return generation_stats(
        generation, evaluated.fitness, evaluated.evaluations, evaluated.unique, perf_counter() - started
    )
