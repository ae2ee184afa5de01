"""File I/O with user-facing guarantees: atomic writes, one-line read errors, only regular files read."""

from __future__ import annotations

import json
import os
import stat
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from mazegen.errors import MazeError
from mazegen.text import printable


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


_KINDS = {stat.S_IFDIR: "a folder", stat.S_IFIFO: "a FIFO", stat.S_IFSOCK: "a socket"}


def _not_regular(mode: int) -> str | None:
    """What a file of ``mode`` is when it is not a regular file (``a FIFO, not a regular file``)."""
    if stat.S_ISREG(mode):
        return None
    return f"{_KINDS.get(stat.S_IFMT(mode), 'a device')}, not a regular file"


def read_bytes(path: Path, what: str, *, limit: int = -1) -> bytes:
    """The bytes of a regular file (at most ``limit``); anything else is a one-line :class:`MazeError`.

    A FIFO is opened without waiting and refused: reading one would wait for a writer forever,
    and a device may never end.

    Args:
        path: The file.
        what: What the file is, for the message (``spec``, ``scenario``…).
        limit: Read no more than this many bytes (-1: all).
    """
    try:
        with open(os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)), "rb") as file:
            kind = _not_regular(os.fstat(file.fileno()).st_mode)
            if kind is None:
                return file.read(limit)
    except OSError as error:
        raise MazeError(f"cannot read {what}: {error.strerror or error}", filename=str(path)) from None
    raise MazeError(f"cannot read {what}: {kind}", filename=str(path))


def read_text(path: Path, what: str) -> str:
    """Read a UTF-8 text file; a missing or unreadable file, or one that is not a regular file, is a
    one-line :class:`MazeError`.

    Args:
        path: The file.
        what: What the file is, for the message (``spec``, ``scenario``…).
    """
    try:
        return read_bytes(path, what).decode("utf-8")
    except UnicodeDecodeError:
        raise MazeError(f"cannot read {what}: not UTF-8 text", filename=str(path)) from None


def found_files(folder: Path, pattern: str) -> list[Path]:
    """The regular files ``folder.glob(pattern)`` finds, in name order.

    Any other entry a name matches (a FIFO, a device, a folder) is said on one line of standard
    error and skipped, never opened: a FIFO would keep its reader waiting forever. One that cannot
    be looked at (a dangling link) stays, for its reader to report.
    """
    found = []
    for path in sorted(folder.glob(pattern)):
        try:
            kind = _not_regular(path.stat().st_mode)
        except OSError:
            kind = None
        if kind is None:
            found.append(path)
        else:
            print(f"{printable(str(path))}: skipped: {kind}", file=sys.stderr)
    return found


def json_value(text: str) -> Any:
    """``json.loads``, every kind of damage a :class:`ValueError`: nesting too deep for the parser
    (a ``RecursionError``) too, so that readers of MazeGen's own files catch one exception."""
    try:
        return json.loads(text)
    except RecursionError:
        raise ValueError("nested too deeply") from None
