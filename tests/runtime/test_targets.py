"""Fitness terms that steer what evolution finds: difficulty targets, diversity and coverage."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

import mazegen
from mazegen.fitness_terms import reads_survey
from mazegen.generator.build import fitness_lines
from mazegen.spec import DIFFICULTY_LEVELS, Spec
from tests.conftest import EXAMPLES
from tests.runtime.floors import geometrically_solvable

WORKSHOP = (EXAMPLES / "workshop.maze").read_text()


def workshop_with(line: str, tmp_path) -> Spec:
    """The workshop example with its coverage term replaced by ``line``."""
    old = "    coverage 0.10..0.30 weight 4 // a well-filled floor, not a crowded one"
    assert old in WORKSHOP
    path = tmp_path / f"{abs(hash(line))}.maze"
    path.write_text(WORKSHOP.replace(old, f"    {line}"))
    return mazegen.load(path)


def test_new_terms_render_as_rewards_with_their_targets(tmp_path):
    spec = workshop_with("difficulty target hard weight 3\n    tortuosity 1.4..2.0 weight 2", tmp_path)
    scored, rejected = fitness_lines(spec)
    lines = {line.key: line.expression for line in scored}
    low, high = DIFFICULTY_LEVELS["hard"]
    assert lines["difficulty"] == f"3.0 * metrics.closeness(metrics.difficulty(pop), {low!r}, {high!r})"
    assert lines["tortuosity"] == "2.0 * metrics.closeness(metrics.path_metric(pop, 'tortuosity'), 1.4, 2.0)"
    assert lines["diversity"] == "2.0 * metrics.distinct_types(pop)"
    assert {line.key for line in rejected} == {"overlap", "outside", "solvable"}
    assert reads_survey(spec)
    assert Spec.from_json(spec.to_json()) == spec


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_hard_targets_give_harder_floors_than_easy_ones(tmp_path, seed):
    difficulty = {}
    for level in ("easy", "hard"):
        spec = workshop_with(f"difficulty target {level} weight 20", tmp_path)
        documents = mazegen.run(spec, seed=seed, population=300, generations=10).best[0]
        difficulty[level] = np.mean([document["metrics"]["difficulty"] for document in documents])
    assert difficulty["hard"] > difficulty["easy"] + 3


def test_workshop_fills_the_floor_with_many_kinds_and_keeps_a_way_through():
    """The paper's overlap-penalised runs stopped at 4 elements."""
    result = mazegen.run(EXAMPLES / "workshop.maze", seed=1)
    best = result.best[0][0]
    elements = best["elements"]
    assert len(elements) >= 12 and len({element["type"] for element in elements}) >= 4
    assert geometrically_solvable(best) and best["metrics"]["solvable"]
    shapes = [shapely.union_all([Polygon(part) for part in element["parts"]]) for element in elements]
    for a, b in itertools.combinations(shapes, 2):
        assert a.intersection(b).area < 1e-6
    width, height = best["arena"]["width"], best["arena"]["height"]
    floor = shapely.box(0, 0, width, height)
    assert all(floor.covers(shape) for shape in shapes)
    assert best["metrics"]["coverage"] >= 0.10
