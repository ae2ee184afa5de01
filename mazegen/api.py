"""The Python API: load a spec, build it, run it, get the best scenarios.

Example::

    import mazegen
    spec = mazegen.load("examples/factory.maze")
    result = mazegen.run(spec, seed=3, population=500)
    print(result.best[0][0]["phenotype"])
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from mazegen.dsl.loader import load_spec
from mazegen.generator.build import build as build_files
from mazegen.spec import Spec

if TYPE_CHECKING:
    from mazegen.runtime.experiment import ExperimentResult
    from mazegen.runtime.progress import Reporter


def load(path: str | os.PathLike[str]) -> Spec:
    """Load and check a ``.maze`` spec.

    Raises:
        MazeError: located at the user's line for any mistake in the spec.
    """
    return load_spec(path)


def build(spec: Spec | str | os.PathLike[str], out_dir: str | os.PathLike[str]) -> list[Path]:
    """Generate grammar.bnf, fitness.py, experiment.py and spec.json into ``out_dir``.

    ``spec`` is a :class:`Spec` or the path of a ``.maze`` file.
    """
    return build_files(spec if isinstance(spec, Spec) else load_spec(spec), Path(out_dir))


def run(
    spec: Spec | str | os.PathLike[str],
    *,
    seed: int | None = None,
    runs: int | None = None,
    population: int | None = None,
    generations: int | None = None,
    out_dir: str | os.PathLike[str] | None = None,
    force: bool = False,
    reporter: Reporter | None = None,
) -> ExperimentResult:
    """Run a spec (a :class:`Spec`, a ``.maze`` file or a build directory).

    Settings given here override the spec's evolution block. With ``out_dir`` the
    run directory is written (atomically); the result holds each run's final
    population and best scenario documents either way.
    """
    from mazegen.runtime.experiment import Experiment

    def _run(build_dir: Path) -> ExperimentResult:
        experiment = Experiment.from_build_dir(build_dir).with_settings(
            seed=seed, runs=runs, population=population, generations=generations
        )
        return experiment.run(
            out_dir=None if out_dir is None else Path(out_dir), force=force, reporter=reporter
        )

    if not isinstance(spec, Spec) and Path(spec).is_dir():
        return _run(Path(spec))
    resolved = spec if isinstance(spec, Spec) else load_spec(spec)
    with tempfile.TemporaryDirectory(prefix="mazegen-build-") as temp:
        build_files(resolved, Path(temp))
        return _run(Path(temp))
