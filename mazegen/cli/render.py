"""``mazegen render SCENARIO.json -o FILE.svg|FILE.png [--spec SPEC.maze]``."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors
from mazegen.errors import MazeError
from mazegen.text import printable


@click.command()
@click.argument("scenario", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "-o",
    "--out",
    required=True,
    type=click.Path(dir_okay=False, path_type=Path),
    help="Picture to write: .svg or .png.",
)
@click.option(
    "--spec",
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    help="Recompute the arena and element outlines from this spec (for floors written by hand).",
)
@reports_errors
def render(scenario: Path, out: Path, spec: Path | None) -> None:
    """Draw SCENARIO (a scenario JSON file) as SVG or PNG."""
    from mazegen.runtime.documents import (
        check_complete,
        completed_document,
        has_parts,
        load_floor,
        read_document,
    )
    from mazegen.runtime.reports import render_file

    document = read_document(scenario)
    base = None
    if spec is not None:
        from mazegen.dsl.loader import load_spec

        loaded = load_spec(spec)
        document, base = completed_document(loaded, document, str(scenario)), loaded.arena.base
    elif "arena" not in document or not has_parts(document):
        raise MazeError(
            "the scenario has no arena or no element parts: give --spec SPEC.maze to compute them",
            filename=str(scenario),
        )
    elif "map" in document["arena"]:  # its walls are its spec's, found beside it
        base = load_floor(scenario).base("its picture")
    check_complete(document, str(scenario))
    render_file(document, out, base=base)
    click.echo(printable(str(out)))
