"""A run directory's life: its start and its end are whole or resumable, failures and full disks are one line.

Kills are simulated deterministically: an exception that is not an ``Exception`` (as a kill
is not) raised at a chosen write, or the half-written states built by hand.
"""

from __future__ import annotations

import errno
import os
import sqlite3
from pathlib import Path

import pytest

import mazegen
from mazegen import api, fileio
from mazegen.errors import MazeError
from mazegen.runtime.catalog import _catalog as catalog_module
from mazegen.runtime.catalog._catalog import Catalog
from mazegen.runtime.documents._folders import RunDirectory
from mazegen.runtime.runs import _results as results
from mazegen.runtime.runs._results import RunDirectoryWriter, staged_directory
from tests.runtime.rundirs import SMALL, SPEC, Killed, file_digests, invoke, small_run

FULL = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def statuses(catalog: Path, table: str = "experiments") -> list[str]:
    with sqlite3.connect(catalog) as db:
        return [row[0] for row in db.execute(f"SELECT status FROM {table}")]


def replace_failing_at(
    monkeypatch, count: int, error: BaseException, *, under: Path, suffix: str = ""
) -> None:
    """Make the ``count``-th atomic write under ``under`` (of names ending with ``suffix``) fail."""
    real, seen = os.replace, []

    def replace(source, target) -> None:
        if Path(target).is_relative_to(under) and str(target).endswith(suffix):
            seen.append(target)
            if len(seen) == count:
                raise error
        real(source, target)

    monkeypatch.setattr(fileio.os, "replace", replace)


@pytest.mark.parametrize("kill_at", [1, 2, 3, 4, 5])
def test_a_kill_during_the_start_leaves_no_run_directory(tmp_path, monkeypatch, kill_at):
    out = tmp_path / "run"
    with monkeypatch.context() as patched:
        replace_failing_at(patched, kill_at, Killed(), under=tmp_path)
        with pytest.raises(Killed):
            small_run(out)
    assert sorted(os.listdir(tmp_path)) == []  # neither a half-made directory nor its stage
    small_run(out)  # no --force needed
    assert (out / "stats.csv").is_file()


def test_a_stage_left_by_a_killed_start_is_deleted_by_the_next_run(tmp_path, small_reference):
    out = tmp_path / "run"
    stage = tmp_path / f".run.{results.STAGED_START}x1y2"
    (stage / "experiment").mkdir(parents=True)
    (stage / "experiment.json").write_text("{}")
    small_run(out)
    assert sorted(os.listdir(tmp_path)) == ["run"] and file_digests(out) == small_reference


def test_a_run_that_fails_before_any_progress_leaves_nothing_and_is_catalogued_failed(tmp_path):
    build = tmp_path / "build"
    mazegen.build(SPEC, build)
    fitness = build / "fitness.py"
    text = fitness.read_text()
    fitness.write_text(text.replace("    return {", '    raise RuntimeError("edited")\n    return {', 1))
    out = tmp_path / "runs" / "x"
    catalog = out.parent / "catalog.sqlite"
    with pytest.raises(MazeError, match="edited"):
        mazegen.run(build, **SMALL, out_dir=out)
    assert not out.exists() and statuses(catalog) == ["failed"]
    assert statuses(catalog, "runs") == ["failed", "failed"]  # none left pending
    listed = invoke("runs", "--catalog", str(catalog)).stdout.splitlines()
    assert [line.split()[2] for line in listed[1:]] == ["failed", "failed"]
    assert [name for name in os.listdir(out.parent) if not name.startswith("catalog.sqlite")] == []

    fitness.write_text(text)
    mazegen.run(build, **SMALL, out_dir=out)  # the next try needs no --force
    assert statuses(catalog) == ["finished"] and statuses(catalog, "runs") == ["finished", "finished"]


@pytest.mark.parametrize("kill", ["catalog", "checkpoints"])
def test_resume_ends_a_directory_killed_while_ending(tmp_path, monkeypatch, small_reference, kill):
    out, catalog = tmp_path / "run", tmp_path / "c.sqlite"
    with monkeypatch.context() as patched:
        if kill == "catalog":
            real = Catalog.finish_experiment

            def finish(self, experiment, *, status):
                if status == "finished":
                    raise Killed
                real(self, experiment, status=status)

            patched.setattr(Catalog, "finish_experiment", finish)
        else:
            patched.setattr(
                RunDirectoryWriter, "drop_checkpoints", lambda self: (_ for _ in ()).throw(Killed())
            )
        with pytest.raises(Killed):
            small_run(out, catalog)
    assert (out / "stats.csv").is_file() and list((out / "checkpoints").rglob("*.ckpt"))

    result = invoke("resume", str(out), "-q", "--executor", "serial", "--catalog", str(catalog))
    assert result.exit_code == 0, result.output
    assert file_digests(out) == small_reference and not (out / "checkpoints").exists()
    assert statuses(catalog) == ["finished"]


def test_resume_deletes_checkpoints_whose_deletion_was_killed(tmp_path, small_reference):
    out = tmp_path / "run"
    small_run(out)
    (RunDirectory(out).dropped_checkpoints / "run-01").mkdir(parents=True)  # renamed, not yet deleted
    (RunDirectory(out).dropped_checkpoints / "run-01" / "gen-000003.ckpt").write_bytes(b"checkpoint")
    result = invoke("resume", str(out), "-q")
    assert result.exit_code == 1 and "finished: nothing to resume" in result.stderr
    assert file_digests(out) == small_reference


def test_a_full_disk_at_a_checkpoint_is_one_line_naming_the_file(tmp_path, monkeypatch):
    out = tmp_path / "run"
    replace_failing_at(monkeypatch, 1, FULL, under=tmp_path, suffix=".ckpt")
    with pytest.raises(MazeError) as error:
        small_run(out)
    assert (
        str(error.value) == f"{out}/checkpoints/run-01/gen-000003.ckpt: cannot write: No space left on device"
    )
    assert not out.exists()  # nothing to resume from: nothing kept


def test_a_full_disk_after_progress_keeps_what_resume_needs(tmp_path, monkeypatch, small_reference):
    out = tmp_path / "run"
    with monkeypatch.context() as patched:
        replace_failing_at(patched, 2, FULL, under=tmp_path, suffix=".ckpt")
        with pytest.raises(
            MazeError, match=r"run-02/gen-000003\.ckpt: cannot write: No space left on device"
        ):
            small_run(out)
    assert (out / "run-01").is_dir()
    api.resume(out, catalog=False)
    assert file_digests(out) == small_reference


def test_a_read_only_disk_is_one_line_and_replaces_nothing(tmp_path, monkeypatch, small_reference):
    out, build = tmp_path / "run", tmp_path / "build"
    small_run(out)
    mazegen.build(SPEC, build)

    def read_only(*args, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(results.tempfile, "mkdtemp", read_only)
    with pytest.raises(MazeError) as error:
        small_run(out, source=build, force=True)  # a build: running a spec needs a temporary folder
    assert str(error.value) == f"{out}: cannot create the folder: Read-only file system"
    assert file_digests(out) == small_reference
    suite = pytest.raises(MazeError, match="suite: cannot create the folder: Read-only file system")
    with suite, staged_directory(tmp_path / "suite", force=False):
        pass


def test_a_folder_that_cannot_be_written_is_named(tmp_path):
    result = invoke("run", str(SPEC), "--runs", "1", "-q", "--executor", "serial", "-o", "/proc/mazegen-run")
    assert result.exit_code == 1 and result.stderr == "/proc: cannot write in this folder\n"


def test_a_catalog_on_a_full_disk_is_not_called_damaged(tmp_path, monkeypatch):
    path = tmp_path / "c.sqlite"
    Catalog.open(path, create=True).close()
    full = sqlite3.OperationalError("database or disk is full")
    full.sqlite_errorname = "SQLITE_FULL"

    class FullDisk:
        def __init__(self, connection: sqlite3.Connection) -> None:
            self._connection = connection

        def execute(self, sql: str, *args):
            if sql.startswith("BEGIN"):
                raise full
            return self._connection.execute(sql, *args)

        def __getattr__(self, name: str):
            return getattr(self._connection, name)

    with Catalog.open(path, create=True) as catalog, pytest.raises(MazeError) as error:
        catalog._db = FullDisk(catalog._db)  # type: ignore[assignment]
        catalog.finish_experiment(1, status="finished")
    assert str(error.value) == f"{path}: cannot write the catalog (database or disk is full)"

    def refused(*args, **kwargs):
        raise full

    monkeypatch.setattr(catalog_module.sqlite3, "connect", refused)
    with pytest.raises(MazeError, match=r"cannot use the catalog \(database or disk is full\)"):
        Catalog.open(path, create=True)


def test_a_replacement_that_cannot_be_renamed_into_place_keeps_the_old_directory(
    tmp_path, monkeypatch, small_reference
):
    out, build = tmp_path / "run", tmp_path / "build"
    small_run(out)
    mazegen.build(SPEC, build)
    real = Path.rename

    def rename(self: Path, target):
        staged = self.name.startswith(f".run.{results.STAGED_START}") and not self.name.endswith(".old")
        if Path(target) == out and staged:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, target)

    monkeypatch.setattr(Path, "rename", rename)
    with pytest.raises(MazeError, match="run: cannot write: No space left on device"):
        small_run(out, source=build, force=True)
    assert file_digests(out) == small_reference and sorted(os.listdir(tmp_path)) == ["build", "run"]
