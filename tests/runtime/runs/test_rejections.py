"""Why individuals are invalid: mapping, each reject term, counted over a generation."""

from __future__ import annotations

import numpy as np

import mazegen
from mazegen.runtime import metrics
from mazegen.runtime.engine._mapping import extract_elements, map_genome
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._problem import REJECTED, Problem
from mazegen.runtime.runs._rejections import EXHAUSTED, OVERFLOW, rejection_causes

SPEC = """
element block { shape square size 20..40 }
arena small { size 300 x 300 cm  start (30, 30)  goal (270, 270)  robot radius 10 }
scenario blocks on small { elements block  grammar nested  max elements 3 }
fitness { count  overlap reject  outside reject }
evolution { population 400  genome 12 }
"""


def built(tmp_path, write_spec) -> Problem:
    mazegen.build(mazegen.load(write_spec(SPEC)), tmp_path / "build")
    return Problem.from_build_dir(tmp_path / "build")


def generation(problem: Problem) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(4)
    settings = problem.spec.evolution
    return (
        random_codons(rng, settings.population, settings.genome, settings.codon_max),
        random_genes(rng, settings.population, problem.slots),
    )


def test_each_cause_counts_the_individuals_it_makes_invalid(tmp_path, write_spec):
    problem = built(tmp_path, write_spec)
    codons, genes = generation(problem)
    causes = {cause.key: cause.count for cause in rejection_causes(problem, codons, genes)}
    # Mapping, by the reference mapper: genomes that end mid-derivation, and those deriving
    # more elements than the 3 slots.
    mapped = [map_genome(problem.grammar, row.tolist()) for row in codons]
    exhausted = sum(not result.valid for result in mapped)
    over = sum(
        result.valid and len(extract_elements(result.phenotype or "", ["block"])) > 3 for result in mapped
    )
    assert causes[EXHAUSTED] == exhausted > 0 and causes[OVERFLOW] == over > 0
    # Each reject term, among the individuals that map to a scenario.
    for key, values in verdicts(problem, codons, genes).items():
        assert causes[key] == np.count_nonzero(values) > 0


def verdicts(problem: Problem, codons: np.ndarray, genes: np.ndarray) -> dict[str, np.ndarray]:
    _, population = problem.decode(codons, genes)
    return {
        "overlap": population.valid & (metrics.overlapping_pairs(population) > 0),
        "outside": population.valid & (metrics.elements_outside(population) > 0),
    }


def test_a_fitness_module_without_rejections_gives_one_verdict(tmp_path, write_spec):
    problem = built(tmp_path, write_spec)
    codons, genes = generation(problem)
    fitness = tmp_path / "build" / "fitness.py"
    text = fitness.read_text()
    start, end = text.index("def rejections"), text.index("def rejected")
    body = "    return (metrics.overlapping_pairs(pop) > 0) | (metrics.elements_outside(pop) > 0)\n"
    fitness.write_text(text[:start] + text[end:].split("    reject = ")[0] + body)  # as generated before
    older = Problem.from_build_dir(fitness.parent)
    causes = {cause.key: cause.count for cause in rejection_causes(older, codons, genes)}
    assert set(causes) == {EXHAUSTED, OVERFLOW, REJECTED}
    either = verdicts(problem, codons, genes)
    assert causes[REJECTED] == np.count_nonzero(either["overlap"] | either["outside"])
