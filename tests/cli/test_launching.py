"""What the commands that launch runs do before the runs: compile the kernels of a first run ahead."""

from __future__ import annotations

import mazegen
import mazegen.runtime
import mazegen.runtime.runs.warmup
from mazegen.cli.launching import compile_first
from mazegen.runtime.engine.problem import Problem
from mazegen.runtime.runs.progress import FIRST_COMPILE_NOTE
from tests.conftest import EXAMPLES
from tests.runtime.runs.test_progress import Notes


def test_only_a_first_local_run_compiles_ahead(monkeypatch, tmp_path):
    compiled = []
    monkeypatch.setattr(
        mazegen.runtime.runs.warmup, "compile_kernels", lambda problem: compiled.append(problem)
    )
    spec = mazegen.load(EXAMPLES / "factory.maze")
    mazegen.build(spec, tmp_path / "build")
    problem = Problem.from_build_dir(tmp_path / "build")
    for cached, executor, calls in (
        (True, "local", 0),  # the conftest's default: kernels cached
        (False, "dask", 0),  # a cluster's workers compile their own
        (False, "local", 1),
        (False, "serial", 1),
    ):
        monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(), cached=cached: cached)
        compiled.clear()
        for source in (spec, tmp_path / "build", problem):  # a spec, a build directory, a loaded problem
            reporter = Notes()
            compile_first(source, executor, reporter)  # type: ignore[arg-type]
            assert reporter.notes == [FIRST_COMPILE_NOTE] * calls
        assert len(compiled) == 3 * calls
        assert any(item is problem for item in compiled) or not calls  # a loaded problem, not reloaded
        assert all(problem.spec.name == "factory" for problem in compiled)
