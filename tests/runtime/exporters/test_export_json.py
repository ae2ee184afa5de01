"""The published JSON Schema of scenario documents: every document MazeGen writes validates."""

from __future__ import annotations

import copy
import itertools
import json
import math

import jsonschema
import numpy as np
import pytest

import mazegen
from mazegen.runtime.documents._floor import load_floor
from mazegen.runtime.documents._scenario import completed_document, dumps, element_documents, read_document
from mazegen.runtime.engine._population import Population
from mazegen.runtime.exporters._documents import json_files
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.geometry._elements import ElementTable
from tests.conftest import EXAMPLES, ROOT

SCHEMA = json.loads((ROOT / "docs" / "scenario.schema.json").read_text(encoding="utf-8"))
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA, format_checker=jsonschema.FormatChecker())
ALL_EXAMPLES = sorted(EXAMPLES.glob("*.maze")) + sorted((EXAMPLES / "table1").glob("exp*.maze"))


def problems(document: dict) -> list[str]:
    """Each error's place, the rule it breaks and its message."""
    return [
        f"{'/'.join(map(str, error.absolute_path))} {error.validator}: {error.message}"
        for error in VALIDATOR.iter_errors(document)
    ]


def test_the_schema_is_a_valid_draft_2020_12_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("example", ALL_EXAMPLES, ids=lambda p: str(p.relative_to(EXAMPLES)))
def test_every_examples_scenarios_validate(example, tmp_path):
    result = mazegen.run(example, runs=1, population=40, generations=1)
    documents = result.best[0]
    assert documents
    for document in documents:
        assert problems(json.loads(json.dumps(document))) == []
        text = dumps(document, "best.json")
        (tmp_path / "best.json").write_text(text)
        assert read_document(tmp_path / "best.json") == json.loads(text)  # within every bound


def test_run_suite_and_completed_documents_validate(factory_run, tmp_path):
    documents = [json.loads(path.read_text()) for path in sorted(factory_run.glob("run-*/best-*.json"))]
    for document in documents:  # the path's corners span the path whose length the metrics give
        corners = document["path"]
        assert (corners is None) == (not document["metrics"]["solvable"])
        if corners:
            assert corners[0] == document["arena"]["start"] and corners[-1] == document["arena"]["goal"]
            length = sum(math.dist(a, b) for a, b in itertools.pairwise(corners))
            assert length == pytest.approx(document["metrics"]["path_length"], abs=1e-3)
    spec = mazegen.load(EXAMPLES / "factory.maze")
    hand = {
        "format": "mazegen-scenario",
        "version": 1,
        "elements": [{"type": "router", "x": 90, "y": 80, "size": 30}],
    }
    documents.append(completed_document(spec, hand, "hand.json"))
    for document in documents:
        assert problems(document) == []
    exported = json_files(load_floor(factory_run / "run-01" / "best-01.json"), ExportOptions())
    assert exported == {"best-01.json": (factory_run / "run-01" / "best-01.json").read_bytes()}


@pytest.mark.parametrize(
    ("change", "where"),
    [
        (lambda d: d["elements"][0].update(rotation=360.0), "rotation"),
        (lambda d: d["elements"][0].pop("parts"), "parts"),
        (lambda d: d["elements"][0].update(size=10.0, width=5.0, depth=5.0), "oneOf"),
        (lambda d: d["arena"].update(unit="ft"), "unit"),
        (lambda d: d.update(path=[[1.0, 2.0]]), "path"),
        (lambda d: d["metrics"].update(difficulty=101.0), "difficulty"),
        (lambda d: d.update(extra=1), "extra"),
    ],
)
def test_the_schema_rejects_damaged_documents(factory_run, change, where):
    document = json.loads((factory_run / "run-01" / "best-01.json").read_text())
    damaged = copy.deepcopy(document)
    change(damaged)
    found = problems(damaged)
    assert found and any(where in message for message in found), found


def test_rotations_just_under_a_turn_are_written_as_zero():
    spec = mazegen.load(EXAMPLES / "factory.maze")
    table = ElementTable.from_types(spec.scenario_elements)
    cobot = list(spec.scenario.elements).index("cobot")
    params = np.array([[[500.0, 500.0, 80.0, 80.0, math.radians(359.99996)]]])
    population = Population(
        np.array([[cobot]], np.int32),
        np.array([1], np.int32),
        lambda: params,
        np.array([True]),
        table,
        spec.arena,
    )
    (element,) = element_documents(spec, population, 0)
    assert element["rotation"] == 0.0
