"""``mazegen classes RUN|SUITE|SCENARIO.json... [--controller C] [--json]``: which floors are the same test.

Each floor's homotopy classes (the ways from start to goal that pass its obstacles on different
sides), the canonical class they make, and the floors grouped by it (and, with ``--controller``, by
each controller's outcome and the class of its trajectory), one representative each. A file that
cannot be read is reported on one line and skipped; the others are classified, and the command
ends with exit status 1.
"""

from __future__ import annotations

import json
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import click

from mazegen.cli.bounds import Bounded, BoundedOption, within
from mazegen.cli.drive import controller_names, controller_option, no_path_line
from mazegen.cli.errors import reports_errors
from mazegen.cli.floors import load_floors, load_spec_file, source_files, sources_and_spec
from mazegen.spec import DETOUR, MAX_CLASSES

if TYPE_CHECKING:
    from mazegen.runtime.documents import Classification


@click.command()
@sources_and_spec
@controller_option
@click.option(
    "--max-classes",
    type=within(1, 64),
    cls=BoundedOption,
    default=MAX_CLASSES,
    show_default=True,
    help="Classes kept per floor and task, the shortest.",
)
@click.option(
    "--detour",
    type=Bounded(float, lambda value: 1.0 <= value <= 10.0, "from 1 to 10"),
    cls=BoundedOption,
    default=DETOUR,
    show_default=True,
    help="Leave out a class whose shortest path is longer than this times the floor's shortest.",
)
@click.option(
    "--json", "as_json", is_flag=True, help="One JSON object: every floor's classes, and the groups."
)
@reports_errors
def classes(
    sources: tuple[Path, ...],
    controllers: tuple[str, ...],
    spec: Path | None,
    max_classes: int,
    detour: float,
    as_json: bool,
) -> None:
    """Find the homotopy classes of each floor of SOURCES (scenario files, run or suite directories,
    folders of them, any mix) and group the floors that are the same test.

    Two floors are the same test when their canonical classes match: the same ways round the same
    obstacles, however different their coordinates. With --controller, the controller's outcome and
    the class of the trajectory it drove must match too. Prints each floor's classes, then each
    group: how many floors, one representative.
    """
    names = controller_names(controllers) if controllers else []
    from mazegen.runtime.compiling import DRIVE_SECONDS, noting_compiles
    from mazegen.runtime.documents import classify

    say = partial(click.echo, err=True)
    floors, failed = load_floors(source_files(sources), load_spec_file(spec), driving=bool(names))
    with noting_compiles(say, "classification", DRIVE_SECONDS):
        found = classify(
            floors,
            names,
            max_classes=max_classes,
            detour=detour,
            no_path=lambda file, batch, task: say(no_path_line(file, batch, task)),
        )
    if (max_classes, detour) == (MAX_CLASSES, DETOUR):  # what the catalog's 'classes' means
        record_in_catalogs({Path(c.file): (c.count, c.signature) for c in found.floors})
    unit = floors[0].spec.arena.unit if floors and floors[0].spec else ""
    if as_json:
        click.echo(json.dumps(classification_record(found, unit), allow_nan=False))
    elif floors:
        click.echo(floor_table(found, unit))
        click.echo()
        click.echo(group_table(found))
    if failed:
        raise SystemExit(1)


def record_in_catalogs(found: dict[Path, tuple[int, str]]) -> None:
    """Record the classes of each best scenario of a run directory in the catalog beside it, if any."""
    from mazegen.runtime.catalog import Catalog, default_catalog

    by_catalog: dict[Path, dict[Path, tuple[int, str]]] = {}
    for path, classes in found.items():
        run_dir = path.parent.parent
        if path.parent.name.startswith("run-") and (run_dir / "experiment.json").is_file():
            catalog = default_catalog(run_dir)
            if catalog.is_file():
                by_catalog.setdefault(catalog, {})[path] = classes
    for catalog, entries in by_catalog.items():
        with Catalog.open(catalog, create=False) as opened:
            opened.record_classes(entries)


def classification_record(found: Classification, unit: str) -> dict:
    """Every floor's classes (and drives' trajectory classes), and the groups, as JSON."""
    floors = []
    for classes, drives in zip(found.floors, found.drives):
        record = classes.record(unit)
        if drives:
            record["drives"] = [
                {
                    "controller": d.controller,
                    "task": d.task,
                    "outcome": d.outcome,
                    "class": classes.trajectory_class(d),
                }
                for d in drives
            ]
        floors.append(record)
    groups = [{"key": g.key, "floors": len(g.files), "representative": g.files[0], "files": list(g.files)}
              for g in found.groups]  # fmt: skip
    return {"floors": floors, "groups": groups}


def floor_table(found: Classification, unit: str) -> str:
    """One row per floor and task: its classes, canonical class, the shortest path's class and length."""
    from mazegen.cli.table import text_table

    rows = []
    for classes in found.floors:
        for task, top in classes.tasks:
            first = top.classes[0] if top.classes else None
            rows.append(
                {
                    "file": classes.file,
                    "task": task,
                    "classes": len(top.classes),
                    "signature": top.signature,
                    "shortest": None if first is None else first.signature or "-",
                    "length": None if first is None else round(first.length, 1),
                    "narrowest": None
                    if first is None or first.narrowest == float("inf")
                    else round(first.narrowest, 1),
                }
            )
    columns = [
        ("file", "file"),
        *([("task", "task")] if any(row["task"] is not None for row in rows) else []),
        ("classes", "classes"),
        ("signature", "canonical class"),
        ("shortest", "shortest's class"),
        ("length", f"its length {unit}".strip()),
        ("narrowest", f"its narrowest gap {unit}".strip()),
    ]
    return text_table(rows, columns)


def group_table(found: Classification) -> str:
    """One row per group of equivalent floors: how many, one representative, what they share."""
    from mazegen.cli.table import text_table

    total = len(found.floors)
    rows = [{"floors": len(g.files), "representative": g.files[0], "key": g.key} for g in found.groups]
    table = text_table(
        rows, [("floors", "floors"), ("representative", "representative"), ("key", "same test")]
    )
    return f"{len(found.groups)} distinct tests among {total} floor{'s' * (total != 1)}\n{table}"
