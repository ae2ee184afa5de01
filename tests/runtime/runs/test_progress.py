"""Progress: a bar per run and one over all runs, with evaluations per second."""

from __future__ import annotations

import importlib
import io
import pkgutil
from pathlib import Path

import numba
from click.testing import CliRunner
from rich.console import Console

import mazegen
import mazegen.runtime
from mazegen.cli.main import main
from mazegen.runtime import kernels_cached
from mazegen.runtime.engine._evolution import GenerationStats
from mazegen.runtime.runs._progress import FIRST_COMPILE_NOTE, QuietReporter, RichReporter
from tests.conftest import EXAMPLES
from tests.runtime.floors import floor_file


def kernel_module(name: str) -> str:
    """The runtime module numba files a kernel under: kernels are named after their file alone."""
    found = [
        module.name
        for module in pkgutil.walk_packages(mazegen.runtime.__path__, "mazegen.runtime.")
        if module.name.rpartition(".")[2] == name
    ]
    assert len(found) == 1, found
    return found[0]


def test_a_bar_per_run_under_an_overall_bar_with_rates():
    screen = io.StringIO()
    reporter = RichReporter(Console(file=screen, width=120, force_terminal=False))
    reporter.add_run((0, 1), "run 1/2", 2)
    reporter.add_run((0, 2), "run 2/2", 2, done=2)  # resumed after its second generation
    for generation in range(3):
        reporter.generation(
            (0, 1), GenerationStats(generation, 500, 4.0 + generation, 2.0, 2.0, 0, 500, 0, 0.25)
        )
    reporter.finish_run((0, 1))
    reporter.generation((0, 1), GenerationStats(3, 500, 9.0, 2.0, 2.0, 0, 500, 0, 0.25))  # late: ignored
    reporter.generation((0, 2), GenerationStats(2, 100, 7.0, 2.0, 2.0, 0, 100, 0, 0.5))
    reporter.finish_run((0, 2))
    reporter.note("a note")
    reporter.close()
    lines = screen.getvalue().splitlines()
    overall = next(line for line in lines if line.startswith("all runs"))
    first = next(line for line in lines if line.startswith("run 1/2"))
    second = next(line for line in lines if line.startswith("run 2/2"))
    assert "6/6" in overall and "evaluations/s" in overall
    assert "best 7 " in overall  # the best of every run (run 2's), not the late report's 9
    assert "3/3" in first and "best 6 " in first and "2,000 evaluations/s" in first  # 1,500 in 0.75 s
    assert "3/3" in second and "200 evaluations/s" in second
    assert "a note" in lines


class Notes(QuietReporter):
    """A reporter that keeps its notes."""

    def __init__(self) -> None:
        self.notes: list[str] = []

    def note(self, message: str) -> None:
        self.notes.append(message)


def test_kernels_are_cached_once_every_run_kernel_has_an_index(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path))
    assert not kernels_cached()
    folder = tmp_path / "work" / "main"  # numba keeps the sources' folders below the cache's
    folder.mkdir(parents=True)
    (folder / "_mapping._map_all-5.py311.nbi").write_bytes(b"")
    assert not kernels_cached()  # a first run cut short: the scenario metrics' kernel is missing
    (folder / "_difficulty._survey_all-9.py311.1.nbc").write_bytes(b"")
    assert not kernels_cached()  # compiled code without its index is not found by numba
    (folder / "_difficulty._survey_all-9.py311.nbi").write_bytes(b"")
    assert kernels_cached()


def test_a_first_run_says_it_is_compiling(monkeypatch, tmp_path):
    spec = mazegen.load(EXAMPLES / "factory.maze")
    for cached, notes in ((False, [FIRST_COMPILE_NOTE]), (True, [])):
        monkeypatch.setattr(mazegen.runtime, "kernels_cached", lambda kernels=(), cached=cached: cached)
        reporter = Notes()
        mazegen.run(spec, population=20, generations=1, reporter=reporter)
        assert reporter.notes == notes


def test_a_score_that_compiles_says_so_once_and_keeps_its_table(monkeypatch, tmp_path):
    from numba import njit

    from mazegen.runtime.compiling import DRIVE_SECONDS, compile_note
    from mazegen.runtime.documents._scoring import Scorer

    monkeypatch.undo()  # the real note, not the tests' silence (conftest)
    floor = floor_file(tmp_path / "floor.json", {"type": "router", "x": 300, "y": 100, "size": 30})
    score = ["score", str(EXAMPLES / "factory.maze"), str(floor)]
    CliRunner().invoke(main, score)  # compiles what is not cached yet
    quiet = CliRunner().invoke(main, score)
    real_score = Scorer.score

    def compiling(self, *args, **kwargs):  # as a score whose kernels were never compiled would
        njit(lambda x: x + 5)(1)
        return real_score(self, *args, **kwargs)

    monkeypatch.setattr(Scorer, "score", compiling)
    noted = CliRunner().invoke(main, score)
    assert quiet.exit_code == noted.exit_code == 0 and quiet.stderr == ""
    assert noted.stderr.splitlines() == [compile_note("score", DRIVE_SECONDS)]
    assert noted.stdout == quiet.stdout and noted.stdout.splitlines()[:2] == ["fitness\t1", "elements\t1"]
