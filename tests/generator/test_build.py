"""Generated artifacts: the paper's grammars, determinism, lint-clean Python, no injection."""

from __future__ import annotations

import dataclasses
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mazegen.dsl.loader import load_spec
from mazegen.errors import MazeError
from mazegen.generator.build import ARTIFACTS, build, render_artifacts
from mazegen.runtime.engine._bnf import parse_bnf
from mazegen.runtime.engine._mapping import map_genome
from mazegen.spec import FitnessTerm
from tests.conftest import EXAMPLES

PAPER_GENOME = [34, 10, 200, 80, 5, 70, 45, 43]

FIGURE_1 = (
    "<scenario> ::= angle | square | eshape | lshape | <composed>\n"
    "<composed> ::= angle(<scenario>) | square(<scenario>) | eshape(<scenario>) | lshape(<scenario>)\n"
)
FIGURE_4 = (
    "<scenario> ::= triangle() | square() | eshape() | lshape() | triangle(<scenario>) | square(<scenario>)"
    " | eshape(<scenario>) | lshape(<scenario>)\n"
)

BASE = """
import figures
arena canvas { size 900 x 900 px start (50, 50) goal (850, 850) }
"""


def rules_of(text: str) -> str:
    return "".join(line + "\n" for line in text.splitlines() if line and not line.startswith("#"))


def test_nested_style_is_the_papers_figure_1():
    grammar = render_artifacts(load_spec(EXAMPLES / "mazegen1.maze"))["grammar.bnf"]
    assert rules_of(grammar) == FIGURE_1


def test_flat_style_is_the_papers_figure_4():
    grammar = render_artifacts(load_spec(EXAMPLES / "mazegen15.maze"))["grammar.bnf"]
    assert rules_of(grammar) == FIGURE_4


def test_worked_example_maps_through_the_generated_grammar():
    grammar = parse_bnf(render_artifacts(load_spec(EXAMPLES / "mazegen1.maze"))["grammar.bnf"])
    result = map_genome(grammar, PAPER_GENOME)
    assert (result.phenotype, result.used_codons) == ("eshape(angle)", 3)


def test_list_style_and_grammar_placement(write_spec):
    path = write_spec(
        BASE + "scenario s on canvas { elements square, lshape grammar list "
        "placement grammar sizes 1..3 scale 50 positions 100..300 step 100 }\n"
    )
    assert rules_of(render_artifacts(load_spec(path))["grammar.bnf"]) == (
        "<scenario> ::= <element> | <element> <scenario>\n"
        "<element> ::= square(<size>,<number>,<number>) | lshape(<size>,<number>,<number>)\n"
        "<size> ::= 1 | 2 | 3\n"
        "<number> ::= 100 | 200 | 300\n"
    )


def test_custom_rules_keep_words_apart(write_spec):
    path = write_spec(
        BASE + 'scenario s on canvas { grammar custom {\n  <s> ::= square lshape | square "(" <s> ")"\n} }\n'
    )
    spec = load_spec(path)
    assert spec.scenario.elements == ("square", "lshape")
    assert rules_of(render_artifacts(spec)["grammar.bnf"]) == '<s> ::= square lshape | square"("<s>")"\n'


@pytest.mark.parametrize("example", sorted(EXAMPLES.glob("*.maze")), ids=lambda p: p.name)
def test_artifacts_are_deterministic_and_end_with_a_newline(example):
    first, second = render_artifacts(load_spec(example)), render_artifacts(load_spec(example))
    assert first == second
    assert set(first) == set(ARTIFACTS)
    for text in first.values():
        assert text.endswith("\n") and not text.endswith("\n\n")


def test_api_builds_from_a_spec_or_its_path(tmp_path):
    import mazegen

    from_path = mazegen.build(EXAMPLES / "factory.maze", tmp_path / "a")
    from_spec = mazegen.build(mazegen.load(EXAMPLES / "factory.maze"), tmp_path / "b")
    assert [p.name for p in from_path] == [p.name for p in from_spec]
    assert all(a.read_bytes() == b.read_bytes() for a, b in zip(from_path, from_spec))


@pytest.mark.parametrize("example", sorted(EXAMPLES.glob("*.maze")), ids=lambda p: p.name)
def test_generated_python_compiles_and_passes_ruff(example, tmp_path):
    build(load_spec(example), tmp_path)
    for name in ("fitness.py", "experiment.py"):
        compile((tmp_path / name).read_text(), name, "exec")
    assert_ruff_clean(tmp_path / "fitness.py", tmp_path / "experiment.py")


def assert_ruff_clean(*paths: Path) -> None:
    """Generated Python passes ruff's default style rules, whatever this project configures."""
    lint = subprocess.run(
        [sys.executable, "-m", "ruff", "check", "--isolated", "--select", "E,F,W,I,B,UP", *map(str, paths)],
        capture_output=True,
        text=True,
    )
    assert lint.returncode == 0, lint.stdout + lint.stderr


def test_fitness_lines_follow_the_terms(write_spec):
    path = write_spec(
        BASE + "scenario s on canvas { elements square }\n"
        "fitness { count weight 2 overlap penalty 0.5 size limit 500 penalty 3 "
        "outside reject }\n"
    )
    fitness = render_artifacts(load_spec(path))["fitness.py"]
    assert "'count': 2.0 * metrics.element_count(pop)" in fitness
    assert "'overlap': -0.5 * metrics.overlapping_pairs(pop)" in fitness
    assert "'size_limit': -3.0 * metrics.elements_over_size(pop, 500.0)" in fitness
    assert "'outside': metrics.elements_outside(pop) > 0," in fitness  # a verdict of rejections(pop)


@pytest.mark.parametrize(
    ("term", "line"),
    [
        ("solvable required", "'solvable': metrics.unsolvable(pop) > 0,"),
        ("solvable penalty 10", "'solvable': -10.0 * metrics.unsolvable(pop)"),
    ],
)
def test_solvable_term_reads_the_navigation_metric(write_spec, term, line):
    path = write_spec(BASE + f"scenario s on canvas {{ elements square }}\nfitness {{ count {term} }}\n")
    assert line in render_artifacts(load_spec(path))["fitness.py"]


def test_hostile_text_cannot_reach_python(write_spec, tmp_path):
    hostile = "'''; import os; os.system('echo pwned') #"
    path = write_spec(
        BASE + "element __import__ { shape square size 10 class os }\n"
        "scenario print on canvas { grammar custom {\n"
        f'  <s> ::= __import__ "{hostile}" | square\n'
        "} }\n"
    )
    spec = load_spec(path)
    out = tmp_path / "out"
    build(spec, out)
    for name in ("fitness.py", "experiment.py"):
        text = (out / name).read_text()
        assert "pwned" not in text and "os.system" not in text
        compile(text, name, "exec")
    assert hostile in (out / "grammar.bnf").read_text()
    assert parse_bnf((out / "grammar.bnf").read_text()).rules["<s>"][0][0].text == "__import__" + hostile


def test_custom_rules_separate_rules_that_derive_words(write_spec, tmp_path):
    path = write_spec(
        BASE + "scenario s on canvas { grammar custom {\n"
        "  <s> ::= <e> <s> | <e>\n  <e> ::= square | lshape\n} }\n"
    )
    spec = load_spec(path)
    assert rules_of(render_artifacts(spec)["grammar.bnf"]).splitlines()[0] == "<s> ::= <e> <s> | <e>"
    build(spec, tmp_path / "b")
    from mazegen.runtime.engine._problem import Problem

    problem = Problem.from_build_dir(tmp_path / "b")
    codons = np.array([[0, 0, 1, 1, 0]], dtype=np.int32)  # <e> <s>: square, then <e>: lshape
    mapped, _ = problem.decode(codons, np.zeros((1, problem.slots, 5), dtype=np.uint16))
    assert mapped.element_ids[0, :2].tolist() == [0, 1]


@pytest.mark.parametrize(
    ("change", "where"),
    [
        (lambda s: {"fitness": (FitnessTerm("count", weight=float("inf")),)}, "fitness[0].weight"),
        (lambda s: {"arena": dataclasses.replace(s.arena, width=float("nan"))}, "arena.width"),
        (
            lambda s: {"elements": (dataclasses.replace(s.elements[0], size=(1.0, float("inf"))),)},
            "elements[0].size[1]",
        ),
    ],
)
def test_no_infinity_or_nan_reaches_the_generated_files(change, where, tmp_path):
    spec = load_spec(EXAMPLES / "mazegen1.maze")
    spec = dataclasses.replace(spec, **change(spec))
    with pytest.raises(MazeError, match=rf"non-finite number at {re.escape(where)}"):
        build(spec, tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_a_grammar_the_run_could_not_read_fails_at_build_naming_the_spec(tmp_path):
    spec = load_spec(EXAMPLES / "mazegen1.maze")
    bad = dataclasses.replace(spec.scenario, grammar="custom", custom_rules=(("<s>", ('angle "\\x"',)),))
    with pytest.raises(MazeError) as caught:
        build(dataclasses.replace(spec, scenario=bad), tmp_path)
    assert "bad escape" in str(caught.value)
    assert caught.value.filename == f"{spec.source} (its grammar)"
    assert list(tmp_path.iterdir()) == []
