"""File I/O with user-facing guarantees: atomic writes, one-line read errors."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from mazegen.errors import MazeError


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


# Temporary files and folders are private (0600, 0700); what they become is given the modes
# ``open`` and ``mkdir`` would give, so a simulator running as another user can read it.
_UMASK = _umask()
FILE_MODE = 0o666 & ~_UMASK
FOLDER_MODE = 0o777 & ~_UMASK


def make_folder(path: Path) -> None:
    """Create folder ``path`` and its parents; one that cannot be made is a one-line :class:`MazeError`."""
    try:
        path.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise MazeError("cannot create the folder: a file is in the way", filename=str(path)) from None
    except OSError as error:
        raise MazeError(f"cannot create the folder: {error.strerror or error}", filename=str(path)) from None


@contextmanager
def disk_errors(path: Path, doing: str = "write") -> Iterator[None]:
    """Turn an :class:`OSError` of the block (disk full, read-only file system…) into a one-line
    :class:`MazeError` naming ``path``: ``cannot write: No space left on device``."""
    try:
        yield
    except OSError as error:
        raise MazeError(f"cannot {doing}: {error.strerror or error}", filename=str(path)) from None


def write_atomic(path: Path, data: str | bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file and a rename: whole or not at all.

    Raises:
        MazeError: when the file cannot be written (disk full, read-only file system…).
    """
    make_folder(path.parent)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    with disk_errors(path):
        fd, temp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        try:
            with os.fdopen(fd, "wb") as handle:
                os.fchmod(handle.fileno(), FILE_MODE)
                handle.write(payload)
            os.replace(temp, path)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise


def read_text(path: Path, what: str) -> str:
    """Read a UTF-8 text file; a missing or unreadable file is a one-line :class:`MazeError`.

    Args:
        path: The file.
        what: What the file is, for the message (``spec``, ``scenario``…).
    """
    try:
        return path.read_text(encoding="utf-8")
    except OSError as error:
        raise MazeError(f"cannot read {what}: {error.strerror or error}", filename=str(path)) from None
    except UnicodeDecodeError:
        raise MazeError(f"cannot read {what}: not UTF-8 text", filename=str(path)) from None


def json_value(text: str) -> Any:
    """``json.loads``, every kind of damage a :class:`ValueError`: nesting too deep for the parser
    (a ``RecursionError``) too, so that readers of MazeGen's own files catch one exception."""
    try:
        return json.loads(text)
    except RecursionError:
        raise ValueError("nested too deeply") from None
