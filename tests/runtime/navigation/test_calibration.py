"""The difficulty score's versions and its calibration against measured traversal (docs/difficulty.md)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from mazegen.runtime.documents._scenario_rules import check_document
from mazegen.runtime.navigation._calibration import (
    fit_nonnegative,
    folds,
    held_out_r_squared,
    ranks,
    read_calibration,
    score_fit,
    spearman,
)
from mazegen.runtime.navigation._difficulty import (
    DIFFICULTY_VERSION,
    HARDNESS,
    INTERCEPT,
    METRICS,
    WEIGHTS,
    difficulty_score,
    survey,
)
from tests.runtime.floors import ARENA, population

ROOT = Path(__file__).resolve().parents[3]
DATA = Path(__file__).with_name("calibration_data.csv")


def random_table(rng: np.random.Generator, n: int, scale: float) -> np.ndarray:
    table = np.empty((n, len(METRICS)))
    column = {name: k for k, name in enumerate(METRICS)}
    for name in ("clearance", "visibility", "dimension", "narrowest"):
        table[:, column[name]] = rng.uniform(0, 20 * scale, n)
    table[:, column["dispersion"]] = rng.uniform(0, 16, n)
    table[:, column["tortuosity"]] = rng.uniform(1, 3, n)
    table[:, column["path_ratio"]] = rng.uniform(1, 1.5, n)
    return table


def test_version_1_is_the_mean_of_barns_five_hardnesses():
    """Version 1 as it was computed before version 2 (its code, verbatim), bit for bit."""
    scale = 20.0
    table = random_table(np.random.default_rng(3), 200, scale)
    column = {name: table[:, k] for k, name in enumerate(METRICS)}
    hardness = (
        np.exp(-column["clearance"] / (2.0 * scale)),
        np.exp(-column["visibility"] / (8.0 * scale)),
        1.0 - np.exp(-column["dispersion"] / 2.0),
        np.exp(-column["dimension"] / (4.0 * scale)),
        1.0 - np.exp(-(column["tortuosity"] - 1.0) / 0.5),
    )
    assert np.array_equal(difficulty_score(table, scale, version=1), 100.0 * np.mean(hardness, axis=0))


def test_version_2_is_monotone_and_bounded():
    """Harder on any metric never scores lower; scores stay in [0, 100]; no path is NaN."""
    scale = 20.0
    rng = np.random.default_rng(4)
    table = random_table(rng, 300, scale)
    score = difficulty_score(table, scale)
    assert ((score >= 0) & (score <= 100)).all()
    harder = table.copy()
    for name in ("clearance", "visibility", "dimension", "narrowest"):
        harder[:, METRICS.index(name)] *= 0.5
    for name in ("dispersion", "tortuosity", "path_ratio"):
        harder[:, METRICS.index(name)] *= 1.2
    assert (difficulty_score(harder, scale) >= score).all()
    assert np.isnan(difficulty_score(np.full((1, len(METRICS)), np.nan), scale)).all()
    with pytest.raises(ValueError, match="version 3"):
        difficulty_score(table, scale, version=3)


def test_the_weights_are_refitted_from_the_saved_calibration_data():
    """benchmarks/calibration.py --save wrote the data; fitting it again gives the score's weights."""
    fit = score_fit(read_calibration(DATA))
    assert fit.intercept == pytest.approx(INTERCEPT, abs=5e-5)
    assert fit.weights == pytest.approx(WEIGHTS, abs=5e-5)


def test_the_docs_state_the_weights_in_use():
    """docs/difficulty.md's table of version 2 gives each term's weight as the code has it."""
    page = (ROOT / "docs" / "difficulty.md").read_text(encoding="utf-8")
    stated = dict(re.findall(r"^\| `([a-z_]+)` hardness \| `[^`]+` \| ([0-9.]+) \|$", page, re.M))
    assert stated == {name: f"{weight:.4f}" for name, weight in zip(HARDNESS, WEIGHTS)}
    assert f"intercept {INTERCEPT:.4f}" in page


def test_nonnegative_fit_finds_planted_weights_and_drops_negative_ones():
    rng = np.random.default_rng(5)
    features = rng.random((400, 4))
    target = 0.1 + features @ np.array([0.5, 0.0, 0.3, -0.4]) + rng.normal(0, 0.01, 400)
    fit = fit_nonnegative(features, target)
    assert fit.weights[3] == 0.0 and (fit.weights >= 0).all()
    assert fit.weights[0] == pytest.approx(0.5, abs=0.05) and fit.weights[2] == pytest.approx(0.3, abs=0.05)


def test_spearman_and_held_out_r_squared():
    x = np.array([1.0, 2.0, 2.0, 5.0, 9.0])
    assert np.array_equal(ranks(x), [0.0, 1.5, 1.5, 3.0, 4.0])
    assert spearman(x, x**3) == pytest.approx(1.0)
    assert spearman(x, -x) == pytest.approx(-1.0)
    rng = np.random.default_rng(6)
    score = rng.random(300)
    fold = folds(300, 10, 1)
    assert sorted(np.bincount(fold)) == [30] * 10
    assert held_out_r_squared(score, 2 * score + 1, fold) == pytest.approx(1.0)
    assert held_out_r_squared(score, rng.random(300), fold) < 0.05


def test_documents_say_their_score_version_and_older_ones_still_read():
    """New documents carry difficulty_version 2; a document without it (version 1) still reads."""
    summary = survey(population(ARENA, [[]])).summary(0)
    assert summary["difficulty_version"] == DIFFICULTY_VERSION == 2
    metrics = {k: v for k, v in summary.items() if k != "difficulty_version"}
    check_document({"metrics": metrics}, "old.json")
    check_document({"metrics": metrics | {"difficulty_version": 1}}, "old.json")
    with pytest.raises(Exception, match="difficulty_version"):
        check_document({"metrics": metrics | {"difficulty_version": 3}}, "new.json")
