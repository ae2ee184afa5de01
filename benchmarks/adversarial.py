"""examples/adversarial.maze: how often dwa fails on its evolved floors, against random floors of as
many elements, and how long the example takes (docs/difficulty.md, "Adversarial floors").

Usage:
    python benchmarks/adversarial.py            # the run's time, then the failure rates (~2 min warm)
    python benchmarks/adversarial.py --best 10  # fewer evolved floors

1. Times ``mazegen run examples/adversarial.maze`` (population 1,000, 20 generations, serial executor,
   in a subprocess): a first untimed run warms numba's cache, the second is timed.
2. Evolves the example once more in this process (same seed) and keeps the ``--best`` fittest
   distinct floors of its last generation.
3. Draws random genomes of the same spec until it holds ``--random`` valid, solvable floors for
   each element count the best floors have, in the same proportions.
4. Drives dwa over both sets with the arena's default robot, from the arena's start (what the
   evolution scored) and from ``--starts`` perturbed starts per floor (as benchmarks/calibration.py
   perturbs them), and prints each set's failure rate (collision or timeout).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from calibration import perturbed_starts, problem_of
from common import ROOT, markdown_table

from mazegen.runtime.documents._scenario import scenario_key
from mazegen.runtime.engine import _evolution as evolution
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._population import Population
from mazegen.runtime.navigation._measures import survey_of
from mazegen.runtime.simulation import ARRIVED, drive
from mazegen.spec import robot_for

EXAMPLE = ROOT / "examples" / "adversarial.maze"


def timed_run() -> float:
    """Seconds of ``mazegen run`` on the example with a warm cache (one untimed run first)."""
    seconds = 0.0
    with tempfile.TemporaryDirectory() as folder:
        for _ in range(2):
            command = [sys.executable, "-m", "mazegen", "run", str(EXAMPLE), "-o", f"{folder}/run"]
            started = time.perf_counter()
            subprocess.run(
                [*command, "--force", "--executor", "serial", "-q"], check=True, capture_output=True
            )
            seconds = time.perf_counter() - started
    return seconds


def distinct_best(population: Population, fitness: np.ndarray, count: int) -> np.ndarray:
    """The ``count`` fittest valid rows whose floors differ."""
    seen: set[bytes] = set()
    rows = []
    for row in np.argsort(-fitness, kind="stable"):
        key = scenario_key(population, int(row))
        if np.isfinite(fitness[row]) and key not in seen:
            seen.add(key)
            rows.append(int(row))
        if len(rows) == count:
            break
    return np.array(rows, np.int64)


def random_matched(problem, elements: np.ndarray, per_floor: int, rng: np.random.Generator):
    """Random valid solvable floors: ``per_floor`` for each entry of ``elements`` (element counts)."""
    wanted = {int(n): per_floor * int((elements == n).sum()) for n in np.unique(elements)}
    settings = problem.spec.evolution
    chosen_codons, chosen_genes = [], []
    while any(wanted.values()):
        codons = random_codons(rng, 5000, settings.genome, settings.codon_max)
        genes = random_genes(rng, 5000, problem.slots)
        evaluation = problem.evaluate(codons, genes)
        population = evaluation.population
        ok = np.isfinite(evaluation.fitness) & survey_of(population).navigation.solvable
        for row in np.flatnonzero(ok):
            n = int(population.n_elements[row])
            if wanted.get(n, 0) > 0:
                wanted[n] -= 1
                chosen_codons.append(codons[row])
                chosen_genes.append(genes[row])
    return problem.evaluate(np.array(chosen_codons), np.array(chosen_genes)).population


def failure_rates(population: Population, rows: np.ndarray, starts: int, seed: int) -> tuple[float, float]:
    """dwa's failure rate over ``rows`` from the arena's start, and from perturbed starts."""
    robot = robot_for(population.arena)
    nominal = drive(population, robot=robot, controller="dwa", indices=rows)
    poses = perturbed_starts(population, rows, starts, seed)
    moved = drive(population, robot=robot, controller="dwa", indices=np.repeat(rows, starts), starts=poses)
    return float(np.mean(nominal.outcome != ARRIVED)), float(np.mean(moved.outcome != ARRIVED))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--best", type=int, default=20, help="evolved floors compared")
    parser.add_argument("--random", type=int, default=10, help="random floors per evolved floor")
    parser.add_argument("--starts", type=int, default=10, help="perturbed starts per floor")
    parser.add_argument("--no-timing", action="store_true", help="skip timing the run")
    args = parser.parse_args()
    if not args.no_timing:
        print(f"mazegen run examples/adversarial.maze (warm cache): {timed_run():.1f} s")
    problem = problem_of(Path(EXAMPLE).stem)
    settings = problem.spec.evolution
    result = evolution.evolve(problem, settings, np.random.default_rng(settings.seed))
    evolved = problem.evaluate(result.codons, result.genes).population
    best = distinct_best(evolved, result.fitness, args.best)
    counts = evolved.n_elements[best]
    randoms = random_matched(problem, counts, args.random, np.random.default_rng(settings.seed + 1))
    rows = []
    for label, population, chosen in (
        ("evolved (best distinct of the last generation)", evolved, best),
        ("random, same element counts", randoms, np.arange(randoms.size)),
    ):
        nominal, moved = failure_rates(population, chosen, args.starts, settings.seed)
        rows.append(
            {
                "floors": label,
                "count": chosen.size,
                "elements": f"{population.n_elements[chosen].mean():.1f}",
                "nominal": nominal,
                "moved": moved,
            }
        )
    print(
        markdown_table(
            rows,
            [
                ("floors", "floors", ""),
                ("count", "n", "d"),
                ("elements", "mean elements", ""),
                ("nominal", "dwa fails (arena start)", ".0%"),
                ("moved", f"dwa fails ({args.starts} perturbed starts)", ".0%"),
            ],
        )
    )


if __name__ == "__main__":
    main()
