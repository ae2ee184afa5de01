"""The evolution block's choice of crossover and mutation operators: parsed, kept in spec.json,
and a spec.json written before operators were a setting runs the operators it always ran."""

from __future__ import annotations

import json

import pytest

import mazegen
from mazegen.spec import FIRST_OPERATORS, Evolution, Spec
from tests.dsl.test_errors import spec


@pytest.mark.parametrize(
    ("written", "crossover", "mutation"),
    [
        ("crossover onepoint within used 0.8", "onepoint within used", Evolution.mutation_operator),
        ("crossover onepoint 0.8", "onepoint within used", Evolution.mutation_operator),
        ("crossover variable 0.8\n mutation within genome 0.1", "variable within used", "within genome"),
        (
            "crossover onepoint within genome 0.8 mutation within used 0.1",
            "onepoint within genome",
            "within used",
        ),
        ("crossover 0.8", Evolution.crossover_operator, Evolution.mutation_operator),
    ],
)
def test_operators_parse_and_round_trip_through_spec_json(write_spec, written, crossover, mutation):
    loaded = mazegen.load(write_spec(spec(tail=f"evolution {{ {written} }}\n")))
    assert (loaded.evolution.crossover_operator, loaded.evolution.mutation_operator) == (crossover, mutation)
    assert loaded.evolution.crossover == 0.8
    assert Spec.from_json(loaded.to_json()) == loaded


def test_a_spec_json_without_operators_runs_the_first_ones(write_spec):
    loaded = mazegen.load(write_spec(spec(tail="evolution { crossover variable 0.8 }\n")))
    data = json.loads(loaded.to_json())
    del data["evolution"]["crossover_operator"], data["evolution"]["mutation_operator"]
    evolution = Spec.from_json(json.dumps(data)).evolution
    assert (evolution.crossover_operator, evolution.mutation_operator) == tuple(FIRST_OPERATORS.values())


def test_an_unknown_operator_in_spec_json_is_refused():
    with pytest.raises(ValueError, match="crossover operator must be one of"):
        Evolution(crossover_operator="uniform")
    with pytest.raises(ValueError, match="mutation operator must be one of"):
        Evolution(mutation_operator="within tail")
