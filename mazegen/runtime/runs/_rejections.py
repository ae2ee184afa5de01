"""Why a run found no valid scenario: what share of its final generation each cause made invalid.

Worked out only when a run ends without a valid scenario, from its final population in the
run directory: the generation is mapped and scored again, and each reject term's verdict
asked of the fitness module's ``rejections``. An individual rejected by several terms
counts under each; one that maps to no scenario counts as invalid only.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mazegen.fitness_terms import term_kind
from mazegen.runtime.engine import EVALUATION_CHUNK
from mazegen.runtime.engine import REJECTED, Problem
from mazegen.runtime.documents import RunDirectory
from mazegen.spec import Spec

EXHAUSTED, OVERFLOW, NOT_FINITE = "exhausted", "overflow", "not finite"
"""The causes that are no reject term's."""


@dataclass(frozen=True)
class Cause:
    """One reason individuals were invalid, and how many of them it made so."""

    key: str
    count: int


def rejection_causes(problem: Problem, codons: np.ndarray, genes: np.ndarray) -> list[Cause]:
    """The causes that made individuals of a generation invalid, most basic first: mapping, then
    each reject term in the spec's order, then a fitness that is not a number."""
    settings = problem.spec.evolution
    codon_limit = codons.shape[1] * (settings.wraps + 1)  # PonyGE2's mapping stops at the end, too
    counts: dict[str, int] = {}

    def tally(key: str, chosen: np.ndarray) -> None:
        counts[key] = counts.get(key, 0) + int(np.count_nonzero(chosen))

    for start in range(0, codons.shape[0], EVALUATION_CHUNK):
        rows = slice(start, start + EVALUATION_CHUNK)
        mapped, population = problem.decode(codons[rows], genes[rows])
        fitness, _ = problem.score(population)
        mapped_ok = mapped.valid
        exhausted = ~mapped_ok & (mapped.used_codons >= codon_limit)
        tally(EXHAUSTED, exhausted)
        tally(OVERFLOW, ~mapped_ok & ~exhausted)
        rejected = np.zeros_like(mapped_ok)
        for key, verdict in problem.rejections(population).items():
            tally(key, verdict & mapped_ok)
            rejected |= verdict
        tally(NOT_FINITE, mapped_ok & ~rejected & ~np.isfinite(fitness))
    return [Cause(key, count) for key, count in counts.items() if count]


def why_no_scenario(run_dir: Path, run: int) -> list[str]:
    """Lines saying what made run ``run`` of ``run_dir`` end without a valid scenario: its final
    generation's size, then a line per cause (none when the run directory lacks the population)."""
    directory = RunDirectory(run_dir)
    population = directory.population(run)
    if not population.is_file():
        return []
    with np.load(population) as arrays:
        codons, genes = arrays["codons"], arrays["placement"]
    problem = Problem.from_build_dir(directory.build)
    causes = rejection_causes(problem, codons, genes)
    return [
        f"of its final generation's {codons.shape[0]} individuals,",
        *cause_lines(problem.spec, codons.shape[0], causes),
    ]


def cause_lines(spec: Spec, size: int, causes: list[Cause]) -> list[str]:
    """Indented lines, one per cause: the share of ``size`` individuals it made invalid, and why."""
    lines = []
    for cause in causes:
        share = 100 * cause.count / size
        shown = "<1" if 0 < share < 0.5 else f"{share:.0f}"
        lines.append(f"  {shown:>3} % {cause_text(spec, cause)}")
    return lines


def cause_text(spec: Spec, cause: Cause) -> str:
    """What a cause means, and what to try."""
    if cause.key == EXHAUSTED:
        return (
            "invalid: the genome ran out of codons before the derivation ended "
            "(try a longer genome or more wraps)"
        )
    if cause.key == OVERFLOW:
        return (
            f"invalid: the derivation made more elements than max elements ({spec.scenario.max_elements}) "
            "allows, or went too deep (raise max elements, or try a shorter genome)"
        )
    if cause.key == NOT_FINITE:
        return "no finite fitness: a term gave NaN or infinity (see fitness.py)"
    if cause.key == REJECTED:
        return "rejected by rejected(pop) of fitness.py"
    term = next((term for term in spec.fitness if term.reject and term.key == cause.key), None)
    if term is None:  # a verdict an edited fitness.py added
        return f"rejected by {cause.key} (fitness.py)"
    return f"rejected by {term_kind(term).words(term)}: {term_kind(term).rejects}"
