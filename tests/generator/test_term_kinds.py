"""The fitness term kinds' table and what reads it: the grammar, the build, the reports and the docs."""

from __future__ import annotations

import re

import pytest

from mazegen.dsl.loader import load_spec
from mazegen.dsl.metamodel import GRAMMAR_FILE
from mazegen.fitness_terms import READS, TERMS
from mazegen.runtime import metrics
from mazegen.spec import DRIVE_MEASURES
from tests.conftest import ROOT

HEAD = """\
element box { shape square size 20..40 }
arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }
scenario s on floor { elements box }
"""
EVERY_KIND = """\
fitness {
    count weight 2
    overlap penalty 0.5
    size limit 30 reject
    outside allow
    solvable required
    difficulty target hard weight 3
    tortuosity 1.2..2.5
    diversity entropy
    coverage 0.1..0.3 weight 4
    travel worst below 2500 weight 2
    reachable 0.9..1
    classes 3 weight 2
    controllers dwa, vfh disagree weight 2
    controller dwa time 2..4
    metric dock_clearance(x=100) from "dock.py" range 0.5..1.5 weight 2
    metric far penalty 3
    metric near reject above 2.5
}
"""
DOCK = """\
def dock_clearance(floors, x=0.0):
    return floors.x[:, 0]


far = near = dock_clearance
"""


def _grammar_alternatives() -> list[str]:
    grammar = GRAMMAR_FILE.read_text(encoding="utf-8")
    body = re.search(r"^FitnessTerm:(.*?);", grammar, re.S | re.M)
    assert body is not None
    return [name.strip() for name in body.group(1).split("|")]


def test_every_kind_has_a_row_and_every_row_a_grammar_rule():
    grammar = GRAMMAR_FILE.read_text(encoding="utf-8")
    assert _grammar_alternatives() == [row.rule for row in TERMS.values()]
    for row in TERMS.values():
        assert re.search(rf"^{row.rule}:", grammar, re.M), f"{row.kind}: no rule {row.rule} in maze.tx"
        assert row.reads in READS


def test_every_row_calls_a_function_of_the_metrics_module():
    for row in TERMS.values():
        names = (
            [row.function.format(measure=m) for m in DRIVE_MEASURES]
            if "{" in row.function
            else [row.function]
        )
        for name in names:
            assert callable(getattr(metrics, name, None)), f"{row.kind}: metrics.{name} does not exist"


@pytest.fixture
def every_kind(write_spec, register_plugins):
    write_spec(DOCK, "dock.py")
    register_plugins("metrics", {"far": lambda floors: floors.x[:, 0], "near": lambda floors: floors.y[:, 0]})
    return load_spec(write_spec(HEAD + EVERY_KIND))


def test_the_spec_covers_every_kind(every_kind):
    assert {term.kind for term in every_kind.fitness} == set(TERMS)


def test_a_terms_words_read_back_as_the_same_term(every_kind, write_spec):
    """What reports print of a term is the language: read back, it is the same term."""
    words = "\n".join(f"    {TERMS[term.kind].words(term)}" for term in every_kind.fitness)
    again = load_spec(write_spec(HEAD + f"fitness {{\n{words}\n}}\n", "again.maze"))
    plain = [
        (t.kind, t.weight, t.limit, t.reject, t.target, t.metric, t.controllers) for t in every_kind.fitness
    ]
    assert [
        (t.kind, t.weight, t.limit, t.reject, t.target, t.metric, t.controllers) for t in again.fitness
    ] == plain
    assert [t.plugin and t.plugin.arguments for t in again.fitness] == [
        t.plugin and t.plugin.arguments for t in every_kind.fitness
    ]


def test_the_language_page_shows_every_kind():
    """docs/language.md §6's synopsis of the fitness block writes each kind as its row does."""
    page = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    synopsis = page[page.index("## 6. `fitness`") : page.index("The fitness is the **sum of the terms**")]
    lines = [" ".join(line.split("//")[0].split()) for line in synopsis.splitlines()]
    for row in TERMS.values():
        assert " ".join(row.syntax.split()) in lines, f"docs/language.md §6 does not show {row.syntax!r}"


def test_a_spec_json_edited_to_an_unknown_kind_is_one_line(every_kind):
    from dataclasses import replace

    from mazegen.errors import MazeError
    from mazegen.generator.build import fitness_lines

    edited = replace(every_kind, fitness=(replace(every_kind.fitness[0], kind="elegance"),))
    with pytest.raises(MazeError, match=r"unknown fitness term kind 'elegance' \(known: count, overlap"):
        fitness_lines(edited)
