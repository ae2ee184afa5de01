"""examples/adversarial.maze evolves few-element floors on which dwa fails (docs/difficulty.md)."""

from __future__ import annotations

from pathlib import Path

import mazegen

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "adversarial.maze"


def test_a_short_run_finds_solvable_floors_of_few_elements_that_dwa_fails_on():
    spec = mazegen.load(EXAMPLE)
    assert spec.scenario.max_elements <= 8
    assert any(term.kind == "drive" and term.metric == "fails" for term in spec.fitness)
    documents = mazegen.run(EXAMPLE, runs=1, population=200, generations=3).best[0]
    failing = [d for d in documents if d["terms"]["dwa_fails"] > 0]
    assert failing and documents[0] is failing[0]  # a floor dwa fails on ranks first
    for document in failing:
        assert document["metrics"]["solvable"] and len(document["elements"]) <= spec.scenario.max_elements
