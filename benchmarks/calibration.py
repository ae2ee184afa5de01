"""Calibrate the difficulty score against measured traversal (docs/difficulty.md, "Calibration").

Usage:
    python benchmarks/calibration.py             # drive the saved floors: the docs' figures (~3 min warm)
    python benchmarks/calibration.py --saved     # the same figures from the saved data, no driving
    python benchmarks/calibration.py --evolve    # 360 fresh floors, 10 starts, 4 controllers
    python benchmarks/calibration.py --evolve --floors 60  # a quick look
    python benchmarks/calibration.py [--evolve] --save     # also rewrite the saved data (and floors)

Floors: by default the saved ones (``tests/runtime/navigation/calibration_floors.json``, each
floor's elements as scenario documents place them), so that the published figures follow from
them whatever the evolution now breeds. ``--evolve`` draws fresh ones: a pool of each bundled
example (``workshop.maze`` and ``factory.maze``: random genomes and the last generation of a short
evolution with the spec's operators), of which the solvable ones are dealt out spread across
difficulty (version 1, the score being calibrated): bins 2.5 points wide, one floor per bin in
turn, so the floors spread over the score's range as evenly as the pool allows.

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
weights, the floors by version 1's old levels, the arrivals and the controllers' agreement: every
figure docs/difficulty.md and the README quote, which a test checks against the saved data.
``--save`` writes ``tests/runtime/navigation/calibration_data.csv`` (per floor its metrics, measured
difficulty and arrivals), from which the tests refit version 2's weights, and with ``--evolve`` the
floors beside it.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import io
import math
import tempfile
import time
from pathlib import Path

import numpy as np
from common import ROOT, markdown_table

import mazegen
from mazegen.generator.build import build
from mazegen.runtime.documents._scenario import element_documents, population_from_documents
from mazegen.runtime.engine import _evolution as evolution
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._population import Population
from mazegen.runtime.engine._problem import Problem
from mazegen.runtime.geometry._elements import ElementTable
from mazegen.runtime.navigation._calibration import (
    TARGET_CONTROLLERS,
    CalibrationFloors,
    arrivals,
    controller_agreement,
    correlations,
    data_scores,
    read_calibration,
    score_fit,
    version_1_levels,
)
from mazegen.runtime.navigation._difficulty import HARDNESS, METRICS, difficulty_score
from mazegen.runtime.navigation._measures import survey_of
from mazegen.runtime.simulation import ARRIVED, COLLISION, drive
from mazegen.spec import Spec, robot_for

SPECS = ("workshop", "factory")
CONTROLLERS = TARGET_CONTROLLERS
DATA = ROOT / "tests" / "runtime" / "navigation" / "calibration_data.csv"
FLOORS = DATA.with_name("calibration_floors.json")
BIN = 2.5
"""Width of the difficulty bins floors are dealt from, in version 1's points."""
PLACEMENT = ("type", "x", "y", "size", "width", "depth", "rotation")
"""What a saved floor keeps of each element's document: its placement, from which the rest follows."""


@dataclasses.dataclass(frozen=True)
class Floors:
    """The floors of one bundled example to drive: rows ``rows`` of ``population``."""

    name: str
    spec: Spec
    population: Population
    rows: np.ndarray


def spec_of(name: str) -> Spec:
    """Bundled example ``name``'s spec."""
    return mazegen.load(ROOT / "examples" / f"{name}.maze")


def problem_of(name: str) -> Problem:
    """Build bundled example ``name`` in a temporary folder and load it."""
    with tempfile.TemporaryDirectory() as folder:
        build(spec_of(name), Path(folder))
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


def evolved_floors(count: int, seed: int) -> list[Floors]:
    """``count`` fresh floors, shared out among :data:`SPECS`, spread over version 1's range."""
    rng = np.random.default_rng(seed)
    chosen = []
    for k, name in enumerate(SPECS):
        problem = problem_of(name)
        population = pool(problem, rng, 2000)
        score = difficulty_score(survey_of(population).table, population.arena.robot_radius, version=1)
        rows = spread(score, count // len(SPECS) + (k < count % len(SPECS)), rng)
        print(f"{name}: {rows.size} floors, version 1 score {score[rows].min():.1f}..{score[rows].max():.1f}")
        chosen.append(Floors(name, problem.spec, population, rows))
    return chosen


def saved_floors(saved: CalibrationFloors) -> list[Floors]:
    """The saved floors, as one population per spec."""
    chosen = []
    for name in SPECS:
        spec = spec_of(name)
        documents = [
            (f"{FLOORS}:{k}", floor) for k, floor in enumerate(saved.floors) if floor["spec"] == name
        ]
        population = population_from_documents(
            spec, ElementTable.from_types(spec.scenario_elements), documents
        )
        chosen.append(Floors(name, spec, population, np.arange(population.size)))
    return chosen


def floor_entries(floors: Floors) -> list[dict]:
    """The saved file's entries of ``floors``: each element's placement, as its document has it."""
    return [
        {
            "spec": floors.name,
            "elements": [
                {key: value for key, value in item.items() if key in PLACEMENT}
                for item in element_documents(floors.spec, floors.population, int(row))
            ],
        }
        for row in floors.rows
    ]


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
    """Per controller, each floor's measured difficulty (``name``: mean time over optimal time of
    its starts, failures counted at the timeout factor) and arrivals (``arrived_name``: the
    fraction of its starts that arrived)."""
    robot = robot_for(population.arena)
    poses = perturbed_starts(population, rows, starts, seed)
    measured = {}
    for name in CONTROLLERS:
        started = time.perf_counter()
        episodes = drive(
            population, robot=robot, controller=name, indices=np.repeat(rows, starts), starts=poses
        )
        per_start = np.minimum(episodes.time_ratio(robot.timeout), robot.timeout)
        measured[name] = per_start.reshape(rows.size, starts).mean(axis=1)
        measured[f"arrived_{name}"] = (episodes.outcome == ARRIVED).reshape(rows.size, starts).mean(axis=1)
        print(
            f"  {name}: {episodes.outcome.size} episodes in {time.perf_counter() - started:.1f} s, "
            f"arrived {np.mean(episodes.outcome == ARRIVED):.0%}"
        )
    return measured


def collect(chosen: list[Floors], starts: int, seed: int) -> list[dict[str, float | str]]:
    """The calibration data: one row per floor (spec, scale, metrics, measured difficulty, arrivals)."""
    data: list[dict[str, float | str]] = []
    for floors in chosen:
        population, rows = floors.population, floors.rows
        table = survey_of(population).table
        scale = population.arena.robot_radius
        print(f"{floors.name}: driving {rows.size} floors")
        measured = measure(population, rows, starts, seed + SPECS.index(floors.name))
        for j, row in enumerate(rows):
            data.append(
                {"spec": floors.name, "scale": scale, "timeout": robot_for(population.arena).timeout}
                | {metric: float(table[row, m]) for m, metric in enumerate(METRICS)}
                | {column: float(values[j]) for column, values in measured.items()}
            )
    return data


def data_text(data: list[dict[str, float | str]]) -> str:
    """The saved data's CSV text: numbers to 10 significant digits."""
    stream = io.StringIO()
    writer = csv.DictWriter(stream, fieldnames=list(data[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: f"{v:.10g}" if isinstance(v, float) else v for k, v in row.items()} for row in data)
    return stream.getvalue()


def report(data: list[dict[str, float | str]], seed: int) -> None:
    """Print ρ and held-out R² per controller, version 2's fit, and the figures the docs quote."""
    rows = correlations(data, seed)
    rows[-1]["controller"] = "mean of " + ", ".join(TARGET_CONTROLLERS)
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
    version_1 = data_scores(data, 1)
    print(f"version 1 on the floors: {version_1.min():.1f}..{version_1.max():.1f}")
    print(
        markdown_table(
            [
                {"level": level, "floors": count, "median": median}
                for level, (count, median) in version_1_levels(data).items()
            ],
            [
                ("level", "version 1 level", ""),
                ("floors", "floors", "d"),
                ("median", "version 2 median", ".0f"),
            ],
        )
    )
    print("arrivals: " + ", ".join(f"{name} {100 * share:.0f} %" for name, share in arrivals(data).items()))
    print(
        "controllers' agreement (ρ): "
        + ", ".join(f"{a}/{b} {rho:.2f}" for (a, b), rho in controller_agreement(data).items())
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--evolve", action="store_true", help="evolve fresh floors instead of the saved ones")
    parser.add_argument("--floors", type=int, help="fresh floors (--evolve; default 360)")
    parser.add_argument("--starts", type=int, help="perturbed starts per floor (--evolve; default 10)")
    parser.add_argument("--seed", type=int, help="seed of the floors and starts (--evolve; default 1)")
    parser.add_argument(
        "--save", action="store_true", help=f"write {DATA.relative_to(ROOT)} (and the floors)"
    )
    parser.add_argument("--saved", action="store_true", help="report from the saved data, no driving")
    args = parser.parse_args()
    if not args.evolve and (args.floors, args.starts, args.seed) != (None, None, None):
        parser.error("--floors, --starts and --seed are for fresh floors: add --evolve")
    if args.saved and (args.evolve or args.save):
        parser.error("--saved reports the saved data: no --evolve or --save with it")
    if args.saved:
        report(read_calibration(DATA), CalibrationFloors.read(FLOORS).seed)
        return
    started = time.perf_counter()
    if args.evolve:
        seed = 1 if args.seed is None else args.seed
        chosen = evolved_floors(360 if args.floors is None else args.floors, seed)
        starts = 10 if args.starts is None else args.starts
        floors = CalibrationFloors(seed, starts, [entry for f in chosen for entry in floor_entries(f)])
    else:
        floors = CalibrationFloors.read(FLOORS)
        chosen = saved_floors(floors)
    data = collect(chosen, floors.starts, floors.seed)
    print(f"collected {len(data)} floors in {time.perf_counter() - started:.0f} s")
    text = data_text(data)
    if not args.evolve:
        same = text == DATA.read_text(encoding="utf-8")
        print("the saved floors give " + ("the saved data" if same else "other data now (--save)"))
    if args.save:
        DATA.write_text(text, encoding="utf-8")
        if args.evolve:
            FLOORS.write_text(floors.text(), encoding="utf-8")
    report(data, floors.seed)


if __name__ == "__main__":
    main()
