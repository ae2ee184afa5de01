"""Scenario documents to attack the readers with: a complete document, and seeded mutants of it."""

from __future__ import annotations

import copy
import json
import random
from pathlib import Path
from typing import Any

import mazegen
from mazegen.runtime.documents._scenario import completed_document
from tests.conftest import EXAMPLES

HAND = [
    {"type": "productionLine", "x": 700, "y": 525, "width": 500, "depth": 80, "rotation": 0},
    {"type": "router", "x": 500, "y": 525, "size": 30},
    {"type": "cobot", "x": 300, "y": 300, "size": 100, "rotation": 30},
]


def whole_document() -> dict[str, Any]:
    """A complete document of examples/factory.maze, every field of the format present."""
    spec = mazegen.load(EXAMPLES / "factory.maze")
    document = completed_document(spec, {"format": "mazegen-scenario", "version": 1, "elements": HAND}, "x")
    document.update(
        phenotype="productionLine(router(cobot))", fitness=1.5, terms={"count": 3.0, "overlap": -1.5}
    )
    document["elements"][0]["row"] = {"name": "lineRow", "index": 0, "member": 0}
    document["origin"] = {
        "seed": 1,
        "run": 1,
        "generation": 2,
        "rank": 1,
        "codons": [3, 1, 4],
        "placement": [[1, 2, 3, 4, 5]] * 3,
        "suite": {"cell": 0, "difficulty": "0-10", "elements": "1-3"},
    }
    document["drive"] = {
        "straight": {
            "outcome": "collision",
            "time": 1.2,
            "distance": 60.0,
            "clearance": 0.0,
            "optimal_time": 32.8,
            "score": 0.0,
            "stuck": False,
            "collision": [120.0, 60.0],
            "trajectory": [[60.0, 60.0, 36.0], [90.0, 60.0, 0.0], [120.0, 60.0, 0.0]],
        },
        "dwa": {
            "outcome": "arrived",
            "time": 70.1,
            "distance": 1650.2,
            "clearance": 12.5,
            "optimal_time": 32.8,
            "score": 0.4679,
            "stuck": False,
            "collision": None,
            "trajectory": [[60.0, 60.0, 36.0], [1340.0, 990.0, 36.0]],
        },
    }
    return json.loads(json.dumps(document))


def text_of(document: dict[str, Any]) -> str:
    return json.dumps(document, allow_nan=True)


def nested(depth: int) -> Any:
    value: Any = 0
    for _ in range(depth):
        value = [value]
    return value


def write(path: Path, text: str) -> Path:
    path.write_bytes(text.encode("utf-8", "surrogateescape"))
    return path


HOSTILE_VALUES: list[Any] = [
    None, True, 0, -1, 1, 5e-324, 1e-5, 1e9, 2e9, -1e308, 1e308, 359.9999, 360, 10**30, 2**63,
    "", "x" * 300, "a\x00b", "\x1b]0;T\x07", "rgb(256,0,0)", "rgb(1, 2, 3)", "red", "#12345g", "cm", "<&]]>",
    "rgb(99999999999999999999,0,0)", ["cm"], -5, 1e-300,
    [], [0], [1, 2], [[0, 0], [1, 1]], [[0, 0], [1, 0], [0, 1]], {}, {"x": 1}, nested(20),
]  # fmt: skip


def places(value: Any, where: tuple = ()) -> list[tuple]:
    """Every path into ``value`` (keys and indices), the value's own included."""
    found = [where]
    if isinstance(value, dict):
        for key, inner in value.items():
            found += places(inner, (*where, key))
    elif isinstance(value, list):
        for index, inner in enumerate(value[:3]):
            found += places(inner, (*where, index))
    return found


def mutant(document: dict[str, Any], chance: random.Random, *, within: str = "") -> tuple[str, bool]:
    """A mutated document's text, and whether only one value was replaced by a scalar or list.

    ``within`` a top-level field (``elements``): only values inside it are changed.
    """
    document = copy.deepcopy(document)
    how = chance.random()
    if how < 0.1:
        text = text_of(document)
        cut = chance.randrange(len(text))
        noise = chance.choice(["", "[" * 5000, "\x01", "9" * 400, '"\\ud800"', "NaN"])
        return text[:cut] + noise + text[cut:], False
    where = chance.choice([place for place in places(document)[1:] if place[0].startswith(within)])
    *parents, last = where
    parent = document
    for key in parents:
        parent = parent[key]
    if how < 0.25 and isinstance(parent, dict):
        del parent[last]
        return text_of(document), False
    value = chance.choice(HOSTILE_VALUES)
    parent[last] = copy.deepcopy(value)
    return text_of(document), not isinstance(value, dict)
