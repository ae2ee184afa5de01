"""``mazegen report RUN_DIR|SUITE_DIR|SWEEP_DIR [-o report.html]``: one HTML page about a folder."""

from __future__ import annotations

from functools import partial
from pathlib import Path

import click

from mazegen.cli.errors import reports_errors
from mazegen.errors import MazeError
from mazegen.text import printable


@click.command()
@click.argument("folder", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.option(
    "-o",
    "--out",
    type=click.Path(dir_okay=False, path_type=Path),
    help="HTML file to write (default FOLDER/report.html).",
)
@click.option("--force", is_flag=True, help="Replace an existing report.")
@reports_errors
def report(folder: Path, out: Path | None, force: bool) -> None:
    """Write a self-contained HTML report of FOLDER (a run, suite or sweep folder): settings, the
    best scenarios (linked to their pictures and JSON files), fitness and distributions, and the
    scenarios grouped by canonical homotopy class (the distinct tests they make)."""
    from mazegen.fileio import write_atomic
    from mazegen.runtime.compiling import DRIVE_SECONDS, noting_compiles
    from mazegen.runtime.reports import folder_report

    target = out or folder / "report.html"
    if target.exists() and not force:
        raise MazeError(
            "already exists (use --force to replace it, or -o to choose another)", filename=str(target)
        )
    with noting_compiles(partial(click.echo, err=True), "report", DRIVE_SECONDS):  # the classes' kernels
        page = folder_report(folder, links_from=target.parent)
    try:
        write_atomic(target, page)
    except OSError as error:
        raise MazeError(f"cannot write: {error.strerror or error}", filename=str(target)) from None
    click.echo(f"wrote {printable(str(target))}")
