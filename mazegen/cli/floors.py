"""Scenario files named on the command line, read as floors: what ``drive`` and ``classes`` share."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import click

from mazegen.cli.errors import skip_file
from mazegen.errors import MazeError

if TYPE_CHECKING:
    from collections.abc import Callable

    from mazegen.runtime.documents import Floor
    from mazegen.spec import Spec


def sources_and_spec(command: Callable) -> Callable:
    """The ``SOURCES...`` argument (scenario files, run and suite directories, folders of them) and the
    ``--spec`` option of a command that reads floors."""
    command = click.option(
        "--spec",
        type=click.Path(exists=True, dir_okay=False, path_type=Path),
        help="The scenarios' spec, when it is not in their run or suite directory.",
    )(command)
    sources = click.argument("sources", nargs=-1, required=True, type=click.Path(exists=True, path_type=Path))
    return sources(command)


def load_spec_file(path: Path | None) -> Spec | None:
    """The spec of ``--spec``, if given."""
    if path is None:
        return None
    from mazegen.dsl.loader import load_spec

    return load_spec(path)


def load_floors(
    files: list[tuple[Path, Path]], spec: Spec | None, *, driving: bool
) -> tuple[list[Floor], bool]:
    """Each scenario file read, completed from its spec and checked against it (``driving``: a robot
    can be sized on its arena); one that cannot be is reported on one line and left out (a lone
    file's error ends the command). A floor with a start and goal of its own is taken on them, with a
    note. Returns the floors and whether one was left out."""
    from mazegen.runtime.documents import driving_robot, load_floor

    floors, failed = [], False
    for path, _ in files:
        try:
            floor = load_floor(path, spec)
            resolved = floor.needs_spec("driving" if driving else "finding classes")
            if driving:
                driving_robot(resolved, floor.where)
            floor.population  # noqa: B018 - builds it, checking every element against the spec
        except MazeError as error:
            skip_file(error, alone=len(files) == 1)
            failed = True
            continue
        note = floor.task_note("driven" if driving else "classified")
        if note is not None:
            click.echo(note, err=True)
        floors.append(floor)
    return floors, failed


def source_files(sources: Sequence[Path]) -> list[tuple[Path, Path]]:
    """Every scenario file of ``sources``, each once, with the folder ``-o`` writes it into: its
    place in its source, under the source's name when several sources are given."""
    from mazegen.runtime.documents import scenario_files

    found: dict[Path, tuple[Path, Path]] = {}
    for source in sources:
        below = Path(source.name) if len(sources) > 1 and source.is_dir() else Path()
        for path, folder in scenario_files(source, any_folder=True):
            found.setdefault(path.resolve(), (path, below / folder))
    return list(found.values())
