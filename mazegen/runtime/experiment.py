"""Experiments: a built problem with its evolution settings, and the command line of a generated build.

A run is a pure function of (spec, seed, run index): run ``i`` draws from
``numpy.random.default_rng(SeedSequence(seed).spawn(runs)[i])``, wherever it executes
(see :mod:`mazegen.runtime.launcher`).
"""

from __future__ import annotations

import argparse
import platform
import sys
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numba
import numpy as np

from mazegen import __version__
from mazegen.errors import MazeError, brief
from mazegen.runtime.launcher import ExperimentResult, Job, RunsInterrupted, run_jobs
from mazegen.runtime.problem import Problem
from mazegen.runtime.progress import reporter_for
from mazegen.runtime.rejections import why_no_scenario
from mazegen.runtime.results import json_text
from mazegen.runtime.worker import BuildFiles
from mazegen.spec import EVOLUTION_BOUNDS, Spec, out_of_bounds
from mazegen.text import printable

BUILD_FILES = ("spec.json", "grammar.bnf", "fitness.py", "experiment.py")


class Experiment:
    """A built problem plus evolution settings, ready to run."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem

    @classmethod
    def from_build_dir(cls, build_dir: Path) -> Experiment:
        """Load the experiment generated in ``build_dir``."""
        return cls(Problem.from_build_dir(build_dir))

    def with_settings(self, **overrides: Any) -> Experiment:
        """A copy whose evolution settings are overridden (see :func:`with_overrides`).

        Raises:
            MazeError: for a value out of its bounds (``--population 0``).
        """
        return Experiment(replace(self.problem, spec=with_overrides(self.problem.spec, **overrides)))

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

    def build_files(self) -> BuildFiles:
        """The texts a worker rebuilds the problem from (``spec.json`` with the overrides)."""
        build = self.problem.build_dir
        return BuildFiles(
            spec=self.problem.spec.to_json(),
            grammar=(build / "grammar.bnf").read_text(encoding="utf-8"),
            fitness=(build / "fitness.py").read_text(encoding="utf-8"),
        )

    def start_files(self) -> dict[str, str | bytes]:
        """The files a run directory holds from its start: the build that runs, and ``experiment.json``."""
        files: dict[str, str | bytes] = {"experiment.json": json_text(self.record())}
        for name in BUILD_FILES:
            source = self.problem.build_dir / name
            if name == "spec.json":
                files[f"experiment/{name}"] = self.problem.spec.to_json()
            elif source.is_file():
                files[f"experiment/{name}"] = source.read_bytes()
        return files


def with_overrides(spec: Spec, **overrides: Any) -> Spec:
    """``spec`` with evolution settings overridden (``None`` values are ignored), the elitism
    lowered below a smaller population.

    Raises:
        MazeError: for a value out of its bounds (``--population 0``), or a population too
            large for the genome.
    """
    given = {key: value for key, value in overrides.items() if value is not None}
    for key, value in given.items():
        problem = out_of_bounds(key, value) if key in EVOLUTION_BOUNDS else None
        if problem is not None:
            raise MazeError(f"--{key} {problem}, got {brief(value)}")
    try:
        spec = spec.with_evolution(**given)
    except ValueError as error:  # settings within bounds alone but not together (population x genome)
        options = " ".join(f"--{key} {value}" for key, value in given.items())
        raise MazeError(f"{options}: {error}") from None
    if spec.evolution.elitism >= spec.evolution.population:
        spec = spec.with_evolution(elitism=spec.evolution.population - 1)
    return spec


def default_run_dir(spec: Spec) -> Path:
    """Where a run is written unless told otherwise: ``runs/<scenario>-seed<seed>``."""
    return Path("runs") / f"{spec.name}-seed{spec.evolution.seed}"


def summary_lines(outcome: ExperimentResult) -> list[str]:
    """One line per run: best fitness and its phenotype, or why it found no valid scenario."""
    lines = []
    for number, documents in enumerate(outcome.best, start=1):
        if documents:
            top = documents[0]
            lines.append(
                f"run {number}: best fitness {top['fitness']:g}, {len(top['elements'])} elements: "
                f"{printable(top['phenotype'])}"  # the grammar's text: control characters too
            )
            continue
        why = [] if outcome.run_dir is None else why_no_scenario(outcome.run_dir, number)
        lines.append(f"run {number}: no valid scenario" + (f"; {why[0]}" if why else ""))
        lines += why[1:]
    return lines


NO_SCENARIO = "no run produced a valid scenario (see why above)"
"""The error of an experiment that ends without a scenario (its run directory is whole)."""


def closing_lines(outcome: ExperimentResult, run_dir: Path) -> list[str]:
    """Where the results went: the run directory, its pictures, and the command of its report page."""
    lines = [f"wrote {run_dir}"]
    if any(outcome.best):
        lines += [
            f"pictures: {run_dir / 'run-NN' / 'best-KK.svg'} (as PNG: mazegen export {run_dir} --format png)",
            f"one page of settings, pictures and plots: mazegen report {run_dir}",
        ]
    return lines


def main(build_dir: Path, argv: list[str] | None = None) -> int:
    """Command line of a generated ``experiment.py``: runs on the local cores, like ``mazegen run``."""
    parser = argparse.ArgumentParser(description=f"Run the MazeGen experiment in {build_dir}.")
    parser.add_argument("--seed", type=int)
    parser.add_argument("--runs", type=int)
    parser.add_argument("--population", type=int)
    parser.add_argument("--generations", type=int)
    parser.add_argument("-o", "--out", type=Path, help="run directory (default runs/<name>-seed<seed>)")
    parser.add_argument("--force", action="store_true", help="replace an existing run directory")
    parser.add_argument("--workers", type=int, help="worker processes (default: the cores)")
    parser.add_argument("--checkpoint-every", type=int, help="generations between checkpoints (0: none)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    reporter = reporter_for(quiet=args.quiet)
    try:
        experiment = Experiment.from_build_dir(build_dir).with_settings(
            seed=args.seed, runs=args.runs, population=args.population, generations=args.generations
        )
        out = args.out or default_run_dir(experiment.problem.spec)
        [outcome] = run_jobs(
            [Job(experiment, out, force=args.force)],
            executor="local",
            workers=args.workers,
            checkpoint_every=args.checkpoint_every,
            reporter=reporter,
        )
    except MazeError as error:
        print(error.render(command_line=True), file=sys.stderr)
        return 1
    except RunsInterrupted:
        print(f"interrupted; continue with: mazegen resume {out}", file=sys.stderr)
        return 130
    finally:
        reporter.close()
    for line in [*summary_lines(outcome), *closing_lines(outcome, out)]:
        print(line)
    if not any(outcome.best):
        print(NO_SCENARIO, file=sys.stderr)
        return 1
    return 0
