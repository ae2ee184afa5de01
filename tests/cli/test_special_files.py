"""Entries that are not regular files, such as a FIFO named like a scenario, are never read: a folder's
walk skips them with a line that says so, a file given by name is a one-line error.

Reading a FIFO waits for a writer forever, so each command runs in a process of its own whose
timeout only guards the test against hanging (the commands take a few seconds).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import EXAMPLES

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are a POSIX thing")

GUARD_SECONDS = 600
"""Longest wait for a command before the test fails instead of hanging (a first call compiles kernels)."""


def mazegen(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "mazegen", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=GUARD_SECONDS,
        check=False,
    )


@pytest.fixture
def run_with_fifo(factory_run, tmp_path) -> tuple[Path, Path]:
    """A copy of the factory run directory with a FIFO among its best scenarios."""
    run = tmp_path / "run"
    shutil.copytree(factory_run, run)
    fifo = run / "run-01" / "best-99.json"
    os.mkfifo(fifo)
    return run, fifo


def skipped(fifo: Path) -> str:
    return f"{fifo}: skipped: a FIFO, not a regular file"


def test_folder_walks_skip_a_fifo_and_say_so(run_with_fifo, tmp_path):
    run, fifo = run_with_fifo
    scenarios = len(list(run.glob("run-*/best-*.json"))) - 1
    spec = str(EXAMPLES / "factory.maze")
    commands = {
        "score": ["score", spec, str(run)],
        "drive": ["drive", str(run), "-c", "straight", "--json"],
        "export": ["export", str(run), "-f", "json", "-o", str(tmp_path / "exported")],
        "report": ["report", str(run), "-o", str(tmp_path / "report.html")],
    }
    for name, args in commands.items():
        done = mazegen(*args, cwd=tmp_path)
        assert done.returncode == 0, (name, done.stderr)
        assert skipped(fifo) in done.stderr.splitlines(), (name, done.stderr)
    assert len(list((tmp_path / "exported").rglob("*.json"))) == scenarios
    assert "best-99" not in (tmp_path / "report.html").read_text(encoding="utf-8")


def test_a_fifo_given_by_name_is_a_one_line_error(run_with_fifo, tmp_path):
    _, fifo = run_with_fifo
    spec = str(EXAMPLES / "factory.maze")
    for args in (
        ["render", str(fifo), "-o", str(tmp_path / "floor.svg")],
        ["score", spec, str(fifo)],
        ["drive", str(fifo), "-c", "straight"],
        ["export", str(fifo), "-f", "json", "-o", str(tmp_path / "exported")],
    ):
        done = mazegen(*args, cwd=tmp_path)
        assert done.returncode == 1, (args, done.stderr)
        assert done.stderr.splitlines() == [f"{fifo}: cannot read scenario: a FIFO, not a regular file"], args
