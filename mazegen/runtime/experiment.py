"""Experiments: several seeded runs of a built problem, written to a run directory.

A run is a pure function of (spec, seed, run index): run ``i`` draws from
``numpy.random.default_rng(SeedSequence(seed).spawn(runs)[i])``.
"""

from __future__ import annotations

import argparse
import platform
import sys
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numba
import numpy as np

from mazegen import __version__
from mazegen.errors import MazeError
from mazegen.fileio import write_atomic
from mazegen.runtime.evolution import RunResult, evolve
from mazegen.runtime.mapping import phenotype
from mazegen.runtime.operators import ranking
from mazegen.runtime.problem import Evaluation, Problem
from mazegen.runtime.progress import QuietReporter, Reporter, reporter_for
from mazegen.runtime.render import scenario_svg
from mazegen.runtime.results import json_text, npz_bytes, staged_directory, stats_csv
from mazegen.runtime.scenario import dumps, scenario_document, scenario_key
from mazegen.spec import Spec

OVERRIDE_MINIMUM = {"seed": 0, "runs": 1, "population": 1, "generations": 0}
BUILD_FILES = ("spec.json", "grammar.bnf", "fitness.py", "experiment.py")


@dataclass(frozen=True)
class ExperimentResult:
    """What an experiment produced: each run's result and best scenario documents."""

    runs: tuple[RunResult, ...]
    best: tuple[tuple[dict[str, Any], ...], ...]
    run_dir: Path | None


def best_documents(
    problem: Problem, result: RunResult, *, count: int, origin: dict[str, Any]
) -> tuple[dict[str, Any], ...]:
    """The ``count`` best distinct valid scenarios of a final population, best first."""
    ranked = ranking(result.fitness)
    ranked = ranked[np.isfinite(result.fitness[ranked])]
    documents: list[dict[str, Any]] = []
    seen: set[bytes] = set()
    # Candidates are evaluated a batch at a time; most batches hold enough distinct scenarios.
    batch = max(4 * count, 64)
    for start in range(0, ranked.size, batch):
        chosen = ranked[start : start + batch]
        codons, genes = result.codons[chosen], result.genes[chosen]
        evaluation = problem.evaluate(codons, genes)
        for row in range(chosen.size):
            key = scenario_key(evaluation.population, row)
            if key in seen:
                continue
            seen.add(key)
            extra = {**origin, "rank": len(documents) + 1}
            documents.append(row_document(problem, evaluation, row, codons[row], genes[row], extra))
            if len(documents) == count:
                return tuple(documents)
    return tuple(documents)


def row_document(
    problem: Problem,
    evaluation: Evaluation,
    row: int,
    codons: np.ndarray,
    genes: np.ndarray,
    origin: dict[str, Any],
) -> dict[str, Any]:
    """The scenario document of row ``row`` of an evaluation, its genome recorded in ``origin``."""
    settings = problem.spec.evolution
    return scenario_document(
        problem.spec,
        evaluation.population,
        row,
        phenotype=phenotype(problem.grammar, codons.tolist(), wraps=settings.wraps, consume=settings.consume),
        fitness=float(evaluation.fitness[row]),
        terms={name: float(values[row]) for name, values in evaluation.terms.items()},
        origin={**origin, "codons": codons.tolist(), "placement": genes.tolist()},
    )


class Experiment:
    """A built problem plus evolution settings, ready to run."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem

    @classmethod
    def from_build_dir(cls, build_dir: Path) -> Experiment:
        """Load the experiment generated in ``build_dir``."""
        return cls(Problem.from_build_dir(build_dir))

    def with_settings(self, **overrides: Any) -> Experiment:
        """A copy whose evolution settings are overridden (``None`` values are ignored).

        Raises:
            MazeError: for a value out of its bounds (``--population 0``).
        """
        for key, low in OVERRIDE_MINIMUM.items():
            value = overrides.get(key)
            if value is not None and value < low:
                raise MazeError(f"--{key} must be at least {low}, got {value}")
        spec = self.problem.spec.with_evolution(**overrides)
        if spec.evolution.elitism >= spec.evolution.population:
            spec = spec.with_evolution(elitism=spec.evolution.population - 1)
        return Experiment(replace(self.problem, spec=spec))

    def run(
        self, *, out_dir: Path | None = None, force: bool = False, reporter: Reporter | None = None
    ) -> ExperimentResult:
        """Run every run of the experiment; write ``out_dir`` if given (whole or not at all)."""
        problem, settings = self.problem, self.problem.spec.evolution
        reporter = reporter or QuietReporter()
        children = np.random.SeedSequence(settings.seed).spawn(settings.runs)
        results, bests = [], []
        for number, child in enumerate(children, start=1):
            reporter.start_run(number, settings.runs, settings.generations)
            result = evolve(
                problem, settings, np.random.default_rng(child), on_generation=reporter.generation
            )
            results.append(result)
            origin = {"seed": settings.seed, "run": number, "generation": settings.generations}
            bests.append(best_documents(problem, result, count=settings.best, origin=origin))
        outcome = ExperimentResult(tuple(results), tuple(bests), out_dir)
        if out_dir is not None:
            self.write(outcome, out_dir, force=force)
        return outcome

    def record(self) -> dict[str, Any]:
        """The resolved experiment: settings, seeds and software versions."""
        spec = self.problem.spec
        return {
            "format": "mazegen-run",
            "version": 1,
            "scenario": spec.name,
            "source": spec.source,
            "evolution": asdict(spec.evolution),
            "run_seeds": [
                {"entropy": spec.evolution.seed, "spawn_key": [i]} for i in range(spec.evolution.runs)
            ],
            "versions": {
                "mazegen": __version__,
                "numpy": np.__version__,
                "numba": numba.__version__,
                "python": platform.python_version(),
            },
        }

    def write(self, outcome: ExperimentResult, out_dir: Path, *, force: bool) -> None:
        """Write the run directory atomically."""
        with staged_directory(out_dir, force=force) as stage:
            for name in BUILD_FILES:
                source = self.problem.build_dir / name
                if name == "spec.json":
                    write_atomic(stage / "experiment" / name, self.problem.spec.to_json())
                elif source.is_file():
                    write_atomic(stage / "experiment" / name, source.read_bytes())
            write_atomic(stage / "experiment.json", json_text(self.record()))
            rows = [
                (number, row) for number, result in enumerate(outcome.runs, start=1) for row in result.stats
            ]
            write_atomic(stage / "stats.csv", stats_csv(rows))
            for number, (result, documents) in enumerate(zip(outcome.runs, outcome.best), start=1):
                run_dir = stage / f"run-{number:02d}"
                for rank, document in enumerate(documents, start=1):
                    write_atomic(run_dir / f"best-{rank:02d}.json", dumps(document))
                    write_atomic(run_dir / f"best-{rank:02d}.svg", scenario_svg(document))
                write_atomic(
                    run_dir / "population.npz",
                    npz_bytes(
                        {"codons": result.codons, "placement": result.genes, "fitness": result.fitness}
                    ),
                )


def default_run_dir(spec: Spec) -> Path:
    """Where a run is written unless told otherwise: ``runs/<scenario>-seed<seed>``."""
    return Path("runs") / f"{spec.name}-seed{spec.evolution.seed}"


def summary_lines(outcome: ExperimentResult) -> list[str]:
    """One line per run: best fitness and its phenotype."""
    lines = []
    for number, documents in enumerate(outcome.best, start=1):
        if documents:
            top = documents[0]
            lines.append(
                f"run {number}: best fitness {top['fitness']:g}, {len(top['elements'])} elements: "
                f"{top['phenotype']}"
            )
        else:
            lines.append(f"run {number}: no valid scenario")
    return lines


def main(build_dir: Path, argv: list[str] | None = None) -> int:
    """Command line of a generated ``experiment.py``."""
    parser = argparse.ArgumentParser(description=f"Run the MazeGen experiment in {build_dir}.")
    parser.add_argument("--seed", type=int)
    parser.add_argument("--runs", type=int)
    parser.add_argument("--population", type=int)
    parser.add_argument("--generations", type=int)
    parser.add_argument("-o", "--out", type=Path, help="run directory (default runs/<name>-seed<seed>)")
    parser.add_argument("--force", action="store_true", help="replace an existing run directory")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    reporter = reporter_for(quiet=args.quiet)
    try:
        experiment = Experiment.from_build_dir(build_dir).with_settings(
            seed=args.seed, runs=args.runs, population=args.population, generations=args.generations
        )
        out = args.out or default_run_dir(experiment.problem.spec)
        outcome = experiment.run(out_dir=out, force=args.force, reporter=reporter)
    except MazeError as error:
        print(error, file=sys.stderr)
        return 1
    finally:
        reporter.close()
    for line in summary_lines(outcome):
        print(line)
    print(f"wrote {out}")
    return 0
