"""Runs that survive: kill -9 or Ctrl-C, then `mazegen resume`, end byte-identical to an uninterrupted run."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.runtime.runs._launcher import RunsInterrupted
from mazegen.runtime.runs._progress import QuietReporter
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


RUN_MARK = "MAZEGEN_TEST_RUN"
"""An environment variable that marks every process of a run started by a test, workers included."""


def processes_of(mark: str) -> list[int]:
    """The live processes (zombies aside) whose environment carries ``RUN_MARK=mark``."""
    needle = f"\0{RUN_MARK}={mark}\0".encode()
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            environ = (entry / "environ").read_bytes()
            state = (entry / "stat").read_text().rpartition(")")[2].split()[0]
        except OSError:  # gone meanwhile, or another user's
            continue
        if state != "Z" and needle in b"\0" + environ + b"\0":
            found.append(int(entry.name))
    return found


def wait_for(condition, what: str, timeout: float = 120) -> None:
    """Poll ``condition`` until it holds; fail after a generous ``timeout`` (seconds)."""
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, f"{what}: not within {timeout} s"
        time.sleep(0.02)


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="finds the run's processes in /proc")
def test_kill_9_of_the_launcher_leaves_no_process_and_resume_gives_the_same_files(tmp_path, uninterrupted):
    out, catalog, mark = tmp_path / "run", str(tmp_path / "c.sqlite"), uuid.uuid4().hex
    command = [sys.executable, "-m", "mazegen", "run", str(SPEC), *settings_args(), "-o", str(out)]
    errors = tmp_path / "stderr.txt"
    local = ["--executor", "local", "--workers", "2", "--checkpoint-every", "1", "--catalog", catalog, "-q"]
    with errors.open("wb") as stderr:  # a file, not a pipe: a pipe would wait for orphans holding it
        # Two local worker processes, checkpoints every generation, in a session of its own.
        process = subprocess.Popen(
            [*command, *local],
            start_new_session=True,
            stdout=subprocess.DEVNULL,
            stderr=stderr,
            env={**os.environ, RUN_MARK: mark},
        )
    try:

        def mid_run() -> bool:
            assert process.poll() is None, errors.read_text()
            return bool(list((out / "checkpoints" / "run-01").glob("gen-00000[3-9].ckpt")))

        wait_for(mid_run, "a checkpoint of generation 3")
        # Frozen (still alive, and not finishing meanwhile), the run holds its directory.
        os.killpg(process.pid, signal.SIGSTOP)
        for refused in (
            invoke("resume", str(out), "-q", "--executor", "serial", "--catalog", catalog),
            invoke(*command[3:], "--force", "-q", "--executor", "serial", "--catalog", catalog),
        ):
            assert refused.exit_code == 1
            assert refused.stderr.count("\n") == 1, refused.stderr
            assert refused.stderr.strip().endswith("this run directory is in use by another mazegen process")
        assert (out / "experiment.json").is_file()  # --force removed nothing

        os.kill(process.pid, signal.SIGKILL)  # the launcher only: its workers must follow it
        process.wait()
        with contextlib.suppress(ProcessLookupError):  # the rest of the run, if any is left
            os.killpg(process.pid, signal.SIGCONT)
        wait_for(lambda: not processes_of(mark), "the run's workers, fork server and resource tracker ending")
        # Their stderr is the launcher's: multiprocessing's resource tracker removes the semaphores
        # of the killed launcher, and must not warn about it.
        assert "leaked semaphore" not in errors.read_text(), errors.read_text()
    finally:
        for pid in processes_of(mark):
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    assert not (out / "stats.csv").exists(), "the run finished before it was killed"

    result = invoke("resume", str(out), "-q", "--catalog", catalog)
    assert result.exit_code == 0, result.output
    assert file_digests(out) == uninterrupted
    listed = invoke("runs", "--catalog", catalog).output.splitlines()
    assert len(listed) == 3 and all(" finished " in line for line in listed[1:])
