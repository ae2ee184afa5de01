"""``mazegen check FILE...``: check specs and libraries."""

from __future__ import annotations

import click

from mazegen.dsl.loader import check_file
from mazegen.errors import MazeError
from mazegen.text import printable


@click.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(dir_okay=False))
def check(files: tuple[str, ...]) -> None:
    """Check each FILE and print FILE: OK, or its first error as FILE:LINE:COL: MESSAGE."""
    failed = False
    for name in files:
        try:
            check_file(name)
        except MazeError as error:
            click.echo(error.render(command_line=True), err=True)
            failed = True
        else:
            click.echo(f"{printable(name)}: OK")
    if failed:
        raise SystemExit(1)
