"""Experiments: a built problem with its evolution settings.

A run is a pure function of (spec, seed, run index): run ``i`` draws from
``numpy.random.default_rng(SeedSequence(seed).spawn(runs)[i])``, wherever it executes
(see :mod:`mazegen.runtime.runs._launcher`).
"""

from __future__ import annotations

import platform
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numba
import numpy as np

from mazegen.version import __version__
from mazegen.errors import MazeError, brief
from mazegen.runtime.documents import RunDirectory
from mazegen.runtime.engine import Problem
from mazegen.runtime.runs._results import json_text
from mazegen.runtime.runs._worker import BuildFiles
from mazegen.spec import EVOLUTION_BOUNDS, Spec, out_of_bounds

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
            "format": RunDirectory.RECORD_FORMAT,
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
        """What a worker rebuilds the problem from (the spec with the overrides)."""
        build = self.problem.build_dir
        return BuildFiles(
            spec=self.problem.spec,
            grammar=(build / "grammar.bnf").read_text(encoding="utf-8"),
            fitness=(build / "fitness.py").read_text(encoding="utf-8"),
        )

    def start_files(self) -> dict[str, str | bytes]:
        """The files a run directory holds from its start: the build that runs, and ``experiment.json``."""
        layout = RunDirectory(Path())  # paths relative to the run directory
        files: dict[str, str | bytes] = {str(layout.record): json_text(self.record())}
        for name in BUILD_FILES:
            source = self.problem.build_dir / name
            if layout.build / name == layout.spec:  # the spec with the overrides, not the build's
                files[str(layout.spec)] = self.problem.spec.to_json()
            elif source.is_file():
                files[str(layout.build / name)] = source.read_bytes()
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
