"""``mazegen build SPEC``: generate the experiment files."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors
from mazegen.dsl.loader import load_spec
from mazegen.generator.build import build as build_files
from mazegen.text import printable


@click.command()
@click.argument("spec", type=click.Path(dir_okay=False))
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Output directory (default build/<scenario name>).",
)
@reports_errors
def build(spec: str, out: Path | None) -> None:
    """Generate grammar.bnf, fitness.py, experiment.py and spec.json from SPEC."""
    resolved = load_spec(spec)
    target = out or Path("build") / resolved.name
    for path in build_files(resolved, target):
        click.echo(printable(str(path)))
