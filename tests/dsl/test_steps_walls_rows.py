"""Steps, walls and rows in the language: what they convert to, their units, their grammar and spec.json
(their mistakes are rows of tests/dsl/test_errors.py)."""

from __future__ import annotations

import pytest

from mazegen.dsl.loader import check_file, load_spec
from mazegen.errors import MazeError
from mazegen.generator.build import grammar_text
from mazegen.runtime.engine import map_genome, parse_bnf
from mazegen.spec import Spec

ARENA = "arena hall { size 20 x 15 m  start (1, 1)  goal (19, 14)  robot radius 0.25 }\n"
LIBRARY = """units cm
element rack { shape rect  size 200..400 step 50 x 80..110  rotation 0, 90 }
element crate { shape square  size 40..60  at step 50 }
element locker { shape rect  size 60..100 x 40..50  against wall }
element kiosk { shape square  size 50  rotation 0, 180  against wall }
row rackRow of rack { count 2..5  spacing 40..80 step 10 }
row lockers of locker { count 3  spacing 0.05 m  rotation 0, 90 }
"""


def load(write_spec, scenario: str, library: str = LIBRARY, arena: str = ARENA) -> Spec:
    write_spec(library, "lib.maze")
    return load_spec(write_spec('import "lib.maze"\n' + arena + scenario))


def test_lengths_convert_from_the_files_units_or_their_own(write_spec):
    spec = load(write_spec, "scenario s on hall { elements rackRow, crate, lockers }\n")
    rack, crate = spec.element("rack"), spec.element("crate")
    assert (rack.size, rack.size_step, rack.depth_step) == ((2.0, 4.0), 0.5, None)
    assert crate.position_step == 0.5 and crate.size_step is None
    row, lockers = spec.scenario.rows
    assert (row.count, row.spacing, row.spacing_step) == ((2, 5), (0.4, 0.8), pytest.approx(0.1))
    assert lockers.spacing == pytest.approx((0.05, 0.05))  # its own unit, whatever the file's
    library = LIBRARY.replace("at step 50", "at step 0.25 m")
    assert (
        load(write_spec, "scenario s on hall { elements crate }\n", library).element("crate").position_step
        == 0.25
    )


def test_an_element_against_a_wall_turns_its_back_to_the_walls_its_rotations_name(write_spec):
    spec = load(write_spec, "scenario s on hall { elements locker, kiosk, lockers }\n")
    assert spec.element("locker").rotations == (0.0, 90.0, 180.0, 270.0)  # no rotation: every wall
    assert spec.element("kiosk").rotations == (0.0, 180.0)
    assert spec.element("locker").against_wall
    assert spec.scenario.rows[0].rotations == (0.0, 90.0)


def test_a_row_turns_as_its_members_unless_it_says(write_spec):
    library = LIBRARY + "row plain of crate { count 2  spacing 10 }\n"
    library += "row turned of rack { count 2  spacing 10  rotation any }\n"
    spec = load(write_spec, "scenario s on hall { elements plain, turned, rackRow }\n", library)
    plain, turned, rack_row = spec.scenario.rows
    assert (plain.rotations, plain.rotation_range) == ((0.0,), None)
    assert turned.rotation_range == (0.0, 360.0)
    assert rack_row.rotations == (0.0, 90.0)


def test_a_rows_members_are_element_types_of_the_scenario_whether_listed_or_not(write_spec):
    spec = load(write_spec, "scenario s on hall { elements crate, rackRow, rack }\n")
    assert spec.scenario.elements == ("crate", "rack")  # ids: each type once, in order of first use
    assert spec.scenario.entries == ("crate", "rackRow", "rack")
    assert spec.row_tokens == (("rackRow", 1, 2, 5),)


GRAMMARS = {
    "nested": [
        "<scenario> ::= crate | rackRow(<rackRow-count>) | <composed>",
        "<composed> ::= crate(<scenario>) | rackRow(<rackRow-count>,<scenario>)",
        "<rackRow-count> ::= 2 | 3 | 4 | 5",
    ],
    "flat": [
        "<scenario> ::= crate() | rackRow(<rackRow-count>) | crate(<scenario>) "
        "| rackRow(<rackRow-count>,<scenario>)",
        "<rackRow-count> ::= 2 | 3 | 4 | 5",
    ],
    "list": [
        "<scenario> ::= <element> | <element> <scenario>",
        "<element> ::= crate | rackRow(<rackRow-count>)",
        "<rackRow-count> ::= 2 | 3 | 4 | 5",
    ],
    "custom { <s> ::= <pair> | <pair> <s>\n <pair> ::= crate rackRow | rackRow crate }": [
        "<s> ::= <pair> | <pair> <s>",
        "<pair> ::= crate rackRow(<rackRow-count>) | rackRow(<rackRow-count>)crate",  # no word to part
        "<rackRow-count> ::= 2 | 3 | 4 | 5",
    ],
}


@pytest.mark.parametrize("style", GRAMMARS)
def test_a_row_is_an_alternative_of_the_grammar_and_its_count_a_choice(write_spec, style):
    spec = load(write_spec, f"scenario s on hall {{ elements crate, rackRow  grammar {style} }}\n")
    rules = [line for line in grammar_text(spec).splitlines() if line and not line.startswith("#")]
    assert rules == GRAMMARS[style]


def test_a_genome_derives_a_row_and_its_count(write_spec):
    spec = load(write_spec, "scenario s on hall { elements crate, rackRow }\n")
    grammar = parse_bnf(grammar_text(spec))
    # <scenario> -> <composed> (2), -> rackRow(<count>,<scenario>) (1), count 4 (2), <scenario> -> crate (0)
    assert map_genome(grammar, [2, 1, 2, 0]).phenotype == "rackRow(4,crate)"


def test_a_spec_without_structure_writes_spec_json_as_before(write_spec):
    spec = load(
        write_spec,
        "scenario s on hall { elements rack }\n",
        "units cm\nelement rack { shape rect  size 200 x 80 }\n",
    )
    text = spec.to_json()
    for key in ("position_step", "size_step", "depth_step", "against_wall", '"rows"', '"listed"'):
        assert key not in text
    assert Spec.from_json(text) == spec


def test_spec_json_keeps_steps_walls_and_rows(write_spec):
    spec = load(write_spec, "scenario s on hall { elements rackRow, crate, lockers, kiosk }\n")
    assert Spec.from_json(spec.to_json()) == spec


def test_a_library_checks_its_rows_on_its_own(write_spec):
    check_file(write_spec(LIBRARY, "library.maze"))
    bad = write_spec(LIBRARY + "row loose of rack { count 2  spacing 0 }\n", "bad.maze")
    with pytest.raises(MazeError, match=r"bad\.maze:8:\d+: spacing must be positive, got 0"):
        check_file(bad)


def test_a_row_of_a_held_type_fits_the_box_of_all_its_zones(write_spec):
    """Members may stand in different zones: the check is of the zones' box together, never too strict."""
    zones = "zone a rect (1, 1) (5, 3) holds rack  zone b rect (5, 1) (9, 3) holds rack"
    arena = ARENA.replace("robot radius 0.25", f"robot radius 0.25 {zones}")
    library = LIBRARY.replace("count 2..5", "count 3").replace("rotation 0, 90 }", "rotation 0 }")
    spec = load(
        write_spec, "scenario s on hall { elements rackRow }\n", library, arena
    )  # 3 x 2 m + 2 gaps: 6.8 m
    assert spec.scenario.rows[0].count == (3, 3)
