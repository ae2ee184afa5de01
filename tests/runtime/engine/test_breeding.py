"""The compiled breeding step against the operators applied one at a time, drawing from the same
generator: same children, and the generator left in the same state."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest

from mazegen.runtime.engine import _operators as ops
from mazegen.runtime.engine import _used_operators as uo
from mazegen.runtime.engine._breeding import breed, make_children
from mazegen.spec import CROSSOVER_OPERATORS, MUTATION_OPERATORS, Evolution

OPERATORS = list(itertools.product(CROSSOVER_OPERATORS, MUTATION_OPERATORS))


def reference_children(draw, codons, genes, parents, settings, usage, map_usage):
    """The children of ``parents`` bred one operator at a time (crossover draws, then the
    whole-genome mutation's, or the crossed children mapped and the mutation within their use)."""
    count, length, slots = parents.size, codons.shape[1], genes.shape[1]
    out = (np.empty((count, length), codons.dtype), np.empty((count, *genes.shape[1:]), genes.dtype))
    if settings.crossover_operator == "onepoint within genome":
        crossover = ops.crossover_draws(draw, count, length, slots, settings.crossover)
        ops.cross(codons, genes, parents, crossover, *out)
    else:
        variable = settings.crossover_operator == "variable within used"
        cuts = uo.cut_draws(draw, used=usage.codons[parents], rate=settings.crossover, variable=variable)
        uo.splice_children(codons, genes, parents, cuts, usage, out)
    if settings.mutation_operator == "within genome":
        mutation = ops.mutation_draws(draw, count, length, slots, settings.mutation, settings.codon_max)
    else:
        mutation = uo.used_mutation_draws(
            draw,
            usage=map_usage(out[0]),
            length=length,
            slots=slots,
            rate=settings.mutation,
            codon_max=settings.codon_max,
        )
    ops.mutate(mutation, *out)
    return out


def reference_breed(draw, codons, genes, fitness, settings, usage, map_usage):
    elites = ops.ranking(fitness, settings.elitism)
    count = fitness.size - elites.size
    if settings.selection == "tournament":
        parents = ops.tournament_parents(draw, fitness, settings.tournament, count)
    else:
        parents = ops.truncation_parents(draw, fitness, settings.truncation, count)
    children = reference_children(draw, codons, genes, parents, settings, usage, map_usage)
    return np.concatenate([codons[elites], children[0]]), np.concatenate([genes[elites], children[1]])


def population(problem, seed, count, codon_max=255):
    draw = np.random.default_rng(seed)
    codons = ops.random_codons(draw, count, problem.spec.evolution.genome, codon_max)
    genes = ops.random_genes(draw, count, problem.slots)
    return codons, genes, problem.evaluate(codons, genes).fitness


@pytest.mark.parametrize(("crossover", "mutation"), OPERATORS)
@pytest.mark.parametrize(
    ("selection", "count", "elitism"), [("tournament", 301, 1), ("truncation", 200, 0), ("tournament", 64, 5)]
)
def test_breeding_equals_the_operators_one_at_a_time(factory, crossover, mutation, selection, count, elitism):
    settings = dataclasses.replace(
        factory.spec.evolution,
        selection=selection,
        elitism=elitism,
        crossover_operator=crossover,
        mutation_operator=mutation,
        mutation=0.2,
    )
    codons, genes, fitness = population(factory, count, count)
    usage = factory.usage(codons)
    out = (np.empty_like(codons), np.empty_like(genes))
    draw, reference_draw = np.random.default_rng(count), np.random.default_rng(count)
    breed(draw, codons, genes, fitness, settings, out, usage, factory.usage)
    expected = reference_breed(reference_draw, codons, genes, fitness, settings, usage, factory.usage)
    assert np.array_equal(out[0], expected[0]) and np.array_equal(out[1], expected[1])
    assert draw.bit_generator.state == reference_draw.bit_generator.state


@pytest.mark.parametrize(("crossover", "mutation"), OPERATORS)
def test_children_of_given_parents_equal_the_operators_one_at_a_time(factory, crossover, mutation):
    settings = dataclasses.replace(
        factory.spec.evolution, crossover_operator=crossover, mutation_operator=mutation, codon_max=1000
    )
    codons, genes, _ = population(factory, 3, 150, codon_max=1000)
    parents = np.random.default_rng(4).integers(0, 150, size=97)
    out = (np.empty((97, codons.shape[1]), codons.dtype), np.empty((97, *genes.shape[1:]), genes.dtype))
    draw, reference_draw = np.random.default_rng(5), np.random.default_rng(5)
    make_children(draw, codons, genes, parents, settings, out, map_usage=factory.usage)
    usage = factory.usage(codons)
    expected = reference_children(reference_draw, codons, genes, parents, settings, usage, factory.usage)
    assert np.array_equal(out[0], expected[0]) and np.array_equal(out[1], expected[1])
    assert draw.bit_generator.state == reference_draw.bit_generator.state


def test_breeding_without_the_usage_it_needs_draws_nothing():
    settings = dataclasses.replace(Evolution(population=4, genome=8), mutation_operator="within used")
    codons = ops.random_codons(np.random.default_rng(), 4, 8, 255)
    genes = ops.random_genes(np.random.default_rng(), 4, 2)
    draw = np.random.default_rng(1)
    before = draw.bit_generator.state
    with pytest.raises(ValueError, match="usage"):
        breed(draw, codons, genes, np.zeros(4), settings, (np.empty_like(codons), np.empty_like(genes)))
    assert draw.bit_generator.state == before


def test_children_are_not_written_into_a_copy():
    settings = Evolution(population=4, genome=8, crossover_operator="onepoint within genome")
    codons = ops.random_codons(np.random.default_rng(), 4, 8, 255)
    genes = ops.random_genes(np.random.default_rng(), 4, 2)
    strided = (np.empty((4, 16), codons.dtype)[:, ::2], np.empty_like(genes))
    with pytest.raises(ValueError, match="C-contiguous"):
        breed(np.random.default_rng(), codons, genes, np.zeros(4), settings, strided)
