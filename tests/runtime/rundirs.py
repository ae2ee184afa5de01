"""Run directories compared file by file: what must be identical whatever the executor or interruptions."""

from __future__ import annotations

import hashlib
from pathlib import Path

from click.testing import CliRunner, Result

import mazegen
from mazegen.cli.main import main
from tests.conftest import EXAMPLES

NOT_DETERMINISTIC = ("timing.csv",)
"""Wall-clock seconds: the only file of a run directory that differs between equal runs."""


def file_digests(directory: Path) -> dict[str, str]:
    """SHA-256 of every file under ``directory`` but the timings, by relative path."""
    return {
        str(path.relative_to(directory)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(directory.rglob("*"))
        if path.is_file() and path.name not in NOT_DETERMINISTIC
    }


SPEC = EXAMPLES / "factory.maze"
SMALL = {"seed": 2, "runs": 2, "population": 30, "generations": 3}
"""A run directory of a second or so."""


class Killed(BaseException):
    """Stands for a kill -9 at a chosen point: no ``except Exception`` handles it."""


def small_run(out: Path, catalog: Path | bool = False, *, source: Path = SPEC, **options) -> None:
    """Run :data:`SMALL` into ``out``, in this process."""
    mazegen.run(source, **SMALL, out_dir=out, catalog=catalog, executor="serial", **options)


def invoke(*args: str) -> Result:
    """A ``mazegen`` command run in this process."""
    return CliRunner().invoke(main, list(args), catch_exceptions=False)
