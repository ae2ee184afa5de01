"""Scenario documents of evolved genomes: the best distinct scenarios of a final population."""

from __future__ import annotations

from typing import Any

import numpy as np

from mazegen.runtime.documents._scenario import scenario_document, scenario_key
from mazegen.runtime.engine import Evaluation, Problem, RunResult, phenotype, ranking
from mazegen.runtime.threads import threads_for


def best_documents(
    problem: Problem, result: RunResult, *, count: int, origin: dict[str, Any]
) -> tuple[dict[str, Any], ...]:
    """The ``count`` best distinct valid scenarios of a final population, best first."""
    # A few scenarios run on one thread, as small populations do (threads_for): measured on 2 cores,
    # waking the second thread made the survey of ten floors 10 ms instead of 0.6 ms.
    with threads_for(count):
        chosen = best_distinct(problem, result, count)
        codons, genes = result.codons[chosen], result.genes[chosen]
        # Evaluated again on their own: the documents' metrics survey these scenarios alone.
        evaluation = problem.evaluate(codons, genes)
        return tuple(
            row_document(problem, evaluation, row, codons[row], genes[row], {**origin, "rank": row + 1})
            for row in range(chosen.size)
        )


def best_distinct(problem: Problem, result: RunResult, count: int) -> np.ndarray:
    """Rows of the ``count`` best valid individuals of a final population whose scenarios differ
    (:func:`scenario_key`), best first."""
    ranked = ranking(result.fitness)
    ranked = ranked[np.isfinite(result.fitness[ranked])]
    chosen: list[int] = []
    seen: set[bytes] = set()
    # Candidates are decoded a batch at a time; most batches hold enough distinct scenarios.
    batch = max(4 * count, 64)
    for start in range(0, ranked.size, batch):
        rows = ranked[start : start + batch]
        _, population = problem.decode(result.codons[rows], result.genes[rows])
        for row in range(rows.size):
            key = scenario_key(population, row)
            if key not in seen:
                seen.add(key)
                chosen.append(int(rows[row]))
                if len(chosen) == count:
                    return np.array(chosen, dtype=np.int64)
    return np.array(chosen, dtype=np.int64)


def row_document(
    problem: Problem,
    evaluation: Evaluation,
    row: int,
    codons: np.ndarray,
    genes: np.ndarray,
    origin: dict[str, Any],
) -> dict[str, Any]:
    """The scenario document of row ``row`` of an evaluation, its genome recorded in ``origin``."""
    settings = problem.spec.evolution
    return scenario_document(
        problem.spec,
        evaluation.population,
        row,
        phenotype=phenotype(problem.grammar, codons.tolist(), wraps=settings.wraps, consume=settings.consume),
        fitness=float(evaluation.fitness[row]),
        terms={name: float(values[row]) for name, values in evaluation.terms.items()},
        origin={**origin, "codons": codons.tolist(), "placement": genes.tolist()},
    )
