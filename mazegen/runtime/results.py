"""The run directory: statistics, best scenarios, final populations; written whole or not at all."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import shutil
import tempfile
import zipfile
from collections.abc import Iterator
from dataclasses import astuple, fields
from pathlib import Path
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.evolution import GenerationStats

STATS_COLUMNS = ("run", *tuple(f.name for f in fields(GenerationStats)))


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "" if value != value else repr(value)  # NaN (no valid individual) → empty cell
    return str(value)


def stats_csv(rows: list[tuple[int, GenerationStats]]) -> str:
    """``stats.csv`` text: one row per run and generation."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(STATS_COLUMNS)
    for run, stats in rows:
        writer.writerow([run, *(_cell(v) for v in astuple(stats))])
    return buffer.getvalue()


def npz_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """An ``.npz`` archive with fixed timestamps, so equal arrays give equal bytes."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, array in arrays.items():
            member = io.BytesIO()
            np.lib.format.write_array(member, np.ascontiguousarray(array), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            archive.writestr(info, member.getvalue())
    return buffer.getvalue()


def json_text(data: Any) -> str:
    """Deterministic, readable JSON text ending with a newline."""
    return json.dumps(data, indent=2, sort_keys=True) + "\n"


@contextlib.contextmanager
def staged_directory(target: Path, *, force: bool) -> Iterator[Path]:
    """Yield a temporary directory that replaces ``target`` only if the block succeeds.

    An interrupted or failed run leaves ``target`` as it was.
    """
    if target.exists() and any(target.iterdir()) and not force:
        raise MazeError(
            "output directory already exists and is not empty (use --force to replace it, "
            "or -o to choose another)",
            filename=str(target),
        )
    target.parent.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        yield stage
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    old = None
    if target.exists():
        old = target.parent / f"{stage.name}.old"
        target.rename(old)
    stage.rename(target)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
