"""Known-bad specs and the one-line located message each must give (a table, as in Lark)."""

from __future__ import annotations

import pytest

from mazegen.dsl.loader import check_file, load_spec
from mazegen.errors import MazeError

ARENA = "arena floor { size 1000 x 800 cm start (50, 50) goal (950, 750) robot radius 20 }\n"
ELEMENT = "element box { shape square size 20..40 }\n"
SCENARIO = "scenario s on floor { elements box }\n"


def spec(*, arena: str = ARENA, element: str = ELEMENT, scenario: str = SCENARIO, tail: str = "") -> str:
    return element + arena + scenario + tail


# (name, text, expected line:col, expected message fragment)
BAD_SPECS = [
    ("syntax: unknown keyword", "elemnt box { }\n", "1:1", "expected 'import', 'element'"),
    (
        "syntax: range needs a number",
        spec(element="element box { shape square size 20.. }\n"),
        "1:38",
        "expected a number, found '}'",
    ),
    (
        "syntax: a number with an exponent",
        spec(tail="fitness { count weight 1e3 }\n"),
        "4:24",
        "expected a number, found '1e3' (write numbers without an exponent",
    ),
    (
        "syntax: a decimal where a whole number goes",
        spec(tail="evolution { population 2.5 }\n"),
        "4:24",
        "expected a whole number, found '2.5' (write a whole number such as 4000)",
    ),
    ("syntax: size needs x", spec(arena="arena floor { size 1000 by 800 }\n"), "2:25", "expected 'x'"),
    ("syntax: unclosed block", ELEMENT + "arena floor { size 10 x 10 cm\n", "3:1", "found end of file"),
    (
        "unknown element",
        spec(scenario="scenario s on floor { elements box, crate }\n"),
        "3:37",
        "unknown element 'crate'",
    ),
    (
        "unknown element suggestion",
        spec(scenario="scenario s on floor { elements bxo }\n"),
        "3:32",
        "did you mean 'box'?",
    ),
    (
        "unknown arena",
        spec(scenario="scenario s on flor { elements box }\n"),
        "3:1",
        "unknown arena 'flor' (did you mean 'floor'?)",
    ),
    ("unknown library", "import manufactoring\n" + spec(), "1:1", "unknown library 'manufactoring'"),
    (
        "missing import file",
        'import "nowhere.maze"\n' + spec(),
        "1:1",
        "imported file 'nowhere.maze' not found",
    ),
    (
        "inverted range",
        spec(element="element box { shape square size 40..20 }\n"),
        "1:33",
        "empty size range 40..20 (low is above high)",
    ),
    ("zero size", spec(element="element box { shape square size 0..20 }\n"), "1:33", "size must be positive"),
    (
        "rect needs depth",
        spec(element="element box { shape rect size 20..40 }\n"),
        "1:26",
        "give 'size WIDTH x DEPTH'",
    ),
    (
        "depth on a square",
        spec(element="element box { shape square size 20 x 30 }\n"),
        "1:38",
        "only a rect takes a depth",
    ),
    ("no shape", spec(element="element box { size 20..40 }\n"), "1:1", "element 'box' has no shape"),
    (
        "duplicate property",
        spec(element="element box { shape square size 2 size 3 }\n"),
        "1:35",
        "duplicate 'size' in element 'box'",
    ),
    (
        "bad colour",
        spec(element='element box { shape square size 2 colour "red; x" }\n'),
        "1:35",
        "bad colour",
    ),
    (
        "two-sided polygon",
        spec(element="element box { shape points (0,0) (1,1) size 2 }\n"),
        "1:21",
        "bad points shape",
    ),
    ("duplicate element", spec(element=ELEMENT + ELEMENT), "2:1", "'box' is already declared at"),
    (
        "start outside",
        spec(arena="arena floor { size 100 x 100 start (150, 50) goal (50, 50) }\n"),
        "2:36",
        "start (150, 50) is outside the arena 100 x 100",
    ),
    (
        "goal inside the wall margin",
        spec(arena="arena floor { size 100 x 100 start (50, 50) goal (95, 50) robot radius 10 }\n"),
        "2:50",
        "goal (95, 50) is closer to the arena wall than the robot radius 10",
    ),
    (
        "arena without start",
        spec(arena="arena floor { size 100 x 100 goal (50, 50) }\n"),
        "2:1",
        "arena 'floor' has no start",
    ),
    (
        "population 0",
        spec(tail="evolution { population 0 }\n"),
        "4:13",
        "population must be at least 1, got 0",
    ),
    ("genome 0", spec(tail="evolution { genome 0 }\n"), "4:13", "genome must be at least 1, got 0"),
    (
        "selection 1.5",
        spec(tail="evolution { selection 1.5 }\n"),
        "4:13",
        "selection must be within (0, 1], got 1.5",
    ),
    ("selection 0", spec(tail="evolution { selection 0 }\n"), "4:13", "selection must be within (0, 1]"),
    ("mutation rate", spec(tail="evolution { mutation 2 }\n"), "4:13", "mutation rate must be within [0, 1]"),
    (
        "codons start at 0",
        spec(tail="evolution { codons 1..255 }\n"),
        "4:20",
        "codons must be written 0..MAX",
    ),
    (
        "elitism too large",
        spec(tail="evolution { population 5 elitism 5 }\n"),
        "4:26",
        "elitism 5 must be below the population 5",
    ),
    (
        "population within the default elitism",
        spec(tail="evolution { population 1 }\n"),
        "4:13",
        "population 1 must be above the elitism 1 (the default",
    ),
    ("duplicate setting", spec(tail="evolution { seed 1 seed 2 }\n"), "4:20", "duplicate 'seed'"),
    ("duplicate term", spec(tail="fitness { count count }\n"), "4:17", "duplicate fitness term 'count'"),
    (
        "grid cell too coarse",
        spec(arena=ARENA.replace("robot radius 20", "robot radius 20 grid 300")),
        "2:81",
        "grid cell must be positive and at most a quarter of the arena's shorter side, got 300",
    ),
    (
        "grid cell too fine",
        spec(arena=ARENA.replace("robot radius 20", "robot radius 20 grid 0.5")),
        "2:81",
        "grid cell 0.5 makes more than 1024 cells on a side",
    ),
    (
        "solvable needs a mode",
        spec(tail="fitness { solvable }\n"),
        "4:20",
        "expected 'required' or 'penalty'",
    ),
    (
        "metric range backwards",
        spec(tail="fitness { tortuosity 2.0..1.4 weight 2 }\n"),
        "4:22",
        "a target range needs low < high, got 2..1.4",
    ),
    (
        "coverage is a fraction",
        spec(tail="fitness { coverage 0.2..1.5 }\n"),
        "4:20",
        "coverage is a fraction of the floor (0..1), got 0.2..1.5",
    ),
    (
        "unknown difficulty level",
        spec(tail="fitness { difficulty target extreme }\n"),
        "4:29",
        "expected 'easy', 'medium' or 'hard'",
    ),
    (
        "duplicate metric term",
        spec(tail="fitness { tortuosity 1.2..1.5 tortuosity 1.5..2.0 }\n"),
        "4:31",
        "duplicate fitness term 'tortuosity'",
    ),
    (
        "size limit allow",
        spec(tail="fitness { size limit 500 allow }\n"),
        "4:11",
        "needs 'reject' or 'penalty W'",
    ),
    (
        "custom rule undefined",
        spec(scenario="scenario s on floor { grammar custom { <s> ::= box <t> } }\n"),
        "3:52",
        "rule <t> is used but never defined",
    ),
    (
        "custom rule twice",
        spec(scenario="scenario s on floor { grammar custom { <s> ::= box <s> ::= box } }\n"),
        "3:52",
        "rule <s> is defined twice",
    ),
    (
        "custom unknown element",
        spec(scenario="scenario s on floor { grammar custom { <s> ::= crate } }\n"),
        "3:48",
        "unknown element 'crate'",
    ),
    ("no elements", spec(scenario="scenario s on floor { grammar flat }\n"), "3:1", "names no elements"),
    (
        "max elements 0",
        spec(scenario="scenario s on floor { elements box max elements 0 }\n"),
        "3:36",
        "max elements must be within 1..1000, got 0",
    ),
    (
        "max elements beyond the slots' bound",
        spec(scenario="scenario s on floor { elements box max elements 100000 }\n"),
        "3:36",
        "max elements must be within 1..1000, got 100000",
    ),
    ("two scenarios", spec(tail=SCENARIO), "4:1", "only one scenario block per file"),
    (
        "positions beyond arena",
        spec(
            scenario="scenario s on floor { elements box placement grammar sizes 1..8 positions 100..900 }\n"
        ),
        "3:75",
        "positions up to 900 go beyond the arena",
    ),
]


@pytest.mark.parametrize(("name", "text", "where", "fragment"), BAD_SPECS, ids=[row[0] for row in BAD_SPECS])
def test_bad_spec_gives_located_message(write_spec, name, text, where, fragment):
    path = write_spec(text)
    with pytest.raises(MazeError) as caught:
        load_spec(path)
    message = str(caught.value)
    assert message.startswith(f"{caught.value.filename}:{where}: "), message
    assert caught.value.filename.endswith("spec.maze")
    assert fragment in message
    assert "\n" not in message


def test_missing_file_is_reported(tmp_path):
    with pytest.raises(MazeError, match="no such spec file"):
        load_spec(tmp_path / "absent.maze")


@pytest.mark.parametrize("text", ["", "   \n\n", "// only a comment\n"])
def test_a_file_that_declares_nothing_is_reported(write_spec, text):
    path = write_spec(text)
    for read in (check_file, load_spec):
        with pytest.raises(MazeError, match=r"spec\.maze: the file declares nothing \(a spec needs"):
            read(path)


def test_library_without_scenario_checks_but_does_not_load(write_spec):
    path = write_spec(ELEMENT)
    check_file(path)
    with pytest.raises(MazeError, match="no scenario declared"):
        load_spec(path)


def test_imported_file_may_not_hold_a_scenario(write_spec):
    write_spec(spec(), name="other.maze")
    path = write_spec(
        'import "other.maze"\n' + ARENA.replace("floor", "hall") + "scenario t on hall { elements box }\n"
    )
    with pytest.raises(MazeError, match="an imported file may declare only elements and arenas") as caught:
        load_spec(path)
    assert caught.value.filename.endswith("other.maze")


def test_error_in_imported_file_points_into_that_file(write_spec):
    write_spec("element bad { shape square size 9..1 }\n", name="lib.maze")
    path = write_spec('import "lib.maze"\n' + spec())
    with pytest.raises(MazeError) as caught:
        load_spec(path)
    assert caught.value.filename.endswith("lib.maze")
    assert (caught.value.line, caught.value.col) == (1, 33)


def test_library_check_finds_duplicate_names(write_spec):
    path = write_spec(ELEMENT + ELEMENT)
    with pytest.raises(MazeError, match="'box' is already declared at"):
        check_file(path)
