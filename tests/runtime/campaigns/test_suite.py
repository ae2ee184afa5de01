"""Graded suites: the MAP-Elites archive's rules and a whole suite's output."""

from __future__ import annotations

import json

import numpy as np

import mazegen
from mazegen.runtime.campaigns._suite import (
    DIFFICULTY_BIN,
    Bins,
    SuiteSettings,
    fill_archive,
    suite_documents,
    write_suite,
)
from mazegen.runtime.engine._problem import Problem
from mazegen.runtime.navigation._measures import class_counts_of, survey_of
from tests.conftest import EXAMPLES
from tests.runtime.floors import geometrically_solvable


def workshop_problem(tmp_path) -> Problem:
    mazegen.build(EXAMPLES / "workshop.maze", tmp_path / "build")
    return Problem.from_build_dir(tmp_path / "build")


def test_bins_place_scores_and_counts():
    bins = Bins.for_slots(32)
    assert (bins.difficulty, bins.elements, bins.per_bin) == (10, 16, 2)
    cells = bins.cell(np.array([0.0, 4.99, 5.0, 99.0]), np.array([1, 2, 3, 32]))
    assert cells.tolist() == [0, 0, 16 + 1, 9 * 16 + 15]
    assert bins.label(17) == ("5-10", "3-4") and bins.label(9 * 16) == ("45+", "1-2")


def test_archive_keeps_the_fittest_per_cell_and_suites_spread_over_it(tmp_path):
    problem = workshop_problem(tmp_path)
    archive = fill_archive(problem, seed=3, iterations=6, batch=400)
    filled = archive.filled
    assert filled.size >= 10
    # Every elite sits in the cell of its own descriptors and scores what the archive says.
    evaluation = problem.evaluate(archive.codons[filled], archive.genes[filled])
    assert np.array_equal(evaluation.fitness, archive.fitness[filled])
    survey = survey_of(evaluation.population)
    assert survey.navigation.solvable.all()
    cells = archive.bins.cell(survey.difficulty, evaluation.population.n_elements)
    assert np.array_equal(cells, filled)
    # Offering the elites again changes nothing: none beats itself.
    assert archive.offer(archive.codons[filled], archive.genes[filled], evaluation) == 0
    # Same seed, same archive.
    again = fill_archive(problem, seed=3, iterations=6, batch=400)
    assert np.array_equal(again.fitness, archive.fitness) and np.array_equal(again.codons, archive.codons)

    documents = suite_documents(problem, archive, 8, seed=3)
    assert len(documents) == 8
    assert len({document["origin"]["suite"]["cell"] for document in documents}) == 8
    assert len({json.dumps(document["elements"]) for document in documents}) == 8
    assert all(document["metrics"]["solvable"] and geometrically_solvable(document) for document in documents)
    # Spread: as many difficulty bins as the archive fills (up to 8) are represented.
    rows = {document["origin"]["suite"]["cell"] // archive.bins.elements for document in documents}
    assert len(rows) == min(8, len(set((filled // archive.bins.elements).tolist())))
    for document in documents:
        low = document["metrics"]["difficulty"] // DIFFICULTY_BIN * DIFFICULTY_BIN
        assert document["origin"]["suite"]["difficulty"].startswith(f"{min(low, 45):g}")

    settings = SuiteSettings(seed=3, iterations=6, batch=400, size=8)
    write_suite(tmp_path / "suite", problem, archive, documents, settings, force=False)
    names = sorted(path.name for path in (tmp_path / "suite").iterdir())
    assert (
        names[:3] == ["archive.json", "archive.png", "scenario-01.json"] and len(names) == 2 + 2 * 8 + 1
    )  # + spec.json
    assert (tmp_path / "suite" / "archive.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    record = json.loads((tmp_path / "suite" / "archive.json").read_text())
    assert record["filled"] == filled.size == len(record["cells"])
    assert record["settings"] == {"seed": 3, "iterations": 6, "batch": 400, "size": 8}


def test_an_archive_over_classes_bins_each_elite_by_its_classes_and_a_suite_keeps_one_per_class(tmp_path):
    problem = workshop_problem(tmp_path)
    archive = fill_archive(problem, seed=5, iterations=2, batch=200, measure="classes")
    filled = archive.filled
    evaluation = problem.evaluate(archive.codons[filled], archive.genes[filled])
    counts = np.rint(class_counts_of(evaluation.population))
    assert np.array_equal(archive.bins.cell(survey_of(evaluation.population).difficulty, counts), filled)
    assert np.array_equal(archive.measured[filled], counts) and len(set(counts.tolist())) >= 3

    every = suite_documents(problem, archive, filled.size, seed=5)
    signatures = [floor.signature for floor in mazegen.classes(every, spec=problem.spec).floors]
    distinct = suite_documents(problem, archive, filled.size, seed=5, distinct=True)
    assert len(distinct) == len(set(signatures)) < len(every)  # some elites share a class
    kept = [floor.signature for floor in mazegen.classes(distinct, spec=problem.spec).floors]
    assert kept == list(dict.fromkeys(signatures))  # the first elite of each class, in the spread's order
    assert all(document["origin"]["suite"]["classes"] for document in distinct)

    settings = SuiteSettings(seed=5, iterations=2, batch=200, size=len(distinct))
    write_suite(tmp_path / "suite", problem, archive, distinct, settings, force=False)
    record = json.loads((tmp_path / "suite" / "archive.json").read_text())
    assert record["bins"]["measure"] == "classes"
    assert all(cell["classes"] == int(archive.measured[cell["cell"]]) for cell in record["cells"])
