"""Breeding a generation in one compiled call: selection, crossover and mutation.

The draws and what they do are those of the operators one at a time
(:mod:`~mazegen.runtime.engine._operators`, :mod:`~mazegen.runtime.engine._used_operators`), made in
the same order from the same generator: the compiled step calls the same compiled draws, so a seed
breeds the same children either way (tested). Bred one operator at a time, the calls and their
temporary arrays were about a quarter of breeding a generation of 1,000 (0.40 ms, 0.29 ms in one
call). The only break is the mutation within the used codons, which reads what the crossed
children use: their mapping, a Python call.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numba import njit

import mazegen.runtime.engine._operators as ops
import mazegen.runtime.engine._used_operators as uo
from mazegen.runtime.engine._placement import PLACEMENT_GENES
from mazegen.runtime.engine._used_operators import Usage
from mazegen.spec import Evolution

_NO_ROWS = np.empty(0, dtype=np.int64)


def breed(
    rng: np.random.Generator,
    codons: np.ndarray,
    genes: np.ndarray,
    fitness: np.ndarray,
    settings: Evolution,
    out: tuple[np.ndarray, np.ndarray],
    usage: Usage | None = None,
    map_usage: Callable[[np.ndarray], Usage] | None = None,
) -> None:
    """Write the next generation into ``out``: elites unchanged, then selected, crossed and mutated children.

    Args:
        rng: The run's random generator.
        codons: This generation's structure codons.
        genes: This generation's placement genes.
        fitness: This generation's fitness.
        settings: Selection, crossover and mutation settings.
        out: C-contiguous codon and gene arrays shaped like ``codons`` and ``genes``, overwritten.
        usage: The :class:`Usage` of each row of ``codons`` (from their evaluation), which the
            crossovers within the used codons read; without it, ``map_usage`` maps the population.
        map_usage: The :class:`Usage` of any structure codons (their mapping): the mutation within
            the used codons maps the crossed children with it.
    """
    _check_mapping(settings, usage, map_usage)
    _check_out(out)
    if usage is None and _crosses_within_used(settings):
        usage = _mapped(map_usage, codons)
    elites = ops.ranking(fitness, settings.elitism)
    # A tournament's size, or None for truncation (the kernels then leave tournaments out), whose
    # parents are drawn from the best fraction, ranked here (no draws).
    if settings.selection == "tournament":
        tournament, pool = settings.tournament, _NO_ROWS
    else:
        tournament, pool = None, ops.truncation_pool(fitness, settings.truncation)
    out_codons, out_genes = out
    _breed_generation(
        rng, codons, _rows(genes), fitness, elites, tournament, pool, *_crossing(settings, usage),
        _mutating_whole(settings), out_codons, _rows(out_genes),
    )  # fmt: skip
    _mutate_within_used(rng, settings, map_usage, (out_codons[elites.size :], out_genes[elites.size :]))


def make_children(
    rng: np.random.Generator,
    codons: np.ndarray,
    genes: np.ndarray,
    parents: np.ndarray,
    settings: Evolution,
    out: tuple[np.ndarray, np.ndarray],
    usage: Usage | None = None,
    map_usage: Callable[[np.ndarray], Usage] | None = None,
) -> None:
    """Write the children of ``parents`` (rows of ``codons`` and ``genes``) into ``out``, one row per
    parent: pairs crossed, then mutated, by the operators ``settings`` name.

    Args:
        usage, map_usage: As in :func:`breed`; without ``usage``, ``map_usage`` maps each parent once.
    """
    _check_mapping(settings, usage, map_usage)
    _check_out(out)
    if usage is None and _crosses_within_used(settings):
        rows = np.unique(parents)  # parents repeat: map each once
        usage = Usage.empty(codons.shape[0], genes.shape[1])
        usage.put(rows, _mapped(map_usage, codons[rows]), np.arange(rows.size))
    out_codons, out_genes = out
    _make_children(
        rng, codons, _rows(genes), parents, *_crossing(settings, usage), _mutating_whole(settings),
        out_codons, _rows(out_genes),
    )  # fmt: skip
    _mutate_within_used(rng, settings, map_usage, out)


def _check_mapping(
    settings: Evolution, usage: Usage | None, map_usage: Callable[[np.ndarray], Usage] | None
) -> None:
    """Raise before any draw when the operators need usage that nothing gives."""
    needs = settings.mutation_operator == "within used" or (usage is None and _crosses_within_used(settings))
    if needs and map_usage is None:
        raise ValueError("operators within the used codons need the usage of the genomes")


def _crosses_within_used(settings: Evolution) -> bool:
    return settings.crossover_operator != "onepoint within genome"


def _mapped(map_usage: Callable[[np.ndarray], Usage] | None, codons: np.ndarray) -> Usage:
    assert map_usage is not None  # _check_mapping raised otherwise
    return map_usage(codons)


def _rows(genes: np.ndarray) -> np.ndarray:
    """Placement genes one flat row per genome (a view of output arrays, which must be C-contiguous)."""
    return genes.reshape(genes.shape[0], genes.shape[1] * PLACEMENT_GENES)


def _check_out(out: tuple[np.ndarray, np.ndarray]) -> None:
    if not (out[0].flags.c_contiguous and out[1].flags.c_contiguous):
        raise ValueError("the children's arrays must be C-contiguous: they are written through flat views")


def _crossing(settings: Evolution, usage: Usage | None) -> tuple[tuple | None, tuple | None]:
    """The crossover as the kernels take it: over whole genomes (its rate), or else within the used
    codons (rate, whether variable, each row's used codons and element codons). numba compiles the
    kernels for the one given, leaving the other (None) out."""
    if not _crosses_within_used(settings):
        return (settings.crossover,), None
    assert usage is not None  # breed and make_children map the parents otherwise
    variable = settings.crossover_operator == "variable within used"
    return None, (settings.crossover, variable, usage.codons, usage.element_codons)


def _mutating(settings: Evolution) -> tuple[float, float, int, type]:
    """The mutation as the kernels take it: rate, gap scale, largest codon and the type codons are
    drawn in."""
    return (
        settings.mutation,
        ops.gap_scale(settings.mutation),
        settings.codon_max,
        ops.codon_type(settings.codon_max),
    )


def _mutating_whole(settings: Evolution) -> tuple[float, float, int, type] | None:
    """The mutation over whole genomes, made with the crossover; None when it is within the used
    codons (made after the children are mapped), which the kernels then leave out."""
    return _mutating(settings) if settings.mutation_operator == "within genome" else None


def _mutate_within_used(
    rng: np.random.Generator,
    settings: Evolution,
    map_usage: Callable[[np.ndarray], Usage] | None,
    children: tuple[np.ndarray, np.ndarray],
) -> None:
    """The mutation within the used codons of crossed ``children``: PonyGE2 maps a crossed child
    before it mutates it, and so do we (the whole-genome mutation is made with the crossover)."""
    if settings.mutation_operator != "within used":
        return
    codons, genes = children
    usage = _mapped(map_usage, codons)
    _mutate(rng, codons, _rows(genes), *_mutating(settings), usage.codons, usage.rows)


@njit(cache=True)
def _breed_generation(
    rng, codons, genes, fitness, elites, tournament, pool, whole, within_used, mutating, out_codons, out_genes
):  # pragma: no cover - compiled
    """Elites first, then the children of parents chosen by ``tournament`` (its size), or when it is
    None drawn from a truncation's ranked ``pool``."""
    for k in range(elites.shape[0]):
        ops.copy_span(codons, elites[k], np.int64(0), out_codons, k, np.int64(0), codons.shape[1])
        ops.copy_span(genes, elites[k], np.int64(0), out_genes, k, np.int64(0), genes.shape[1])
    count = fitness.shape[0] - elites.shape[0]
    if tournament is not None:
        parents = ops.draw_tournaments(rng, fitness, tournament, count)
    else:
        parents = ops.draw_from_pool(rng, pool, count)
    done = elites.shape[0]
    _make_children(
        rng, codons, genes, parents, whole, within_used, mutating, out_codons[done:], out_genes[done:]
    )


@njit(cache=True)
def _make_children(
    rng, codons, genes, parents, whole, within_used, mutating, out_codons, out_genes
):  # pragma: no cover - compiled
    """Children of ``parents``, crossed over ``whole`` genomes or ``within_used`` codons (the other
    None: see :func:`_crossing`), then mutated over whole genomes unless ``mutating`` is None."""
    pairs = parents.shape[0] // 2
    if whole is not None:
        slots = genes.shape[1] // PLACEMENT_GENES
        crosses, codon_cut, gene_cut = ops.draw_crossover(rng, pairs, codons.shape[1], slots, whole[0])
        ops.cross_pairs(codons, genes, parents, crosses, codon_cut, gene_cut, out_codons, out_genes)
    elif within_used is not None:
        rate, variable, used, element_codons = within_used
        crosses, first, second = uo.draw_cuts(rng, used[parents], rate, variable)
        uo.splice_pairs(codons, genes, parents, crosses, first, second, element_codons, out_codons, out_genes)
    if mutating is not None:
        rate, scale, codon_max, drawn_as = mutating
        _mutate(rng, out_codons, out_genes, rate, scale, codon_max, drawn_as, None, None)


@njit(cache=True)
def _mutate(rng, codons, genes, rate, scale, codon_max, drawn_as, used_codons, used_rows):  # pragma: no cover
    """Draw and apply an int-flip mutation of the rows of ``codons`` and flat ``genes``, within the
    used codons and element rows where they are given."""
    slots = genes.shape[1] // PLACEMENT_GENES
    draws = ops.draw_mutation(
        rng, codons.shape[0], codons.shape[1], slots, rate, scale, codon_max, drawn_as, used_codons, used_rows
    )
    ops.apply_mutation(*draws, codons, genes)
