"""Fitting the difficulty score to measured traversal: rank correlation, held-out R², and
non-negative least squares over the metrics' hardness terms.

``benchmarks/calibration.py`` drives the bundled controllers over a suite of floors and saves the
floors (their elements) and, per floor, the metrics and the measured difficulty; :func:`score_fit`
turns that into the weights of :data:`mazegen.runtime.navigation._difficulty.WEIGHTS` (version 2 of
the score), and tests refit them from the saved data and check the figures the docs quote
against it. Plain NumPy: a handful of features, a few hundred floors.
"""

from __future__ import annotations

import csv
import itertools
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mazegen.runtime.navigation._difficulty import METRICS, difficulty_score, hardness


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
"""The controllers whose mean measured difficulty version 2 of the score is fitted to: the columns
of the saved calibration data, so a bundled controller added later joins only when the score is
refitted (``benchmarks/calibration.py``)."""


def measured_target(data: list[dict[str, float | str]], controllers: tuple[str, ...]) -> np.ndarray:
    """Per floor (a row of the calibration data), the mean over ``controllers`` of the measured
    difficulty (time over optimal time, failures at the timeout factor), scaled to 0 at the
    optimal time and 1 at the timeout."""
    ratio = np.array([[float(row[name]) for name in controllers] for row in data]).mean(axis=1)
    timeout = np.array([float(row["timeout"]) for row in data])
    return (ratio - 1.0) / (timeout - 1.0)


def metric_table(data: list[dict[str, float | str]]) -> tuple[np.ndarray, np.ndarray]:
    """``float64[N, len(METRICS)]``, the metrics of each floor of the data, and ``float64[N]``, its scale
    (the robot's radius)."""
    table = np.array([[float(row[name]) for name in METRICS] for row in data])
    return table, np.array([float(row["scale"]) for row in data])


def score_features(data: list[dict[str, float | str]]) -> np.ndarray:
    """The :func:`~mazegen.runtime.navigation._difficulty.hardness` of each floor of the data."""
    table, scale = metric_table(data)
    return np.vstack([hardness(table[k : k + 1], scale[k]) for k in range(len(data))])


def data_scores(data: list[dict[str, float | str]], version: int) -> np.ndarray:
    """The :func:`~mazegen.runtime.navigation._difficulty.difficulty_score` (``version``) of each floor."""
    table, scale = metric_table(data)
    return np.concatenate(
        [difficulty_score(table[k : k + 1], scale[k], version=version) for k in range(len(data))]
    )


def score_fit(data: list[dict[str, float | str]]) -> Fit:
    """Version 2 of the difficulty score fitted to the calibration data: the non-negative linear
    model of the hardness terms that best predicts :data:`TARGET_CONTROLLERS`' measured difficulty."""
    return fit_nonnegative(score_features(data), measured_target(data, TARGET_CONTROLLERS))


@dataclass(frozen=True)
class CalibrationFloors:
    """The floors the calibration drives, as ``benchmarks/calibration.py`` saved them.

    Attributes:
        seed: The seed of the perturbed starts (the first spec's; each next spec's is one more)
            and of the held-out folds.
        starts: Perturbed starts per floor.
        floors: One ``{"spec": name, "elements": [...]}`` per floor, the elements as scenario
            documents place them (type, position, size, rotation; docs/scenario-format.md).
    """

    seed: int
    starts: int
    floors: list[dict[str, Any]]

    def text(self) -> str:
        """The saved file's text: deterministic, one floor a line."""
        lines = ",\n".join(json.dumps(floor) for floor in self.floors)
        return f'{{"seed": {self.seed}, "starts": {self.starts}, "floors": [\n{lines}\n]}}\n'

    @classmethod
    def read(cls, path: Path) -> CalibrationFloors:
        """The floors saved at ``path``."""
        saved = json.loads(path.read_text(encoding="utf-8"))
        return cls(int(saved["seed"]), int(saved["starts"]), saved["floors"])


def read_calibration(path: Path) -> list[dict[str, float | str]]:
    """The calibration data ``benchmarks/calibration.py --save`` wrote: one row per floor, its
    ``spec`` named, every other column a number."""
    with path.open(newline="") as stream:
        return [{k: v if k == "spec" else float(v) for k, v in row.items()} for row in csv.DictReader(stream)]


FOLDS = 10
"""Held-out R² is cross-validated over this many folds of floors."""

VERSION_1_LEVELS = {"easy": (0.0, 10.0), "medium": (10.0, 25.0), "hard": (25.0, 100.0)}
"""The levels of version 1 of the score, before version 2 re-set them (docs/difficulty.md, "Levels")."""


def correlations(data: list[dict[str, float | str]], seed: int) -> list[dict[str, float | str]]:
    """The table of docs/difficulty.md's calibration: one row per controller of
    :data:`TARGET_CONTROLLERS`, then one for their mean (``controller`` ``"mean"``), each with
    Spearman's ρ of version 1 and 2 of the score and of each metric with the measured difficulty
    (``rho_v1``, ``rho_v2``, ``rho_<metric>``) and the held-out R² (:data:`FOLDS` folds by floor,
    drawn with ``seed``) of version 1, of version 2 and of version 2's model refitted on each
    training fold (``r2_v1``, ``r2_v2``, ``r2_refit``)."""
    table, _ = metric_table(data)
    features = score_features(data)
    scores = {version: data_scores(data, version) for version in (1, 2)}
    fold = folds(len(data), FOLDS, seed)
    rows: list[dict[str, float | str]] = []
    for name in (*TARGET_CONTROLLERS, "mean"):
        target = measured_target(data, TARGET_CONTROLLERS if name == "mean" else (name,))
        rows.append(
            {"controller": name}
            | {f"rho_v{version}": spearman(score, target) for version, score in scores.items()}
            | {f"rho_{metric}": spearman(table[:, m], target) for m, metric in enumerate(METRICS)}
            | {f"r2_v{version}": held_out_r_squared(score, target, fold) for version, score in scores.items()}
            | {"r2_refit": r_squared(target, held_out_predictions(features, target, fold))}
        )
    return rows


def controller_agreement(data: list[dict[str, float | str]]) -> dict[tuple[str, str], float]:
    """Spearman's ρ between the measured difficulties of each pair of :data:`TARGET_CONTROLLERS`."""
    return {
        (a, b): spearman(measured_target(data, (a,)), measured_target(data, (b,)))
        for a, b in itertools.combinations(TARGET_CONTROLLERS, 2)
    }


def arrivals(data: list[dict[str, float | str]]) -> dict[str, float]:
    """Per controller of :data:`TARGET_CONTROLLERS`, the fraction of all starts it arrived from
    (the data's ``arrived_<controller>``: the fraction of each floor's starts, as many per floor)."""
    return {
        name: float(np.mean([float(row[f"arrived_{name}"]) for row in data])) for name in TARGET_CONTROLLERS
    }


def version_1_levels(data: list[dict[str, float | str]]) -> dict[str, tuple[int, float]]:
    """Per level of :data:`VERSION_1_LEVELS`, how many floors of the data version 1 puts in it and
    their median version 2 score."""
    version_1, version_2 = data_scores(data, 1), data_scores(data, 2)
    levels = {}
    for level, (low, high) in VERSION_1_LEVELS.items():
        inside = (version_1 >= low) & (version_1 < high)
        levels[level] = (int(inside.sum()), float(np.median(version_2[inside])))
    return levels
