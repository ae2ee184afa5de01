"""Operators within the used codons against PonyGE2's definitions, written out in plain NumPy and
Python lists and drawing the same random numbers; placement rows follow the element slots."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mazegen.runtime.engine import _operators as ops
from mazegen.runtime.engine import _used_operators as uo
from mazegen.runtime.engine._breeding import breed
from mazegen.runtime.engine._evolution import evolve
from mazegen.runtime.engine._mapping import NO_ELEMENT
from mazegen.runtime.engine._placement import GENE_MAX
from mazegen.spec import CROSSOVER_OPERATORS, MUTATION_OPERATORS, Evolution

LENGTH, SLOTS = 12, 4


def rng(seed: int = 0) -> np.random.Generator:
    return np.random.default_rng(seed)


def random_usage(seed: int, count: int, length: int = LENGTH, slots: int = SLOTS) -> uo.Usage:
    """Used codons in 0..length (0: a lazy mapping that read none) and elements complete in codon order."""
    draw = rng(seed)
    used = draw.integers(0, length + 1, size=count)
    rows = draw.integers(0, slots + 1, size=count)
    element_codons = np.full((count, slots), NO_ELEMENT, dtype=np.int32)
    for i in range(count):
        element_codons[i, : rows[i]] = np.sort(draw.integers(0, used[i] + 1, size=rows[i]))
    return uo.Usage(used, rows, element_codons)


def ponyge2_children(first, second, first_cut, second_cut):
    """PonyGE2's one-point crossover of two genomes (lists), then fitted to the width: cut at it when
    longer, and where shorter the first parent's own values fill the rest."""
    width = len(first)
    child = (first[:first_cut] + second[second_cut:])[:width]
    return child + first[len(child) :]


def elements_within(element_codons, cut):
    return int(np.sum(element_codons <= cut))


def reference_splice(codons, genes, parents, cuts, usage):
    """Each pair's children as lists, PonyGE2's way; placement rows spliced at the element slots."""
    out_codons, out_genes = codons[parents].copy(), genes[parents].copy()
    for p in range(parents.size // 2):
        a, b = parents[2 * p], parents[2 * p + 1]
        if not cuts.crossing[p]:
            continue
        cut_a, cut_b = int(cuts.first_cut[p]), int(cuts.second_cut[p])
        rows_a = elements_within(usage.element_codons[a], cut_a)
        rows_b = elements_within(usage.element_codons[b], cut_b)
        codons_a, codons_b = codons[a].tolist(), codons[b].tolist()
        out_codons[2 * p] = ponyge2_children(codons_a, codons_b, cut_a, cut_b)
        out_codons[2 * p + 1] = ponyge2_children(codons_b, codons_a, cut_b, cut_a)
        genes_a, genes_b = genes[a].tolist(), genes[b].tolist()
        out_genes[2 * p] = ponyge2_children(genes_a, genes_b, rows_a, rows_b)
        out_genes[2 * p + 1] = ponyge2_children(genes_b, genes_a, rows_b, rows_a)
    return out_codons, out_genes


def reference_cuts(draw, parents, usage, rate, variable):
    """PonyGE2's ``randint(1, used)`` per parent (variable) or ``randint(1, min(used))`` (one-point)."""
    pairs = parents.size // 2
    used = [max(1, int(usage.codons[i])) for i in parents[: 2 * pairs]]
    crossing = draw.random(pairs) < rate
    if variable:
        first = np.array([draw.integers(1, used[2 * p] + 1) for p in range(pairs)], dtype=np.int64)
        second = np.array([draw.integers(1, used[2 * p + 1] + 1) for p in range(pairs)], dtype=np.int64)
        return uo.CutDraws(crossing, first, second)
    cut = np.array([draw.integers(1, min(used[2 * p : 2 * p + 2]) + 1) for p in range(pairs)], dtype=np.int64)
    return uo.CutDraws(crossing, cut, cut)


@pytest.mark.parametrize("variable", [False, True])
@pytest.mark.parametrize("seed", range(4))
def test_within_used_crossover_never_cuts_past_either_parents_used_length(variable, seed):
    usage = random_usage(seed, 300)
    parents = rng(seed + 10).integers(0, 300, size=2001)
    cuts = uo.cut_draws(rng(seed), used=usage.codons[parents], rate=0.9, variable=variable)
    used = np.maximum(usage.codons, 1)
    first, second = parents[0:2000:2], parents[1:2000:2]
    assert (cuts.first_cut >= 1).all() and (cuts.second_cut >= 1).all()
    assert (cuts.first_cut <= used[first]).all() and (cuts.second_cut <= used[second]).all()
    if not variable:
        assert (cuts.first_cut == cuts.second_cut).all()
    else:
        assert (cuts.first_cut != cuts.second_cut).any()
    assert (cuts.first_cut == used[first]).any()  # the whole used range is reached
    assert 0.85 < cuts.crossing.mean() < 0.95


@pytest.mark.parametrize("variable", [False, True])
@pytest.mark.parametrize(
    ("population", "count", "rate"), [(40, 41, 0.9), (9, 8, 1.0), (30, 30, 0.0), (5, 1, 1.0)]
)
def test_crossover_equals_ponyge2s_definition(variable, population, count, rate):
    codons = ops.random_codons(rng(1), population, LENGTH, 255)
    genes = ops.random_genes(rng(2), population, SLOTS)
    usage = random_usage(3, population)
    parents = rng(4).integers(0, population, size=count)
    cuts = uo.cut_draws(rng(5), used=usage.codons[parents], rate=rate, variable=variable)
    expected_cuts = reference_cuts(rng(5), parents, usage, rate, variable)
    for name in ("crossing", "first_cut", "second_cut"):
        assert np.array_equal(getattr(cuts, name), getattr(expected_cuts, name)), name
    out = (np.full((count, LENGTH), -1, np.int32), np.zeros((count, SLOTS, 5), np.uint16))
    uo.splice_children(codons, genes, parents, cuts, usage, out)
    expected = reference_splice(codons, genes, parents, cuts, usage)
    assert np.array_equal(out[0], expected[0]) and np.array_equal(out[1], expected[1])


def test_a_shorter_variable_child_is_padded_with_its_first_parents_codons():
    codons = np.array([list(range(8)), list(range(10, 18))], dtype=np.int32)
    genes = np.zeros((2, 1, 5), np.uint16)
    usage = uo.Usage(np.array([8, 8]), np.array([0, 0]), np.full((2, 1), NO_ELEMENT, np.int32))
    cuts = uo.CutDraws(np.array([True]), np.array([2]), np.array([5]))
    out = (np.empty((2, 8), np.int32), np.empty((2, 1, 5), np.uint16))
    uo.splice_children(codons, genes, np.array([0, 1]), cuts, usage, out)
    assert out[0][0].tolist() == [0, 1, 15, 16, 17, 5, 6, 7]  # PonyGE2's child is [0, 1, 15, 16, 17]
    assert out[0][1].tolist() == [10, 11, 12, 13, 14, 2, 3, 4]  # and [10 .. 14, 2 .. 7] cut at 8


@pytest.mark.parametrize("variable", [False, True])
def test_a_childs_placement_rows_come_from_the_parent_its_element_slots_came_from(factory, variable):
    """The head's elements are the first parent's, with its placements; the next slots carry the
    second parent's rows from its first element past its cut, in order."""
    draw = rng(7)
    codons = ops.random_codons(draw, 400, factory.spec.evolution.genome, 255)
    genes = ops.random_genes(draw, 400, factory.slots)
    parents_map = factory.evaluate(codons, genes).mapped
    usage = factory.usage(codons)
    assert np.array_equal(usage.element_codons, parents_map.element_codons)
    parents = np.flatnonzero(parents_map.valid & (parents_map.n_elements >= 2))[:200]
    cuts = uo.cut_draws(draw, used=usage.codons[parents], rate=1.0, variable=variable)
    out = (
        np.empty((parents.size, codons.shape[1]), np.int32),
        np.empty((parents.size, factory.slots, 5), np.uint16),
    )
    uo.splice_children(codons, genes, parents, cuts, usage, out)
    children = factory.evaluate(*out)
    parents_placed = factory.evaluate(codons[parents], genes[parents]).population.params
    checked = 0
    for p in range(parents.size // 2):
        for head, tail, child, head_cut, tail_cut in (
            (2 * p, 2 * p + 1, 2 * p, cuts.first_cut[p], cuts.second_cut[p]),
            (2 * p + 1, 2 * p, 2 * p + 1, cuts.second_cut[p], cuts.first_cut[p]),
        ):
            kept = elements_within(usage.element_codons[parents[head]], head_cut)
            if children.mapped.valid[child]:
                ids = children.mapped.element_ids[child, :kept]
                assert np.array_equal(ids, parents_map.element_ids[parents[head], :kept])
                placed = children.population.params[child, :kept]
                assert np.array_equal(placed, parents_placed[head, :kept])
                checked += kept
            first_tail = elements_within(usage.element_codons[parents[tail]], tail_cut)
            taken = factory.slots - max(kept, first_tail)
            rows = out[1][child, kept : kept + taken]
            assert np.array_equal(rows, genes[parents[tail], first_tail : first_tail + taken])
    assert checked > 50


def test_element_codons_mark_the_prefix_that_derives_each_element(factory):
    """Any genome that keeps the first ``element_codons[k]`` codons derives the same first k+1 elements."""
    draw = rng(11)
    codons = ops.random_codons(draw, 300, factory.spec.evolution.genome, 255)
    usage = factory.usage(codons)
    mapped = factory.evaluate(codons, ops.random_genes(draw, 300, factory.slots)).mapped
    for i in np.flatnonzero(mapped.valid)[:60]:
        for k in range(mapped.n_elements[i]):
            keep = usage.element_codons[i, k]
            assert keep <= mapped.used_codons[i]
            variants = ops.random_codons(draw, 20, codons.shape[1], 255)
            variants[:, :keep] = codons[i, :keep]
            again = factory.usage(variants)
            complete = again.rows > k  # valid and with that many elements
            assert np.array_equal(
                again.element_codons[complete, : k + 1],
                np.broadcast_to(usage.element_codons[i, : k + 1], (complete.sum(), k + 1)),
            )


@pytest.mark.parametrize(("rate", "seed"), [(0.05, 0), (0.5, 1), (1.0, 2), (0.0, 3)])
def test_mutation_touches_only_used_codons_and_element_rows(rate, seed):
    usage = random_usage(seed, 500)
    codons = np.full((500, LENGTH), -1, np.int32)
    genes = np.zeros((500, SLOTS, 5), np.uint16)
    flips = uo.used_mutation_draws(rng(seed), usage=usage, length=LENGTH, slots=SLOTS, rate=rate, codon_max=7)
    ops.mutate(flips, codons, genes)
    columns, slots = np.arange(LENGTH)[None, :], np.arange(SLOTS)[None, :, None]
    used = columns < usage.codons[:, None]
    element_rows = np.broadcast_to(slots < usage.rows[:, None, None], genes.shape)
    assert (codons[~used] == -1).all() and (genes[~element_rows] == 0).all()
    touched = codons[used] >= 0
    assert codons.max() <= 7
    if rate == 1.0:
        assert touched.all()
    elif rate > 0:
        assert abs(touched.mean() - rate) < 0.05  # each used codon with probability rate
    else:
        assert not touched.any()


@pytest.mark.parametrize(("rate", "seed"), [(0.05, 0), (0.3, 1), (1.0, 2)])
def test_mutation_equals_ponyge2s_int_flip_per_codon_within_used(rate, seed):
    """The reference hits each position with probability ``rate`` (the same geometric draws), keeps
    those within the used part, and draws their values in order."""
    usage = random_usage(seed, 200)
    flips = uo.used_mutation_draws(
        rng(seed), usage=usage, length=LENGTH, slots=SLOTS, rate=rate, codon_max=255
    )
    draw = rng(seed)
    codon_hits = [
        h for h in ops.hit_positions(draw, 200 * LENGTH, rate) if h % LENGTH < usage.codons[h // LENGTH]
    ]
    codon_values = draw.integers(0, 255, size=len(codon_hits), dtype=np.uint8, endpoint=True)
    row = SLOTS * 5
    gene_hits = [h for h in ops.hit_positions(draw, 200 * row, rate) if h % row // 5 < usage.rows[h // row]]
    gene_values = draw.integers(0, GENE_MAX, size=len(gene_hits), dtype=np.uint16, endpoint=True)
    assert flips.codon_hits.tolist() == codon_hits and flips.codon_values.tolist() == codon_values.tolist()
    assert flips.gene_hits.tolist() == gene_hits and flips.gene_values.tolist() == gene_values.tolist()


def test_breeding_within_used_mutates_what_the_child_uses(factory):
    """PonyGE2 maps a crossed child before mutating it: the mutation follows the child's usage."""
    settings = dataclasses.replace(
        factory.spec.evolution, crossover_operator="onepoint within used", mutation_operator="within used"
    )
    settings = dataclasses.replace(settings, population=300, elitism=0, crossover=0.0, mutation=0.5)
    draw = rng(3)
    codons = ops.random_codons(draw, 300, settings.genome, 255)
    genes = ops.random_genes(draw, 300, factory.slots)
    fitness = factory.evaluate(codons, genes).fitness
    out = (np.empty_like(codons), np.empty_like(genes))
    seen = []

    def usage(rows):
        seen.append(rows.copy())
        return factory.usage(rows)

    breed(rng(4), codons, genes, fitness, settings, out, map_usage=usage)
    parents_mapped, children_before = seen
    child_usage = factory.usage(children_before)
    changed = out[0] != children_before
    assert changed.any()
    assert (np.argwhere(changed)[:, 1] < child_usage.codons[np.argwhere(changed)[:, 0]]).all()
    assert np.array_equal(parents_mapped, codons)  # without the generation's usage, it is mapped once


@pytest.mark.parametrize("crossover", CROSSOVER_OPERATORS[:2])
def test_breeding_from_the_generations_usage_equals_mapping_the_parents(factory, crossover):
    """The evolution hands breeding the usage its evaluation found; mapping the parents again gives
    the same children."""
    settings = dataclasses.replace(factory.spec.evolution, crossover_operator=crossover, population=300)
    draw = rng(6)
    codons = ops.random_codons(draw, 300, settings.genome, 255)
    genes = ops.random_genes(draw, 300, factory.slots)
    fitness = factory.evaluate(codons, genes).fitness
    mapped, carried = (
        (np.empty_like(codons), np.empty_like(genes)),
        (np.empty_like(codons), np.empty_like(genes)),
    )
    breed(rng(7), codons, genes, fitness, settings, mapped, map_usage=factory.usage)
    breed(rng(7), codons, genes, fitness, settings, carried, factory.usage(codons))
    assert np.array_equal(mapped[0], carried[0]) and np.array_equal(mapped[1], carried[1])
    wrong = factory.usage(codons)
    wrong.codons[:] = 1  # as if every genome used its first codon alone: other cuts, other children
    breed(rng(7), codons, genes, fitness, settings, carried, wrong)
    assert not np.array_equal(mapped[0], carried[0])


@pytest.mark.parametrize("crossover", CROSSOVER_OPERATORS)
@pytest.mark.parametrize("mutation", MUTATION_OPERATORS)
def test_every_operator_pair_evolves_reproducibly(factory, crossover, mutation):
    settings = dataclasses.replace(
        factory.spec.evolution,
        crossover_operator=crossover,
        mutation_operator=mutation,
        population=60,
        generations=3,
        elitism=1,
    )
    first = evolve(factory, settings, rng(5))
    again = evolve(factory, settings, rng(5))
    assert np.array_equal(first.codons, again.codons) and np.array_equal(first.genes, again.genes)
    bests = [row.best for row in first.stats]
    assert bests == sorted(bests)


def test_breeding_within_used_needs_the_usage():
    settings = dataclasses.replace(
        Evolution(population=4, genome=8), crossover_operator="variable within used"
    )
    codons = ops.random_codons(rng(), 4, 8, 255)
    genes = ops.random_genes(rng(), 4, 2)
    with pytest.raises(ValueError, match="need the usage"):
        breed(rng(), codons, genes, np.zeros(4), settings, (np.empty_like(codons), np.empty_like(genes)))
