"""``mazegen drive SCENARIO.json|RUN_DIR|SUITE_DIR --controller NAME... [--json] [-o DIR]``: robots
driven through scenarios.

Each controller drives every floor in one batch; a floor where the robot has no path from start
to goal is reported (one line on standard error) before anything is driven, and not driven. A
file that cannot be read is reported on one line and skipped; the others are driven, and the
command ends with exit status 1. ``-o DIR`` writes each scenario document with its ``drive``
section, and its picture, to the same relative place in ``DIR``.
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, NoReturn

import click

from mazegen import plugins
from mazegen.cli.errors import reports_errors
from mazegen.cli.floors import load_floors, load_spec_file, source_files, sources_and_spec
from mazegen.controllers import BUNDLED
from mazegen.errors import MazeError
from mazegen.policies import is_policy_path, malformed_path
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.documents import Drive, Floor, Floors, Summary
    from mazegen.spec import Task


def controller_names(given: Sequence[str]) -> list[str]:
    """The controllers of ``--controller`` options (each one name or a comma-separated list), in
    order, each once; an unknown one, or a malformed policy's path, is one line (naming the known
    ones) and exit status 2.

    A name is known when it is bundled, a dotted path ``package.module:name`` to a user's
    policy (loaded when it drives), or registered by an installed package.
    """
    names = list(dict.fromkeys(name.strip() for text in given for name in text.split(",") if name.strip()))
    registered = set(plugins.names("controllers"))
    for name in names:
        if ":" in name and not is_policy_path(name):
            _usage_error(malformed_path(name))
        if name not in BUNDLED and ":" not in name and name not in registered:
            known = ", ".join(sorted({*BUNDLED, *registered}))
            _usage_error(
                f"unknown controller {name!r}: known are {known}, or a user's policy as package.module:name"
            )
    if not names:
        raise MazeError("--controller names no controller")
    return names


def _usage_error(message: str) -> NoReturn:
    click.echo(message, err=True)
    raise SystemExit(2)


controller_option = click.option(
    "-c",
    "--controller",
    "controllers",
    multiple=True,
    metavar="NAME",
    help=f"A controller to drive with: {', '.join(BUNDLED)}, or package.module:name (repeatable, "
    "or comma-separated).",
)
"""The ``--controller`` option of the commands that drive robots."""


@click.command()
@sources_and_spec
@controller_option
@click.option(
    "--json", "as_json", is_flag=True, help="One JSON object per scenario and controller, a line each."
)
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Write each scenario with its drive, and its picture, here (the source's own folder: in place; "
    "with several sources, each under a folder of its name).",
)
@reports_errors
def drive(
    sources: tuple[Path, ...],
    controllers: tuple[str, ...],
    spec: Path | None,
    as_json: bool,
    out: Path | None,
) -> None:
    """Drive robots through SOURCES: scenario files, run or suite directories (their scenarios),
    folders of scenario files, any mix; the floors of one spec drive in one batch.

    Prints per scenario and controller the outcome, time, distance driven and closest approach,
    then per controller the success rate and BARN's mean score. The robot is the spec's, or the
    arena's default (BARN's Jackal limits in the arena's unit).
    """
    if not controllers:
        raise MazeError("give at least one --controller NAME")
    names = controller_names(controllers)
    from mazegen.runtime.compiling import DRIVE_SECONDS, noting_compiles
    from mazegen.runtime.documents import drive_floors, summaries
    from mazegen.runtime.runs import folder_in_use

    resolved = load_spec_file(spec)
    say = partial(click.echo, err=True)
    # -o: the folder is held from the first read to the last write; a second drive into it, a run or
    # a resume of it is refused meanwhile, instead of one overwriting the other's results.
    with contextlib.nullcontext() if out is None else folder_in_use(out):
        files = source_files(sources)
        loaded, failed = load_floors(files, resolved, driving=True)
        with noting_compiles(say, "drive", DRIVE_SECONDS):
            compile_ahead(loaded, names)
            floors_of, drives = drive_floors(
                loaded, names, no_path=lambda file, batch, task: say(no_path_line(file, batch, task))
            )
        if as_json:
            for row in drives:
                for result in row:
                    click.echo(json.dumps(result.record(), allow_nan=False))
        elif drives:
            unit = floors_of[0].spec.arena.unit if floors_of[0].spec else ""
            click.echo(drive_table([result for row in drives for result in row], unit))
            click.echo()
            click.echo(summary_table(summaries(drives, names)))
        if out is not None:
            _write(floors_of, drives, dict(files), out)
    if failed:
        raise SystemExit(1)


def compile_ahead(floors: Sequence[Floor], controllers: Sequence[str]) -> None:
    """Before a first drive of bundled ``controllers``, compile its kernels on two cores at once
    (:func:`mazegen.runtime.runs.compile_drive_kernels`); nothing when their loops are cached. Here
    rather than in the API, as a first run's: a helper process imports the program's main module."""
    from mazegen.runtime import CONTROLLER_KERNELS, kernels_cached
    from mazegen.runtime.runs import compile_drive_kernels

    bundled = [name for name in controllers if name in CONTROLLER_KERNELS]
    spec = next((floor.spec for floor in floors if floor.spec is not None), None)
    if spec is None or not bundled or kernels_cached(tuple(CONTROLLER_KERNELS[name] for name in bundled)):
        return
    with contextlib.suppress(MazeError):  # the drive says what keeps the floors from driving
        compile_drive_kernels(spec, bundled)


def no_path_line(file: str, floors: Floors, task: Task | None) -> str:
    """The line that says a floor (or one of its tasks) is not driven."""
    arena = floors.spec.arena
    named = "" if task is None else f"task {printable(task.name)}: "
    ends = (arena.start, arena.goal) if task is None else (task.start, task.goal)
    start, goal = (f"({x:g}, {y:g})" for x, y in ends)
    return (
        f"{printable(file)}: {named}no path for a robot of radius {arena.robot_radius:g} {arena.unit} "
        f"from start {start} to goal {goal}: not driven"
    )


def drive_table(drives: Sequence[Drive], unit: str) -> str:
    """One row per scenario and controller: outcome, time, distance, closest approach, BARN's score."""
    from mazegen.cli.table import text_table

    rows = [
        {
            "file": result.file,
            "task": result.task,
            "controller": result.controller,
            "outcome": result.outcome,
            "time": round(result.time, 2) if result.driven else None,
            "distance": round(result.distance, 1) if result.driven else None,
            "clearance": None if result.clearance is None else round(result.clearance, 1),
            "score": round(result.score, 3) if result.driven else None,
        }
        for result in drives
    ]
    columns = [
        ("file", "file"),
        *([("task", "task")] if any(result.task is not None for result in drives) else []),
        ("controller", "controller"),
        ("outcome", "outcome"),
        ("time", "time s"),
        ("distance", f"distance {unit}".strip()),
        ("clearance", f"closest {unit}".strip()),
        ("score", "score"),
    ]
    return text_table(rows, columns)


def summary_table(found: Sequence[Summary]) -> str:
    """One row per controller: floors driven, arrivals, success rate and BARN's mean score."""
    from mazegen.cli.table import text_table

    rows = [
        {
            "controller": summary.controller,
            "driven": summary.driven,
            "arrived": summary.arrived,
            "success": None if summary.success is None else round(summary.success, 3),
            "mean_score": None if summary.mean_score is None else round(summary.mean_score, 3),
        }
        for summary in found
    ]
    columns = [
        (key, key.replace("_", " ")) for key in ("controller", "driven", "arrived", "success", "mean_score")
    ]
    return text_table(rows, columns)


def _write(floors: list[Floor], drives: list[list[Drive]], subfolders: dict[Path, Path], out: Path) -> None:
    """Each driven document and its picture into ``out``, at the source's relative place, each
    written whole or not at all; every document is made before any is written, so one that cannot
    be leaves every file as it was."""
    from mazegen.fileio import write_atomic
    from mazegen.runtime.documents import dumps, with_drives
    from mazegen.runtime.reports import render_file

    made, targets = [], dict[Path, Path]()
    for floor, row in zip(floors, drives):
        target = out / subfolders[floor.source] / floor.source.name
        if target in targets:
            raise MazeError(
                f"{printable(str(floor.source))} and {printable(str(targets[target]))} would both be written "
                "to this file: drive them into different folders",
                filename=str(target),
            )
        targets[target] = floor.source
        document = with_drives(floor.document, row)
        made.append((target, document, dumps(document, str(target)), floor.base("its picture")))
    for target, document, text, base in made:
        write_atomic(target, text)
        render_file(document, target.with_suffix(".svg"), base=base)
    click.echo(f"wrote {len(floors)} scenarios and their pictures to {printable(str(out))}", err=True)
