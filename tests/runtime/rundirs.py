"""Run directories compared file by file: what must be identical whatever the executor or interruptions."""

from __future__ import annotations

import hashlib
from pathlib import Path

NOT_DETERMINISTIC = ("timing.csv",)
"""Wall-clock seconds: the only file of a run directory that differs between equal runs."""


def file_digests(directory: Path) -> dict[str, str]:
    """SHA-256 of every file under ``directory`` but the timings, by relative path."""
    return {
        str(path.relative_to(directory)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(directory.rglob("*"))
        if path.is_file() and path.name not in NOT_DETERMINISTIC
    }
