"""Exporting a scenario file, or every scenario of a run or suite directory, whole or not at all."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from mazegen.errors import MazeError
from mazegen.export_formats import ExportFormat
from mazegen.fileio import write_atomic
from mazegen.runtime.documents import Floor, load_floor, scenario_files
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.spec import Spec
from mazegen.text import quoted


def default_out_dir(source: Path, fmt: str) -> Path:
    """Where exports go unless told otherwise: ``exports/FORMAT/`` in the directory of ``source``."""
    return (source if source.is_dir() else source.parent) / "exports" / fmt


def export_plan(
    source: Path,
    fmt: ExportFormat,
    out_dir: Path,
    *,
    spec: Spec | None = None,
    options: ExportOptions | None = None,
) -> dict[Path, bytes]:
    """Every file an export of ``source`` writes, by path, made before anything is written.

    Args:
        source: A scenario file, or a run or suite directory (see
            :func:`~mazegen.runtime.documents._folders.scenario_files`).
        fmt: The format (:func:`~mazegen.export_formats.export_format`).
        out_dir: The directory to write into.
        spec: The scenarios' spec, if not found beside them.
        options: Scale and cell size (each only for the formats that read it).

    Raises:
        MazeError: For an option the format does not read, any scenario that cannot be read or
            exported, or a plug-in's writer that fails or returns anything but files.
    """
    options = options or ExportOptions()
    fmt.check_options(options.given())
    writer = fmt.load_writer()
    files: dict[Path, bytes] = {}
    for path, sub in scenario_files(source):
        floor = load_floor(path, spec)
        for name, data in _written(fmt, writer, floor, options).items():
            if out_dir / sub / name in files:
                raise MazeError(
                    f"{fmt.described} writes {quoted(name)} for another scenario too "
                    "(name each file after the scenario: floor.name)",
                    filename=floor.where,
                )
            files[out_dir / sub / name] = data
    return files


def _written(
    fmt: ExportFormat, writer: Callable[..., Any], floor: Floor, options: ExportOptions
) -> dict[str, bytes]:
    """The files ``writer`` makes of ``floor``, checked: a plug-in's mistake is one line naming it,
    found before anything is written."""
    try:
        files = writer(floor, options)
    except MazeError:
        raise  # a mistake of the user's, said by the writer
    except (Exception, SystemExit) as error:
        if fmt.plugin is None:
            raise
        raise MazeError(
            f"{fmt.described} fails ({type(error).__name__}: {error})", filename=floor.where
        ) from None
    if not isinstance(files, dict):
        raise MazeError(
            f"{fmt.described} returns {type(files).__name__}, not a dict of file names to bytes or str",
            filename=floor.where,
        )
    checked: dict[str, bytes] = {}
    for name, data in files.items():
        if not isinstance(name, str) or name in ("", ".", "..") or any(char in name for char in "/\\\0"):
            raise MazeError(
                f"{fmt.described} returns the file name {quoted(str(name))}: a file's name, not a path",
                filename=floor.where,
            )
        content = _content(data)
        if content is None:
            raise MazeError(
                f"{fmt.described} returns {type(data).__name__} for {quoted(name)}, not bytes or UTF-8 text",
                filename=floor.where,
            )
        checked[name] = content
    return checked


def _content(data: object) -> bytes | None:
    """A file's bytes: ``data`` itself, or text in UTF-8; None when it is neither."""
    if isinstance(data, bytes):
        return data
    try:
        return data.encode("utf-8") if isinstance(data, str) else None
    except UnicodeEncodeError:  # a lone surrogate
        return None


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
