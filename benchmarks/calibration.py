"""Calibrate the difficulty score against measured traversal (docs/difficulty.md, "Calibration").

Usage:
    python benchmarks/calibration.py             # 360 floors, 10 starts, 4 controllers (~3 min warm)
    python benchmarks/calibration.py --save      # also rewrite the saved data the tests refit from
    python benchmarks/calibration.py --floors 60 # a quick look

Floors: a pool of each bundled example (``workshop.maze`` and ``factory.maze``: random genomes and
the last generation of a short evolution with the spec's operators), of which the solvable ones are
dealt out spread across difficulty (version 1, the score being calibrated): bins 2.5 points wide,
one floor per bin in turn, so the floors spread over the score's range as evenly as the pool allows.

Drives: every bundled controller (straight, dwa, purepursuit, vfh) with the arena's default robot
(BARN's Jackal limits, timeout 8 × optimal time) from ``--starts`` seeded start perturbations per
floor: the start moved up to half the robot's radius in a random direction and the heading turned
up to ±0.5 rad from the goal's bearing (a perturbed start that touches an element is put back on
the arena's start). Measured difficulty, as BARN's: time over optimal time, a failure (collision or
timeout) counted as the timeout factor; per floor and controller the mean over the starts, scaled
to 0..1 between the optimal time and the timeout.

Prints per controller Spearman's ρ of the score (version 1 and 2) and of each metric with measured
difficulty, and the held-out R² (10-fold by floor, seeded) of version 1, of version 2 and of a model
refitted to that controller alone; then version 2's fit (the mean over the controllers) and its
weights. ``--save`` writes ``tests/runtime/navigation/calibration_data.csv``, from which a test
refits version 2's weights.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import tempfile
import time
from pathlib import Path

import numpy as np
from common import ROOT, markdown_table

import mazegen
from mazegen.generator.build import build
from mazegen.runtime.engine import evolution
from mazegen.runtime.engine.operators import random_codons, random_genes
from mazegen.runtime.engine.population import Population
from mazegen.runtime.engine.problem import Problem
from mazegen.runtime.navigation.calibration import (
    TARGET_CONTROLLERS,
    folds,
    held_out_predictions,
    held_out_r_squared,
    measured_target,
    r_squared,
    read_calibration,
    score_features,
    score_fit,
    spearman,
)
from mazegen.runtime.navigation.difficulty import HARDNESS, METRICS, difficulty_score, survey
from mazegen.runtime.simulation import ARRIVED, COLLISION, drive
from mazegen.spec import robot_for

SPECS = ("workshop", "factory")
CONTROLLERS = ("straight", "dwa", "purepursuit", "vfh")
DATA = ROOT / "tests" / "runtime" / "navigation" / "calibration_data.csv"
BIN = 2.5
"""Width of the difficulty bins floors are dealt from, in version 1's points."""
FOLDS = 10


def problem_of(name: str) -> Problem:
    """Build bundled example ``name`` in a temporary folder and load it."""
    with tempfile.TemporaryDirectory() as folder:
        build(mazegen.load(ROOT / "examples" / f"{name}.maze"), Path(folder))
        return Problem.from_build_dir(Path(folder))


def pool(problem: Problem, rng: np.random.Generator, size: int) -> Population:
    """Random genomes and the last generation of a short evolution, evaluated together."""
    settings = problem.spec.evolution
    evolved = evolution.evolve(
        problem, dataclasses.replace(settings, population=size, generations=8, runs=1), rng
    )
    codons = np.concatenate([random_codons(rng, size, settings.genome, settings.codon_max), evolved.codons])
    genes = np.concatenate([random_genes(rng, size, problem.slots), evolved.genes])
    return problem.evaluate(codons, genes).population


def spread(score: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` rows with a finite ``score``, dealt one per :data:`BIN` bin in turn."""
    rows = np.flatnonzero(np.isfinite(score))
    rows = rows[rng.permutation(rows.size)]
    bins = (score[rows] // BIN).astype(np.int64)
    rank = np.zeros(rows.size, np.int64)
    for b in np.unique(bins):
        rank[bins == b] = np.arange(int((bins == b).sum()))
    return rows[np.lexsort((bins, rank))[:count]]


def perturbed_starts(population: Population, rows: np.ndarray, starts: int, seed: int) -> np.ndarray:
    """``float64[len(rows) * starts, 3]``: each floor's perturbed starts, floor by floor."""
    arena = population.arena
    rng = np.random.default_rng(seed)
    (sx, sy), (gx, gy) = arena.start, arena.goal
    n = rows.size * starts
    radius = 0.5 * arena.robot_radius * np.sqrt(rng.random(n))
    angle = rng.uniform(0, 2 * math.pi, n)
    x, y = sx + radius * np.cos(angle), sy + radius * np.sin(angle)
    theta = np.arctan2(gy - y, gx - x) + rng.uniform(-0.5, 0.5, n)
    poses = np.column_stack([x, y, theta])
    robot = robot_for(arena)
    touching = drive(
        population, robot=robot, controller="straight", indices=np.repeat(rows, starts), starts=poses
    )
    bad = (touching.outcome == COLLISION) & (touching.steps == 0)
    poses[bad, :2] = (sx, sy)
    return poses


def measure(population: Population, rows: np.ndarray, starts: int, seed: int) -> dict[str, np.ndarray]:
    """Per controller, each floor's measured difficulty: mean time over optimal time of its
    starts, failures counted at the timeout factor."""
    robot = robot_for(population.arena)
    poses = perturbed_starts(population, rows, starts, seed)
    measured = {}
    for name in CONTROLLERS:
        started = time.perf_counter()
        episodes = drive(
            population, robot=robot, controller=name, indices=np.repeat(rows, starts), starts=poses
        )
        measured[name] = (
            np.minimum(episodes.time_ratio(robot.timeout), robot.timeout)
            .reshape(rows.size, starts)
            .mean(axis=1)
        )
        print(
            f"  {name}: {episodes.outcome.size} episodes in {time.perf_counter() - started:.1f} s, "
            f"arrived {np.mean(episodes.outcome == ARRIVED):.0%}"
        )
    return measured


def collect(floors: int, starts: int, seed: int) -> list[dict[str, float | str]]:
    """The calibration data: one row per floor (spec, scale, metrics, measured difficulty)."""
    rng = np.random.default_rng(seed)
    data: list[dict[str, float | str]] = []
    for k, name in enumerate(SPECS):
        problem = problem_of(name)
        population = pool(problem, rng, 2000)
        table = survey(population).table
        scale = population.arena.robot_radius
        score = difficulty_score(table, scale, version=1)
        rows = spread(score, floors // len(SPECS) + (k < floors % len(SPECS)), rng)
        print(f"{name}: {rows.size} floors, version 1 score {score[rows].min():.1f}..{score[rows].max():.1f}")
        measured = measure(population, rows, starts, seed + k)
        for j, row in enumerate(rows):
            data.append(
                {"spec": name, "scale": scale, "timeout": robot_for(population.arena).timeout}
                | {metric: float(table[row, m]) for m, metric in enumerate(METRICS)}
                | {controller: float(measured[controller][j]) for controller in CONTROLLERS}
            )
    return data


def report(data: list[dict[str, float | str]], seed: int) -> None:
    """Print ρ and held-out R² per controller, and version 2's fit."""
    table = np.array([[row[m] for m in METRICS] for row in data], np.float64)
    scale = np.array([row["scale"] for row in data], np.float64)
    features = score_features(data)
    v1 = np.array([difficulty_score(table[k : k + 1], scale[k], version=1)[0] for k in range(len(data))])
    v2 = np.array([difficulty_score(table[k : k + 1], scale[k], version=2)[0] for k in range(len(data))])
    fold = folds(len(data), FOLDS, seed)
    rows = []
    for name in (*CONTROLLERS, "target"):
        y = measured_target(data, TARGET_CONTROLLERS if name == "target" else (name,))
        refit = held_out_predictions(features, y, fold)
        rows.append(
            {
                "controller": name if name != "target" else "mean of " + ", ".join(TARGET_CONTROLLERS),
                "rho_v1": spearman(v1, y),
                "rho_v2": spearman(v2, y),
                **{f"rho_{metric}": spearman(table[:, m], y) for m, metric in enumerate(METRICS)},
                "r2_v1": held_out_r_squared(v1, y, fold),
                "r2_v2": held_out_r_squared(v2, y, fold),
                "r2_refit": r_squared(y, refit),
            }
        )
    columns = [
        ("controller", "controller", ""),
        ("rho_v1", "ρ v1", ".2f"),
        ("rho_v2", "ρ v2", ".2f"),
        *[(f"rho_{metric}", f"ρ {metric}", ".2f") for metric in METRICS],
        ("r2_v1", "R² v1", ".2f"),
        ("r2_v2", "R² v2", ".2f"),
        ("r2_refit", "R² refit", ".2f"),
    ]
    print(markdown_table(rows, columns))
    fit = score_fit(data)
    print(f"version 2 (fitted on all {len(data)} floors): intercept {fit.intercept:.4f}")
    print(
        markdown_table(
            [{"term": h, "weight": w} for h, w in zip(HARDNESS, fit.weights)],
            [("term", "term", ""), ("weight", "weight", ".4f")],
        )
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--floors", type=int, default=360)
    parser.add_argument("--starts", type=int, default=10)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--save", action="store_true", help=f"write {DATA.relative_to(ROOT)}")
    parser.add_argument("--saved", action="store_true", help="report from the saved data, no driving")
    args = parser.parse_args()
    if args.saved:
        data = read_calibration(DATA)
    else:
        started = time.perf_counter()
        data = collect(args.floors, args.starts, args.seed)
        print(f"collected {len(data)} floors in {time.perf_counter() - started:.0f} s")
        if args.save:
            with DATA.open("w", newline="") as stream:
                writer = csv.DictWriter(stream, fieldnames=list(data[0]), lineterminator="\n")
                writer.writeheader()
                writer.writerows(
                    {k: f"{v:.10g}" if isinstance(v, float) else v for k, v in row.items()} for row in data
                )
    report(data, args.seed)


if __name__ == "__main__":
    main()
