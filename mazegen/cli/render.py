"""``mazegen render SCENARIO.json -o FILE.svg|FILE.png``."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors


@click.command()
@click.argument("scenario", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("-o", "--out", required=True, type=click.Path(dir_okay=False, path_type=Path),
              help="Picture to write: .svg or .png.")
@reports_errors
def render(scenario: Path, out: Path) -> None:
    """Draw SCENARIO (a scenario JSON file) as SVG or PNG."""
    from mazegen.runtime.render import render_file
    from mazegen.runtime.scenario import read_document

    render_file(read_document(scenario.read_text(encoding="utf-8"), str(scenario)), out)
    click.echo(str(out))
