"""A row's members in scenario documents: ordinary elements with their ``row``, written, checked against
the schema, read back, scored and completed."""

from __future__ import annotations

import json

import jsonschema
import numpy as np
import pytest

from mazegen.dsl.loader import load_spec
from mazegen.generator.build import build
from mazegen.runtime.documents import Scorer, read_document
from mazegen.runtime.documents._scenario import (
    completed_document,
    dumps,
    population_from_document,
    scenario_document,
)
from mazegen.runtime.engine import Problem
from mazegen.runtime.geometry import ElementTable
from tests.conftest import ROOT
from tests.runtime.engine.test_placement import SPEC

SCHEMA = json.loads((ROOT / "docs" / "scenario.schema.json").read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def floors(tmp_path_factory):
    """Documents of 40 floors of the structure spec, the most rows first."""
    folder = tmp_path_factory.mktemp("rows")
    (folder / "store.maze").write_text(SPEC, encoding="utf-8")
    spec = load_spec(folder / "store.maze")
    build(spec, folder / "build")
    problem = Problem.from_build_dir(folder / "build")
    rng = np.random.default_rng(8)
    codons = rng.integers(0, 256, size=(400, spec.evolution.genome), dtype=np.int32)
    genes = rng.integers(0, 65536, size=(400, problem.slots, 5), dtype=np.uint16)
    evaluation = problem.evaluate(codons, genes)
    members = (evaluation.mapped.membership[..., 0] >= 0).sum(axis=1)
    rows = np.argsort(-members, kind="stable")[:40]
    documents = [
        scenario_document(
            spec, evaluation.population, int(row), phenotype=None, fitness=1.0, terms={}, origin={}
        )
        for row in rows
    ]
    return spec, folder, documents


def test_members_carry_their_row(floors):
    spec, _, documents = floors
    names = {row.name for row in spec.scenario.rows}
    for document in documents:
        seen: list[tuple[str, int]] = []
        for element in document["elements"]:
            row = element.get("row")
            if row is None:
                continue
            assert row["name"] in names
            assert (
                element["type"]
                == spec.scenario.rows[[r.name for r in spec.scenario.rows].index(row["name"])].member
            )
            if row["member"] == 0:
                seen.append((row["name"], row["index"]))
            assert seen[-1] == (row["name"], row["index"])  # a row's members follow its first
        assert [index for _, index in seen] == list(range(len(seen)))
    assert sum(len(document["elements"]) for document in documents) > 100


def test_documents_with_rows_pass_the_schema_and_read_back(floors, tmp_path):
    spec, _, documents = floors
    validator = jsonschema.Draft202012Validator(SCHEMA)
    for number, document in enumerate(documents):
        path = tmp_path / f"floor{number}.json"
        path.write_text(dumps(document, path.name), encoding="utf-8")
        read = read_document(path)
        assert list(validator.iter_errors(read)) == []
        population = population_from_document(
            spec, ElementTable.from_types(spec.scenario_elements), read, str(path)
        )
        assert population.n_elements[0] == len(document["elements"])
        completed = completed_document(
            spec, {k: read[k] for k in ("format", "version", "elements")}, str(path)
        )
        assert [e.get("row") for e in completed["elements"]] == [e.get("row") for e in document["elements"]]
        for again, written in zip(completed["elements"], document["elements"]):  # from rounded placements
            assert np.allclose(np.concatenate(again["parts"]), np.concatenate(written["parts"]), atol=3e-4)


def test_documents_with_rows_are_scored_as_their_floors_were(floors, tmp_path):
    """``mazegen score`` reads a row's members as elements: the same count and overlaps as the run's."""
    spec, _, documents = floors
    with Scorer.built(spec) as scorer:
        for number, document in enumerate(documents[:5]):
            path = tmp_path / f"floor{number}.json"
            path.write_text(dumps(document, path.name), encoding="utf-8")
            scored = scorer.score(path, note=lambda line: None)
            assert scored.elements == len(document["elements"])
            assert scored.terms["count"] == len(document["elements"])
