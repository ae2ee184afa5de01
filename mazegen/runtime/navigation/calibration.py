"""Fitting the difficulty score to measured traversal: rank correlation, held-out R², and
non-negative least squares over the metrics' hardness terms.

``benchmarks/calibration.py`` drives the bundled controllers over a suite of floors and saves, per
floor, the metrics and the measured difficulty; :func:`fit_score` turns that into the weights of
:data:`mazegen.runtime.navigation.difficulty.WEIGHTS` (version 2 of the score), and a test refits
them from the saved data. Plain NumPy: a handful of features, a few hundred floors.
"""

from __future__ import annotations

import csv
import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mazegen.runtime.navigation.difficulty import METRICS, hardness


def ranks(values: np.ndarray) -> np.ndarray:
    """Ranks from 0, ties given their mean rank (as Spearman's ρ needs)."""
    values = np.asarray(values, np.float64)
    order = np.argsort(values, kind="stable")
    sorted_values = values[order]
    rank = np.empty(len(values))
    start = 0
    for end in range(1, len(values) + 1):
        if end == len(values) or sorted_values[end] != sorted_values[start]:
            rank[order[start:end]] = (start + end - 1) / 2.0
            start = end
    return rank


def spearman(x: np.ndarray, y: np.ndarray) -> float:
    """Spearman's rank correlation of ``x`` and ``y`` (NaN when either is constant)."""
    a, b = ranks(x), ranks(y)
    a, b = a - a.mean(), b - b.mean()
    scale = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / scale) if scale > 0 else float("nan")


def r_squared(truth: np.ndarray, predicted: np.ndarray) -> float:
    """Coefficient of determination of ``predicted`` against ``truth`` (1 − SSE / SST)."""
    residual = float(((truth - predicted) ** 2).sum())
    total = float(((truth - truth.mean()) ** 2).sum())
    return 1.0 - residual / total if total > 0 else float("nan")


@dataclass(frozen=True)
class Fit:
    """A linear model ``intercept + features @ weights`` with non-negative weights."""

    intercept: float
    weights: np.ndarray

    def predict(self, features: np.ndarray) -> np.ndarray:
        """The model's prediction for each row of ``features``."""
        return self.intercept + features @ self.weights


def fit_nonnegative(features: np.ndarray, target: np.ndarray) -> Fit:
    """Least squares with a free intercept and non-negative weights.

    The constrained optimum is the unconstrained least-squares fit on some subset of the
    features whose weights all come out non-negative, so every subset is tried (a handful of
    features: at most a few hundred small solves) and the best admissible one kept. Exact and
    deterministic, with no iterative solver's tolerance.
    """
    rows, count = features.shape
    best = Fit(float(target.mean()), np.zeros(count))
    best_error = float(((target - best.intercept) ** 2).sum())
    for size in range(1, count + 1):
        for subset in itertools.combinations(range(count), size):
            design = np.column_stack([np.ones(rows), features[:, subset]])
            solution, *_ = np.linalg.lstsq(design, target, rcond=None)
            if (solution[1:] < 0).any():
                continue
            error = float(((design @ solution - target) ** 2).sum())
            if error < best_error - 1e-12:
                weights = np.zeros(count)
                weights[list(subset)] = solution[1:]
                best, best_error = Fit(float(solution[0]), weights), error
    return best


def folds(count: int, k: int, seed: int) -> np.ndarray:
    """Fold number (0..k-1) of each of ``count`` rows: a seeded shuffle dealt round-robin."""
    fold = np.empty(count, np.int64)
    fold[np.random.default_rng(seed).permutation(count)] = np.arange(count) % k
    return fold


def held_out_predictions(features: np.ndarray, target: np.ndarray, fold: np.ndarray) -> np.ndarray:
    """Each row's prediction by :func:`fit_nonnegative` fitted on the other folds."""
    predicted = np.empty(len(target))
    for k in np.unique(fold):
        train = fold != k
        predicted[~train] = fit_nonnegative(features[train], target[train]).predict(features[~train])
    return predicted


def held_out_r_squared(score: np.ndarray, target: np.ndarray, fold: np.ndarray) -> float:
    """Held-out R² of a fixed score as a predictor: a line ``a + b·score`` (b ≥ 0) fitted on the
    other folds maps the score to the target's scale, as BARN's linear model maps its metrics."""
    return r_squared(target, held_out_predictions(score[:, None], target, fold))


TARGET_CONTROLLERS = ("straight", "dwa", "purepursuit", "vfh")
"""The controllers whose mean measured difficulty version 2 of the score is fitted to."""


def measured_target(data: list[dict[str, float | str]], controllers: tuple[str, ...]) -> np.ndarray:
    """Per floor (a row of the calibration data), the mean over ``controllers`` of the measured
    difficulty (time over optimal time, failures at the timeout factor), scaled to 0 at the
    optimal time and 1 at the timeout."""
    ratio = np.array([[float(row[name]) for name in controllers] for row in data]).mean(axis=1)
    timeout = np.array([float(row["timeout"]) for row in data])
    return (ratio - 1.0) / (timeout - 1.0)


def score_features(data: list[dict[str, float | str]]) -> np.ndarray:
    """The :func:`~mazegen.runtime.navigation.difficulty.hardness` of each floor of the data."""
    table = np.array([[float(row[name]) for name in METRICS] for row in data])
    scale = np.array([float(row["scale"]) for row in data])
    return np.vstack([hardness(table[k : k + 1], scale[k]) for k in range(len(data))])


def score_fit(data: list[dict[str, float | str]]) -> Fit:
    """Version 2 of the difficulty score fitted to the calibration data: the non-negative linear
    model of the hardness terms that best predicts :data:`TARGET_CONTROLLERS`' measured difficulty."""
    return fit_nonnegative(score_features(data), measured_target(data, TARGET_CONTROLLERS))


def read_calibration(path: Path) -> list[dict[str, float | str]]:
    """The calibration data ``benchmarks/calibration.py --save`` wrote: one row per floor, its
    ``spec`` named, every other column a number."""
    with path.open(newline="") as stream:
        return [{k: v if k == "spec" else float(v) for k, v in row.items()} for row in csv.DictReader(stream)]
