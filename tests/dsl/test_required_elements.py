"""``exactly N TYPE`` and ``at least N TYPE``: the grammar derives the required elements first, so every
floor holds them, in every generated grammar style."""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest

import mazegen
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._problem import Problem
from tests.conftest import EXAMPLES

SPEC = """
element rack { shape rect size 100..200 x 40..80 rotation 0, 90 }
element line { shape rect size 200..300 x 60..100 }
element pallet { shape square size 40..80 }
arena plant { size 3000 x 2000 cm  start (100, 100)  goal (2900, 1900)  robot radius 25 }
scenario layout on plant {
    elements rack, line, pallet
    exactly 3 rack
    at least 2 line
    max elements 12
    grammar STYLE
}
evolution { population 50  generations 1  genome 30  seed 1 }
"""


@pytest.mark.parametrize("style", ["nested", "flat", "list"])
def test_every_floor_of_every_style_holds_the_required_elements(write_spec, tmp_path, style):
    spec = mazegen.load(write_spec(SPEC.replace("STYLE", style)))
    assert spec.scenario.required == (("rack", 3, True), ("line", 2, False))
    mazegen.build(spec, tmp_path / "build")
    problem = Problem.from_build_dir(tmp_path / "build")
    rng = np.random.default_rng(3)
    codons = random_codons(rng, 400, 30, spec.evolution.codon_max)
    genes = random_genes(rng, 400, problem.slots)
    population = problem.evaluate(codons, genes).population
    names = spec.scenario.elements
    assert population.valid.mean() > 0.5
    more_lines = 0
    for i in np.flatnonzero(population.valid):
        counts = Counter(names[k] for k in population.element_ids[i, : population.n_elements[i]])
        assert counts["rack"] == 3 and counts["line"] >= 2, counts
        more_lines += counts["line"] > 2
    assert more_lines > 0  # 'at least' leaves room for more; 'exactly' does not


def test_the_layout_example_keeps_the_tasks_short(tmp_path):
    """examples/layout.maze, briefly: its best floor holds six racks and two lines, overlaps nothing,
    and every task's path is within 2 % of the straight line (random layouts of the same elements are
    13 % longer at the median: benchmarks/layout.py)."""
    spec = mazegen.load(EXAMPLES / "layout.maze")
    result = mazegen.run(spec, population=200, generations=8, catalog=False)
    best = result.best[0][0]
    counts = Counter(element["type"] for element in best["elements"])
    assert (counts["rack"], counts["line"]) == (6, 2)
    assert all(best["terms"][key] == 0 for key in ("overlap", "outside", "solvable"))
    straight = sum(np.hypot(t.goal[0] - t.start[0], t.goal[1] - t.start[1]) for t in spec.arena.tasks)
    assert sum(task["metrics"]["path_length"] for task in best["tasks"]) <= 1.02 * straight
