"""Graded suites: a MAP-Elites archive over difficulty score and element count (or number of classes).

The archive is a grid: one axis bins the difficulty score (:mod:`difficulty`),
the other a second measure: the number of elements, or the number of homotopy classes (the
ways round the obstacles, docs/classes.md). Each cell keeps the fittest solvable scenario
whose descriptors fall in it (its elite). Filling it (Mouret and Clune, 2015):
evaluate a random batch, then repeatedly breed a batch from elites drawn
uniformly from the filled cells (one-point crossover and int-flip mutation, the
run's own operators) and offer every child to its cell.

The archive is this package's own, not pyribs': the genomes are integer codons
plus 16-bit placement genes, which pyribs would hold as float vectors and round
back on every draw, and a two-descriptor grid with fitness replacement is a
few array operations.
"""

from __future__ import annotations

import dataclasses
import io
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.fileio import write_atomic
from mazegen.runtime.documents import SuiteDirectory, dumps, row_document
from mazegen.runtime.engine import (
    PLACEMENT_GENES,
    Evaluation,
    GenerationStats,
    Population,
    Problem,
    generation_stats,
    make_children,
    random_codons,
    random_genes,
)
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.navigation import class_counts_of, floor_topology, survey_of, task_views
from mazegen.runtime.reports import scenario_svg
from mazegen.runtime.runs import json_text, staged_directory
from mazegen.spec import MAX_CLASSES

DIFFICULTY_BIN = 5.0
"""Width of a difficulty bin in score points; the last bin is open above."""
MEASURES = ("elements", "classes")
"""The archive's second measure: a floor's number of elements, or its number of homotopy classes."""


@dataclass(frozen=True)
class Bins:
    """The archive's grid.

    Attributes:
        difficulty: Number of difficulty bins, each :data:`DIFFICULTY_BIN` wide from 0.
        elements: Number of element-count bins.
        per_bin: Element counts per element bin (bin ``j`` holds ``1 + j*per_bin ..``).
    """

    difficulty: int
    elements: int
    per_bin: int

    @classmethod
    def for_classes(cls, *, difficulty: int = 10) -> Bins:
        """Bins for floors of 1 to :data:`~mazegen.spec.MAX_CLASSES` classes, one bin each."""
        return cls(difficulty, MAX_CLASSES, 1)

    @classmethod
    def for_slots(cls, max_elements: int, *, difficulty: int = 10, elements: int = 16) -> Bins:
        """Bins for scenarios of 1..``max_elements`` elements, at most ``elements`` element bins."""
        per_bin = max(1, math.ceil(max_elements / elements))
        return cls(difficulty, math.ceil(max_elements / per_bin), per_bin)

    def cell(self, difficulty: np.ndarray, elements: np.ndarray) -> np.ndarray:
        """Flat cell index (difficulty bin × element bins + element bin) of each scenario."""
        row = np.clip((difficulty // DIFFICULTY_BIN).astype(np.int64), 0, self.difficulty - 1)
        col = np.clip((elements.astype(np.int64) - 1) // self.per_bin, 0, self.elements - 1)
        return row * self.elements + col

    def label(self, cell: int) -> tuple[str, str]:
        """Human-readable (difficulty range, element range) of a cell."""
        row, col = divmod(cell, self.elements)
        low = row * DIFFICULTY_BIN
        difficulty = f"{low:g}+" if row == self.difficulty - 1 else f"{low:g}-{low + DIFFICULTY_BIN:g}"
        first = 1 + col * self.per_bin
        elements = str(first) if self.per_bin == 1 else f"{first}-{first + self.per_bin - 1}"
        return difficulty, elements


@dataclass(frozen=True)
class SuiteSettings:
    """What a suite ran with, as ``mazegen suite`` names it: the seed, the batches bred after the random
    one (``iterations``), the scenarios per batch and the scenarios written (``size``)."""

    seed: int
    iterations: int
    batch: int
    size: int


class Archive:
    """Elites of a :class:`Bins` grid: genome, fitness and descriptors per cell (``measured``: each
    elite's value of ``measure``, one of :data:`MEASURES`)."""

    def __init__(
        self, *, bins: Bins, genome: int, slots: int, codon_dtype: np.dtype, measure: str = "elements"
    ) -> None:
        cells = bins.difficulty * bins.elements
        self.bins = bins
        self.measure = measure
        self.fitness = np.full(cells, -np.inf)
        self.difficulty = np.full(cells, np.nan)
        self.measured = np.zeros(cells, np.int32)
        self.codons = np.zeros((cells, genome), codon_dtype)
        self.genes = np.zeros((cells, slots, PLACEMENT_GENES), np.uint16)

    @property
    def filled(self) -> np.ndarray:
        """Indices of the cells holding an elite, in cell order."""
        return np.flatnonzero(np.isfinite(self.fitness))

    def offer(self, codons: np.ndarray, genes: np.ndarray, evaluation: Evaluation) -> int:
        """Offer a batch to the archive; returns how many cells gained a new elite.

        A solvable valid child enters its cell when it beats the elite there; among
        children of one batch aimed at the same cell the fittest (then the first) wins.
        """
        survey = survey_of(evaluation.population)
        fitness = evaluation.fitness
        ok = np.isfinite(fitness) & survey.navigation.solvable
        rows = np.flatnonzero(ok)
        if rows.size == 0:
            return 0
        difficulty = survey.difficulty[rows]
        measured = self.measured_of(evaluation.population)[rows]
        cells = self.bins.cell(difficulty, measured)
        order = np.lexsort((rows, -fitness[rows], cells))  # by cell, fittest first, then batch order
        first = np.ones(order.size, bool)
        first[1:] = cells[order][1:] != cells[order][:-1]
        best = order[first]
        better = fitness[rows[best]] > self.fitness[cells[best]]
        best = best[better]
        target, source = cells[best], rows[best]
        self.fitness[target] = fitness[source]
        self.difficulty[target] = difficulty[best]
        self.measured[target] = measured[best]
        self.codons[target] = codons[source]
        self.genes[target] = genes[source]
        return int(target.size)

    def measured_of(self, population: Population) -> np.ndarray:
        """Each floor's value of the archive's measure (classes: the tasks' mean, rounded)."""
        if self.measure == "classes":
            return np.rint(class_counts_of(population)).astype(np.int32)
        return population.n_elements

    def spread(self, count: int) -> np.ndarray:
        """Up to ``count`` filled cells spread over the grid: each difficulty bin's fittest first, then
        each one's second fittest, and so on."""
        filled = self.filled
        rows = filled // self.bins.elements
        rank = np.zeros(filled.size, np.int64)
        for row in np.unique(rows):
            members = np.flatnonzero(rows == row)
            rank[members[np.argsort(-self.fitness[filled[members]], kind="stable")]] = np.arange(members.size)
        order = np.lexsort((filled, rank))
        return filled[order[:count]]


def fill_archive(
    problem: Problem,
    *,
    seed: int,
    iterations: int,
    batch: int,
    bins: Bins | None = None,
    measure: str = "elements",
    on_iteration: Callable[[GenerationStats], None] | None = None,
) -> Archive:
    """Fill a MAP-Elites archive for ``problem``: a random batch, then ``iterations`` bred batches.

    Args:
        problem: The built spec; its fitness ranks the elites of a cell.
        seed: Seed of the random generator (same seed, same archive).
        iterations: Batches bred from the archive after the random one.
        batch: Scenarios per batch.
        bins: The grid (default :meth:`Bins.for_slots` of the spec's ``max elements``, or
            :meth:`Bins.for_classes`).
        measure: The second descriptor, one of :data:`MEASURES`.
        on_iteration: Called after each batch with its statistics.
    """
    settings = problem.spec.evolution
    rng = np.random.default_rng(seed)
    genome, slots = settings.genome, problem.slots
    codons = random_codons(rng, batch, genome, settings.codon_max)
    genes = random_genes(rng, batch, slots)
    if measure not in MEASURES:
        raise MazeError(f"a suite's archive measures {' or '.join(MEASURES)}, not {measure!r}")
    default = Bins.for_classes() if measure == "classes" else Bins.for_slots(slots)
    archive = Archive(
        bins=bins or default, genome=genome, slots=slots, codon_dtype=codons.dtype, measure=measure
    )
    for iteration in range(iterations + 1):
        started = time.perf_counter()
        if iteration and archive.filled.size:
            parents = archive.filled[rng.integers(0, archive.filled.size, size=batch)]
            make_children(
                rng,
                archive.codons,
                archive.genes,
                parents,
                settings,
                (codons, genes),
                map_usage=problem.usage,
            )
        elif iteration:  # nothing solvable yet: start afresh
            codons = random_codons(rng, batch, genome, settings.codon_max)
            genes = random_genes(rng, batch, slots)
        evaluation = problem.evaluate(codons, genes, searching=True)
        archive.offer(codons, genes, evaluation)
        if on_iteration is not None:
            seconds = time.perf_counter() - started
            on_iteration(generation_stats(iteration, archive.fitness, batch, archive.filled.size, seconds))
    return archive


def suite_documents(
    problem: Problem, archive: Archive, size: int, *, seed: int, distinct: bool = False
) -> list[dict[str, Any]]:
    """Scenario documents of up to ``size`` elites spread over the archive (see :meth:`Archive.spread`);
    with ``distinct``, one per canonical class (docs/classes.md): an elite of a class already written
    gives way to the next cell in the spread's order."""
    cells = archive.spread(archive.filled.size if distinct else size)
    codons, genes = archive.codons[cells], archive.genes[cells]
    evaluation = problem.evaluate(codons, genes)
    rows = distinct_rows(evaluation.population, size) if distinct else range(len(cells))
    documents = []
    for row in rows:
        cell = int(cells[row])
        difficulty, measured = archive.bins.label(cell)
        origin = {"seed": seed, "suite": {"cell": cell, "difficulty": difficulty, archive.measure: measured}}
        documents.append(row_document(problem, evaluation, row, codons[row], genes[row], origin))
    return documents


def distinct_rows(population: Population, size: int) -> list[int]:
    """Up to ``size`` floors of ``population``, in order, each of a canonical class (every task's) no
    floor before it has."""
    views = task_views(population)
    grids = [grid_of(view.arena) for view in views]
    seen: set[tuple[str, ...]] = set()
    rows = []
    for row in range(population.size):
        signature = tuple(floor_topology(view, grid, row).signature for view, grid in zip(views, grids))
        if signature not in seen:
            seen.add(signature)
            rows.append(row)
            if len(rows) == size:
                break
    return rows


def archive_heatmap(archive: Archive, chosen: np.ndarray, title: str) -> bytes:
    """PNG of the archive: each cell's elite fitness, empty cells blank, written scenarios circled."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    bins = archive.bins
    grid = np.where(np.isfinite(archive.fitness), archive.fitness, np.nan).reshape(
        bins.difficulty, bins.elements
    )
    figure, axes = plt.subplots(figsize=(1.2 + 0.45 * bins.elements, 1.0 + 0.4 * bins.difficulty), dpi=100)
    image = axes.imshow(grid, origin="lower", cmap="viridis", aspect="auto")
    figure.colorbar(image, ax=axes, label="elite fitness")
    rows, cols = np.divmod(chosen, bins.elements)
    axes.scatter(cols, rows, s=60, facecolors="none", edgecolors="white", linewidths=1.5, label="written")
    axes.set_xticks(range(bins.elements), [bins.label(c)[1] for c in range(bins.elements)], rotation=90)
    axes.set_yticks(
        range(bins.difficulty), [bins.label(r * bins.elements)[0] for r in range(bins.difficulty)]
    )
    axes.set_xlabel("homotopy classes" if archive.measure == "classes" else "elements")
    axes.set_ylabel("difficulty score")
    axes.set_title(f"{title}: {archive.filled.size} of {grid.size} cells filled")
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", metadata={"Software": None})
    plt.close(figure)
    return buffer.getvalue()


def write_suite(
    out_dir: Path,
    problem: Problem,
    archive: Archive,
    documents: list[dict[str, Any]],
    settings: SuiteSettings,
    *,
    force: bool,
) -> None:
    """Write the suite directory atomically: scenarios, drawings, the archive (with the suite's
    ``settings``, which its report shows instead of the spec's evolution block) and its heatmap."""
    bins = archive.bins
    filled = archive.filled
    record = {
        "scenario": problem.spec.name,
        "settings": dataclasses.asdict(settings),
        "bins": {"difficulty": bins.difficulty, "difficulty_width": DIFFICULTY_BIN,
                 "measure": archive.measure, "elements": bins.elements, "elements_per_bin": bins.per_bin},
        "filled": int(filled.size),
        "cells": [
            {
                "cell": int(cell),
                "difficulty_bin": bins.label(int(cell))[0],
                f"{archive.measure}_bin": bins.label(int(cell))[1],
                "fitness": float(archive.fitness[cell]),
                "difficulty": round(float(archive.difficulty[cell]), 4),
                archive.measure: int(archive.measured[cell]),
            }
            for cell in filled
        ],
    }  # fmt: skip
    chosen = np.array([d["origin"]["suite"]["cell"] for d in documents], np.int64)
    with staged_directory(out_dir, force=force) as stage:
        suite = SuiteDirectory(stage)
        write_atomic(suite.spec, problem.spec.to_json())
        write_atomic(suite.archive, json_text(record))
        write_atomic(suite.heatmap, archive_heatmap(archive, chosen, problem.spec.name))
        for number, document in enumerate(documents, start=1):
            name = SuiteDirectory.scenario_name(number, ".json")
            write_atomic(stage / name, dumps(document, str(out_dir / name)))
            write_atomic(
                stage / SuiteDirectory.scenario_name(number, ".svg"),
                scenario_svg(document, base=problem.spec.arena.base),
            )
