"""Scenario files are read safely and checked against one table of rules, which the JSON Schema states too.

BAD_DOCUMENTS is the bad-input table of scenario files: each hostile file gives one line naming
the file and the JSON path of the bad value. A fuzzer mutates a whole document: whatever the
reader accepts passes the published schema, and nothing gives more than a one-line error.
"""

from __future__ import annotations

import copy
import json
import random
from pathlib import Path
from typing import Any

import jsonschema
import pytest

from mazegen.errors import MazeError
from mazegen.runtime.documents import _scenario_rules as scenario_rules
from mazegen.runtime.documents._floor import EXPORT_METRES_PER_UNIT
from mazegen.runtime.documents._scenario import read_document
from mazegen.runtime.documents._scenario_rules import DOCUMENT, Fields, Flag, Items, Number, Rule, Text
from tests.conftest import ROOT
from tests.runtime.scenario_mutants import HAND, mutant, nested, text_of, whole_document, write

SCHEMA = json.loads((ROOT / "docs" / "scenario.schema.json").read_text(encoding="utf-8"))
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA)


def changed(change):
    """A document's text after ``change(document)``."""

    def make(document: dict[str, Any]) -> str:
        document = copy.deepcopy(document)
        change(document)
        return text_of(document)

    return make


def replaced(old: str, new: str):
    """A document's text with the first ``old`` replaced by ``new``."""
    return lambda document: text_of(document).replace(old, new, 1)


@pytest.fixture(scope="module")
def whole() -> dict[str, Any]:
    return whole_document()


BAD_DOCUMENTS = [
    ("deep brackets", lambda d: "[" * 100_000, "nested deeper than 16 levels"),
    ("deep field", changed(lambda d: d.update(extra=nested(40))), "nested deeper than 16 levels"),
    ("5000 digits", replaced('"fitness": 1.5', '"fitness": ' + "9" * 5000), "a number of 5000 characters"),
    ("long decimals", replaced('"fitness": 1.5', '"fitness": 1.' + "5" * 100), "a number of 102 characters"),
    ("huge float", replaced('"fitness": 1.5', '"fitness": 1e400'), "1e400 is too large for a number"),
    ("NaN", replaced('"fitness": 1.5', '"fitness": NaN'), "NaN is not a number in JSON"),
    ("-Infinity", replaced('"fitness": 1.5', '"fitness": -Infinity'), "-Infinity is not a number in JSON"),
    ("tiny width", changed(lambda d: d["arena"].update(width=5e-324)),
     "arena.width: must be a number from 0.0001 to 1e+09, got 5e-324"),
    ("unit list", changed(lambda d: d["arena"].update(unit=["cm"])),
     'arena.unit: must be one of mm, cm, m, px, got ["cm"]'),
    ("unit unknown", changed(lambda d: d["arena"].update(unit="ft")),
     'arena.unit: must be one of mm, cm, m, px'),
    ("colour overflow", changed(lambda d: d["elements"][0].update(colour="rgb(99999999999999999999,0,0)")),
     'elements[0].colour: must be a colour: #rgb, #rrggbb, a colour name, or rgb(R, G, B) with R, G and B '
     'from 0 to 255, got "rgb(99999999999999999999,0,0)"'),
    ("colour 256", changed(lambda d: d["elements"][0].update(colour="rgb(256, 0, 0)")), "elements[0].colour"),
    ("negative height", changed(lambda d: d["elements"][1].update(height=-5)),
     "elements[1].height: must be a number from 0.0001 to 1e+09, got -5"),
    ("zero size", changed(lambda d: d["elements"][1].update(size=0)),
     "elements[1].size: must be a number from"),
    ("far x", changed(lambda d: d["elements"][2].update(x=2e9)),
     "elements[2].x: must be a number from -1e+09 to 1e+09, got 2000000000.0"),
    ("text x", changed(lambda d: d["elements"][0].update(x="abc")), 'elements[0].x: must be a number from'),
    ("boolean y", changed(lambda d: d["elements"][0].update(y=True)), "elements[0].y: must be a number"),
    ("a turn", changed(lambda d: d["elements"][0].update(rotation=360)),
     "elements[0].rotation: must be a number at least 0 and below 360, got 360"),
    ("1001 elements", changed(lambda d: d.update(elements=d["elements"] * 334)),
     "elements: must be a list of at most 1000 items, got 1002 items"),
    ("element not an object", changed(lambda d: d.update(elements=[3])),
     "elements[0]: must be an object, got 3"),
    ("control type", changed(lambda d: d["elements"][0].update(type="a\x01b")),
     'elements[0].type: must be a name without control characters, got "a\\u0001b"'),
    ("escape in class", changed(lambda d: d["elements"][0].update({"class": "\x1b]0;T\x07"})),
     "elements[0].class"),
    ("long type", changed(lambda d: d["elements"][0].update(type="t" * 201)),
     "elements[0].type: must be at most 200 characters long"),
    ("lone surrogate", replaced('"scenario": "factory"', '"scenario": "\\ud800"'),
     "scenario: must be a name"),
    ("short part", changed(lambda d: d["elements"][0].update(parts=[[[0, 0]]])),
     "elements[0].parts[0]: must be a list of 3 to 1024 items, got 1 items"),
    ("no parts", changed(lambda d: d["elements"][0].update(parts=[])),
     "elements[0].parts: must be a list of 1 to"),
    ("start of one", changed(lambda d: d["arena"].update(start=[1])),
     "arena.start: must be a list of exactly 2"),
    ("path of one", changed(lambda d: d.update(path=[[1, 2]])), "path: must be a list of 2 to 1000000 items"),
    ("negative radius", changed(lambda d: d["arena"].update(robot_radius=-1)), "arena.robot_radius"),
    ("metrics list", changed(lambda d: d.update(metrics=[])), "metrics: must be an object, got []"),
    ("coverage 2", changed(lambda d: d["metrics"].update(coverage=2)),
     "metrics.coverage: must be a number from 0"),
    ("solvable text", changed(lambda d: d["metrics"].update(solvable="yes")),
     'metrics.solvable: must be true or false, got "yes"'),
    ("negative codon", changed(lambda d: d["origin"].update(codons=[-1])),
     "origin.codons[0]: must be an integer at least 0, got -1"),
    ("short placement", changed(lambda d: d["origin"].update(placement=[[1, 2]])),
     "origin.placement[0]: must be a list of exactly 5 items"),
    ("text term", changed(lambda d: d["terms"].update(count="x")), 'terms.count: must be a number, got "x"'),
    ("negative member", changed(lambda d: d["elements"][0]["row"].update(member=-1)),
     "elements[0].row.member: must be an integer at least 0, got -1"),
    ("row of a number", changed(lambda d: d["elements"][0]["row"].update(name=3)),
     "elements[0].row.name: must be a string, got 3"),
    ("row a list", changed(lambda d: d["elements"][0].update(row=[0, 1])),
     "elements[0].row: must be an object"),
    ("control term name", changed(lambda d: d["terms"].update({"a\nb": 1})), "terms: a name: must be a name"),
    ("phenotype number", changed(lambda d: d.update(phenotype=5)),
     "phenotype: must be a string or null, got 5"),
    ("fitness text", changed(lambda d: d.update(fitness="high")),
     'fitness: must be a number or null, got "high"'),
    ("version 1.0", changed(lambda d: d.update(version=1.0)),
     "version: must be an integer equal to 1, got 1.0"),
    ("size and width", changed(lambda d: d["elements"][1].update(width=3)),
     "elements[1]: give 'size', or 'width' and 'depth' for a rect, not 'size', 'width'"),
    ("width alone", changed(lambda d: d["elements"][0].pop("depth")),
     "elements[0]: give 'size', or 'width' and"),
    ("drive outcome", changed(lambda d: d["drive"]["dwa"].update(outcome="crashed")),
     'drive.dwa.outcome: must be one of arrived, collision, timeout, no path, got "crashed"'),
    ("drive pose of two", changed(lambda d: d["drive"]["dwa"].update(trajectory=[[1, 2]])),
     "drive.dwa.trajectory[0]: must be a list of exactly 3 items, got 2 items"),
    ("drive far pose", changed(lambda d: d["drive"]["dwa"]["trajectory"][1].__setitem__(0, 1e10)),
     "drive.dwa.trajectory[1][0]: must be a number from -1e+09 to 1e+09"),
    ("drive negative time", changed(lambda d: d["drive"]["dwa"].update(time=-1)),
     "drive.dwa.time: must be a number from 0 to 1e+09, got -1"),
    ("drive score above BARN's", changed(lambda d: d["drive"]["dwa"].update(score=0.9)),
     "drive.dwa.score: must be a number from 0 to 0.5, got 0.9"),
    ("drive collision text", changed(lambda d: d["drive"]["straight"].update(collision="here")),
     'drive.straight.collision: must be a list or null, got "here"'),
    ("drive controller name", changed(lambda d: d["drive"].update({"a\x1bb": {}})),
     "drive: a name: must be a name"),
    ("drive not an object", changed(lambda d: d.update(drive=[])), "drive: must be an object, got []"),
    ("not UTF-8", lambda d: "\udcff", "cannot read scenario: not UTF-8 text"),
    ("not JSON", lambda d: "{not json", "floor.json:1:2: not valid JSON: Expecting property name"),
]  # fmt: skip


def error_of(path: Path) -> str:
    with pytest.raises(MazeError) as caught:
        read_document(path)
    return str(caught.value)


@pytest.mark.parametrize(
    ("make", "fragment"), [row[1:] for row in BAD_DOCUMENTS], ids=[r[0] for r in BAD_DOCUMENTS]
)
def test_a_hostile_scenario_file_is_one_line(whole, tmp_path, make, fragment):
    path = write(tmp_path / "floor.json", make(whole))
    message = error_of(path)
    assert message.startswith(f"{path}") and fragment in message and "\n" not in message, message


def test_the_number_that_is_too_long_is_located(whole, tmp_path):
    text = text_of(whole).replace('"fitness": 1.5', '"fitness":\n  ' + "9" * 50)
    path = write(tmp_path / "floor.json", text)
    line = text[: text.index("9" * 50)].count("\n") + 1
    assert error_of(path).startswith(f"{path}:{line}:3: not valid JSON: a number of 50 characters")


def test_a_file_too_large_is_refused_before_it_is_parsed(whole, tmp_path, monkeypatch):
    monkeypatch.setattr(scenario_rules, "MAX_FILE_BYTES", 2**20)
    path = write(tmp_path / "floor.json", text_of(whole) + " " * 2**20)
    assert error_of(path) == f"{path}: larger than 1 MiB: not a scenario file"


def test_hand_written_floors_and_whole_documents_pass(whole, tmp_path):
    path = write(
        tmp_path / "hand.json", json.dumps({"format": "mazegen-scenario", "version": 1, "elements": HAND})
    )
    assert read_document(path)["elements"] == HAND
    assert read_document(write(tmp_path / "whole.json", text_of(whole))) == whole
    assert list(VALIDATOR.iter_errors(whole)) == []


def test_a_document_without_its_drive_is_read_and_the_drive_outcomes_are_the_simulators(whole, tmp_path):
    from mazegen.runtime.simulation import OUTCOMES

    bare = {key: value for key, value in whole.items() if key != "drive"}
    assert "drive" not in read_document(write(tmp_path / "bare.json", text_of(bare)))
    assert read_document(write(tmp_path / "driven.json", text_of(whole)))["drive"] == whole["drive"]
    assert OUTCOMES == scenario_rules.DRIVE_OUTCOMES


def test_the_units_are_those_exports_know():
    assert set(EXPORT_METRES_PER_UNIT) == set(scenario_rules.UNITS)


def test_at_most_the_elements_the_language_allows():
    from mazegen.dsl.blocks import MAX_SLOTS

    assert scenario_rules.MAX_ELEMENTS == MAX_SLOTS


# --- the schema states the table's rules -------------------------------------------------------------


def resolved(node: dict[str, Any]) -> dict[str, Any]:
    """``node`` with its ``$ref`` (one level of ``#/$defs/NAME``) merged in."""
    if "$ref" not in node:
        return node
    target = SCHEMA["$defs"][node["$ref"].removeprefix("#/$defs/")]
    return resolved({**target, **{k: v for k, v in node.items() if k != "$ref"}})


def without_null(node: dict[str, Any]) -> tuple[dict[str, Any], bool]:
    """The schema of a value that may also be null, and whether it may."""
    node = resolved(node)
    if "oneOf" in node and {"type": "null"} in node["oneOf"]:
        (other,) = [resolved(n) for n in node["oneOf"] if n != {"type": "null"}]
        return other, True
    kinds = node.get("type")
    if isinstance(kinds, list) and "null" in kinds:
        (kind,) = [k for k in kinds if k != "null"]
        return {**node, "type": kind}, True
    return node, False


def schema_agrees(rule: Rule, node: dict[str, Any], where: str) -> list[str]:
    """Where the schema ``node`` of the value at ``where`` says something else than ``rule``."""
    node, null = without_null(node)
    found = [f"{where}: null"] if null != getattr(rule, "null", False) else []
    if isinstance(rule, Number):
        want = {
            "type": "integer" if rule.integer else "number",
            "exclusiveMinimum" if rule.low_open else "minimum": rule.low,
            "exclusiveMaximum" if rule.high_open else "maximum": rule.high,
        }
    elif isinstance(rule, Text) and rule.choices is not None:
        want = {"enum": list(rule.choices)} if len(rule.choices) > 1 else {"const": rule.choices[0]}
    elif isinstance(rule, Text):
        want = {"type": "string", "maxLength": rule.longest, "pattern": rule.pattern}
    elif isinstance(rule, Flag):
        want = {"type": "boolean"}
    elif isinstance(rule, Items):
        want = {"type": "array", "minItems": rule.least or None, "maxItems": rule.most}
        found += schema_agrees(rule.item, node.get("items", {}), f"{where}[]")
    elif isinstance(rule, Fields):
        want = {"type": "object"}
        if set(rule.fields) != set(node.get("properties", {})):
            found.append(f"{where}: fields {sorted(rule.fields)} != {sorted(node.get('properties', {}))}")
        for key, inner in rule.fields.items():
            found += schema_agrees(inner, node.get("properties", {}).get(key, {}), f"{where}.{key}")
    else:
        want = {"type": "object"}
        found += schema_agrees(Text(), {"type": "string", **node.get("propertyNames", {})}, f"{where} names")
        found += schema_agrees(rule.value, node.get("additionalProperties", {}), f"{where}.*")
    for key, value in want.items():
        if node.get(key) != value and not (value is None and key not in node):
            found.append(f"{where}: {key} is {node.get(key)!r}, the table says {value!r}")
    return found


def test_the_schema_states_the_rules_of_the_table():
    assert schema_agrees(DOCUMENT, SCHEMA, "") == []


# --- a fuzzer over scenario files ---------------------------------------------------------------------


def test_fuzzed_documents_are_read_or_refused_in_one_line_and_what_is_read_passes_the_schema(whole, tmp_path):
    chance = random.Random(19)
    outcomes = {"read": 0, "refused": 0}
    for index in range(400):
        text, replaced_one = mutant(whole, chance)
        path = write(tmp_path / f"m{index}.json", text)
        try:
            document = read_document(path)
        except MazeError as error:
            assert "\n" not in str(error) and str(error).startswith(str(path)), (text[:200], str(error))
            outcomes["refused"] += 1
            continue
        outcomes["read"] += 1
        if replaced_one:
            assert list(VALIDATOR.iter_errors(document)) == [], text[:300]
    assert min(outcomes.values()) > 40, outcomes
