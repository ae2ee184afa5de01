"""What the commands that launch runs do before the runs: compile the kernels of a first run ahead."""

from __future__ import annotations

import csv

from click.testing import CliRunner

import mazegen
import mazegen.cli.launching
import mazegen.runtime
import mazegen.runtime.runs._warmup
from mazegen.cli.launching import compile_first
from mazegen.cli.main import main
from mazegen.runtime.catalog._catalog import Catalog
from mazegen.runtime.catalog._catalog_query import run_rows
from mazegen.runtime.engine._problem import Problem
from mazegen.runtime.reports._report import read_run
from mazegen.runtime.runs._progress import FIRST_COMPILE_NOTE
from tests.conftest import EXAMPLES
from tests.runtime.runs.test_progress import Notes


def test_only_a_first_local_run_compiles_ahead(monkeypatch, tmp_path):
    compiled = []
    monkeypatch.setattr(
        mazegen.runtime.runs._warmup, "compile_kernels", lambda problem: compiled.append(problem)
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


def test_the_kernels_compiled_ahead_count_in_the_first_runs_first_generation(monkeypatch, tmp_path):
    # A first run waited minutes for its kernels, yet its report said it took 0.14 seconds: only its
    # generations were timed, and the kernels had been compiled before the first one.
    monkeypatch.setattr(mazegen.runtime.runs._warmup, "compile_kernels", lambda problem: None)
    monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(): False)
    clock = iter([100.0, 1100.0])  # compiling ahead took 1000 seconds
    monkeypatch.setattr(mazegen.cli.launching, "monotonic", lambda: next(clock))
    out = tmp_path / "run"
    args = ["run", str(EXAMPLES / "factory.maze"), "--runs", "2", "--population", "20", "--generations", "1"]
    result = CliRunner().invoke(main, [*args, "--executor", "serial", "-q", "-o", str(out)])
    assert result.exit_code == 0, result.output
    rows = csv.DictReader((out / "timing.csv").open())
    timing = {(row["run"], row["generation"]): float(row["seconds"]) for row in rows}
    assert timing["1", "0"] >= 1000 and timing["1", "1"] < 1000
    assert timing["2", "0"] < 1000  # counted once: run 2 would have found them compiled
    assert read_run(out).seconds[1] >= 1000 > read_run(out).seconds[2]  # what the report shows
    with Catalog.open(tmp_path / "catalog.sqlite", create=False) as catalog:
        assert [row["seconds"] >= 1000 for row in run_rows(catalog)] == [True, False]
