"""Who may write a folder: the ``flock`` locks of run directories, and of the folders ``drive -o``
rewrites.

A launch holds an exclusive lock on its run directory, the folder itself, while it writes there;
its workers hold a shared lock on ``checkpoints/`` while a run goes. A folder is free only when
both are, so a second launch (a resume, ``run --force``) or a ``drive -o`` into it is refused
meanwhile, also while the workers of a launcher killed outright are on their way out. A lock goes
with the process that holds it, also when it is killed. Where the system has no ``flock``
(Windows), folders are not locked.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

try:
    import fcntl
except ImportError:  # Windows: folders are not locked
    fcntl = None  # type: ignore[assignment]

from mazegen.errors import MazeError
from mazegen.fileio import make_folder
from mazegen.runtime.documents import RunDirectory


def _flock(path: Path, operation: int) -> int | None:
    """A descriptor of ``path`` holding the ``flock`` ``operation``, or ``None`` when another
    open descriptor holds a lock that a non-blocking one would wait for."""
    handle = os.open(path, os.O_RDONLY)
    try:
        fcntl.flock(handle, operation)
    except BlockingIOError:
        os.close(handle)
        return None
    except BaseException:
        os.close(handle)
        raise
    return handle


def lock_folder(path: Path, what: str) -> int | None:
    """A descriptor holding ``path``'s exclusive lock, taken once no worker writes its ``checkpoints/``
    (None where the system has no ``flock``); closing it releases the lock.

    Raises:
        MazeError: when another process holds either: ``this WHAT is in use by another mazegen process``.
    """
    if fcntl is None:
        return None
    handle = _flock(path, fcntl.LOCK_EX | fcntl.LOCK_NB)
    checkpoints = RunDirectory(path).all_checkpoints
    if handle is not None and checkpoints.is_dir():
        workers = _flock(checkpoints, fcntl.LOCK_EX | fcntl.LOCK_NB)
        if workers is None:
            os.close(handle)
            handle = None
        else:
            os.close(workers)
    if handle is None:
        raise MazeError(f"this {what} is in use by another mazegen process", filename=str(path))
    return handle


@contextlib.contextmanager
def folder_in_use(path: Path) -> Iterator[None]:
    """Hold the lock of the folder ``path`` for the block, creating the folder if need be.

    A command that rewrites the files of a run or suite directory in place (``drive -o``) reads
    and writes them under it, so that no other mazegen process writes there meanwhile and none of
    the two's results is lost.

    Raises:
        MazeError: when another process holds it, or the folder cannot be made.
    """
    make_folder(path)
    handle = lock_folder(path, "folder")
    try:
        yield
    finally:
        if handle is not None:
            os.close(handle)


@contextlib.contextmanager
def writing_checkpoints(folder: Path) -> Iterator[None]:
    """Hold a shared lock on a run directory's ``checkpoints/`` ``folder`` while a worker may write
    there; it waits only for a launch's look whether the folder is free."""
    if fcntl is None:
        yield
        return
    handle = _flock(folder, fcntl.LOCK_SH)
    assert handle is not None, "a blocking lock waits until it is taken"
    try:
        yield
    finally:
        os.close(handle)
