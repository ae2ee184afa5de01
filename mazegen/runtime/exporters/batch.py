"""Exporting a scenario file, or every scenario of a run or suite directory, whole or not at all."""

from __future__ import annotations

from pathlib import Path

from mazegen.errors import MazeError
from mazegen.fileio import write_atomic
from mazegen.runtime.documents.floor import load_floor
from mazegen.runtime.documents.folders import scenario_files
from mazegen.runtime.exporters import FORMATS, check_options
from mazegen.runtime.exporters.floor import ExportOptions
from mazegen.spec import Spec


def default_out_dir(source: Path, fmt: str) -> Path:
    """Where exports go unless told otherwise: ``exports/FORMAT/`` in the directory of ``source``."""
    return (source if source.is_dir() else source.parent) / "exports" / fmt


def export_plan(
    source: Path, fmt: str, out_dir: Path, *, spec: Spec | None = None, options: ExportOptions | None = None
) -> dict[Path, bytes]:
    """Every file an export of ``source`` writes, by path, made before anything is written.

    Args:
        source: A scenario file, or a run or suite directory (see
            :func:`~mazegen.runtime.documents.folders.scenario_files`).
        fmt: A key of :data:`~mazegen.runtime.exporters.FORMATS`.
        out_dir: The directory to write into.
        spec: The scenarios' spec, if not found beside them.
        options: Scale and cell size (each only for the formats that read it).

    Raises:
        MazeError: For an unknown format, an option the format does not read, or any scenario
            that cannot be read or exported.
    """
    if fmt not in FORMATS:
        raise MazeError(f"unknown export format {fmt!r} (one of {', '.join(FORMATS)})")
    options = options or ExportOptions()
    check_options(fmt, options)
    files: dict[Path, bytes] = {}
    for path, sub in scenario_files(source):
        floor = load_floor(path, spec)
        for name, data in FORMATS[fmt](floor, options).items():
            files[out_dir / sub / name] = data
    return files


def write_files(files: dict[Path, bytes], *, force: bool) -> None:
    """Write every file, each atomically; none if one exists already and ``force`` is not set.

    Raises:
        MazeError: For an existing file without ``force``, or a file that cannot be written.
    """
    if not force:
        for path in files:
            if path.exists():
                raise MazeError(
                    "already exists (use --force to replace it, or -o to choose another directory)",
                    filename=str(path),
                )
    for path, data in files.items():
        try:
            write_atomic(path, data)
        except OSError as error:
            raise MazeError(f"cannot write: {error.strerror or error}", filename=str(path)) from None
