"""Runs that survive: kill -9 or Ctrl-C, then `mazegen resume`, end byte-identical to an uninterrupted run."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.runtime.launcher import RunsInterrupted
from mazegen.runtime.progress import QuietReporter
from tests.conftest import EXAMPLES
from tests.runtime.rundirs import file_digests

SPEC = EXAMPLES / "factory.maze"
SETTINGS = {"seed": 4, "runs": 2, "population": 800, "generations": 80}
"""Long enough (about a second a run) to be killed in the middle."""


def invoke(*args: str):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def settings_args() -> list[str]:
    return [part for key, value in SETTINGS.items() for part in (f"--{key}", str(value))]


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory) -> dict[str, str]:
    """The reference: the same experiment run in this process, one run after the other."""
    out = tmp_path_factory.mktemp("reference") / "run"
    mazegen.run(SPEC, **SETTINGS, out_dir=out, executor="serial", catalog=False)
    return file_digests(out)


class _CtrlCAt(QuietReporter):
    """Presses Ctrl-C (a real SIGINT to this process) when run 1 reaches ``generation``."""

    def __init__(self, generation: int) -> None:
        self.generation_to_stop = generation

    def generation(self, key, stats) -> None:
        if key[1] == 1 and stats.generation == self.generation_to_stop:
            os.kill(os.getpid(), signal.SIGINT)


def interrupted_run(out: Path) -> None:
    with pytest.raises(RunsInterrupted):
        mazegen.run(SPEC, **SETTINGS, out_dir=out, reporter=_CtrlCAt(5), checkpoint_every=2, catalog=False)


def test_ctrl_c_saves_a_checkpoint_and_resume_skips_a_damaged_one(tmp_path, uninterrupted):
    out = tmp_path / "run"
    interrupted_run(out)
    assert not (out / "stats.csv").exists()
    checkpoints = sorted(p.name for p in (out / "checkpoints" / "run-01").iterdir())
    assert checkpoints == ["gen-000004.ckpt", "gen-000005.ckpt"]  # every 2, and where Ctrl-C stopped it
    assert not (out / "checkpoints" / "run-02").exists()  # never started
    newest = out / "checkpoints" / "run-01" / "gen-000005.ckpt"
    newest.write_bytes(newest.read_bytes()[:1000])  # truncated

    result = invoke("resume", str(out), "-q", "--executor", "serial", "--catalog", str(tmp_path / "c.sqlite"))
    assert result.exit_code == 0, result.output
    assert "gen-000005.ckpt: damaged checkpoint" in result.stderr and "using the one before" in result.stderr
    assert file_digests(out) == uninterrupted
    assert not (out / "checkpoints").exists() and (out / "timing.csv").is_file()


def test_resume_refuses_what_it_cannot_continue(tmp_path, uninterrupted):
    out = tmp_path / "run"
    interrupted_run(out)
    for path in (out / "checkpoints" / "run-01").iterdir():
        path.write_bytes(b"not a checkpoint")
    errors = {
        "all damaged": invoke("resume", str(out), "-q", "--executor", "serial"),
        "not a run": invoke("resume", str(tmp_path), "-q"),
    }
    (out / "stats.csv").write_text("")
    shutil.rmtree(out / "checkpoints")  # a directory's ending deletes them last
    errors["finished"] = invoke("resume", str(out), "-q")
    for name, result in errors.items():
        assert result.exit_code == 1, name
        assert len(result.stderr.strip().splitlines()) == 1 and "Traceback" not in result.output, name
    assert "run-01: no usable checkpoint (2 damaged)" in errors["all damaged"].stderr
    assert errors["not a run"].stderr.strip().endswith("not a MazeGen run directory (no experiment.json)")
    assert errors["finished"].stderr.strip().endswith("this run directory is finished: nothing to resume")


def test_kill_9_then_resume_gives_the_same_files(tmp_path, uninterrupted):
    out = tmp_path / "run"
    command = [sys.executable, "-m", "mazegen", "run", str(SPEC), *settings_args(), "-o", str(out)]
    # Two local worker processes; checkpoints every generation; its own process group to kill.
    process = subprocess.Popen(
        [*command, "--checkpoint-every", "1", "--catalog", str(tmp_path / "c.sqlite"), "-q"],
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 120
        while not list((out / "checkpoints" / "run-01").glob("gen-00000[3-9].ckpt")):
            assert process.poll() is None, process.stderr.read().decode() if process.stderr else ""
            assert time.monotonic() < deadline, "no checkpoint within two minutes"
            time.sleep(0.01)
    finally:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    assert not (out / "stats.csv").exists(), "the run finished before it was killed"

    result = invoke("resume", str(out), "-q", "--catalog", str(tmp_path / "c.sqlite"))
    assert result.exit_code == 0, result.output
    assert file_digests(out) == uninterrupted
    listed = invoke("runs", "--catalog", str(tmp_path / "c.sqlite")).output.splitlines()
    assert len(listed) == 3 and all(" finished " in line for line in listed[1:])
