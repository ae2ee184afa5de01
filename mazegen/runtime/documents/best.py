"""Scenario documents of evolved genomes: the best distinct scenarios of a final population."""

from __future__ import annotations

from typing import Any

import numpy as np

from mazegen.runtime.documents.scenario import scenario_document, scenario_key
from mazegen.runtime.engine.evolution import RunResult
from mazegen.runtime.engine.mapping import phenotype
from mazegen.runtime.engine.operators import ranking
from mazegen.runtime.engine.problem import Evaluation, Problem


def best_documents(
    problem: Problem, result: RunResult, *, count: int, origin: dict[str, Any]
) -> tuple[dict[str, Any], ...]:
    """The ``count`` best distinct valid scenarios of a final population, best first."""
    ranked = ranking(result.fitness)
    ranked = ranked[np.isfinite(result.fitness[ranked])]
    documents: list[dict[str, Any]] = []
    seen: set[bytes] = set()
    # Candidates are evaluated a batch at a time; most batches hold enough distinct scenarios.
    batch = max(4 * count, 64)
    for start in range(0, ranked.size, batch):
        chosen = ranked[start : start + batch]
        codons, genes = result.codons[chosen], result.genes[chosen]
        evaluation = problem.evaluate(codons, genes)
        for row in range(chosen.size):
            key = scenario_key(evaluation.population, row)
            if key in seen:
                continue
            seen.add(key)
            extra = {**origin, "rank": len(documents) + 1}
            documents.append(row_document(problem, evaluation, row, codons[row], genes[row], extra))
            if len(documents) == count:
                return tuple(documents)
    return tuple(documents)


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
