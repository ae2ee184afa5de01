"""``mazegen report RUN_DIR [-o report.html]``: one HTML page about a run."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors
from mazegen.errors import MazeError


@click.command()
@click.argument("run_dir", type=click.Path(exists=True, file_okay=False, path_type=Path))
@click.option(
    "-o",
    "--out",
    type=click.Path(dir_okay=False, path_type=Path),
    help="HTML file to write (default RUN_DIR/report.html).",
)
@click.option("--force", is_flag=True, help="Replace an existing report.")
@reports_errors
def report(run_dir: Path, out: Path | None, force: bool) -> None:
    """Write a self-contained HTML report of RUN_DIR: settings, gallery, fitness, distributions."""
    from mazegen.fileio import write_atomic
    from mazegen.runtime.report import read_run, report_html

    target = out or run_dir / "report.html"
    if target.exists() and not force:
        raise MazeError(
            "already exists (use --force to replace it, or -o to choose another)", filename=str(target)
        )
    page = report_html(read_run(run_dir))
    try:
        write_atomic(target, page)
    except OSError as error:
        raise MazeError(f"cannot write: {error.strerror or error}", filename=str(target)) from None
    click.echo(f"wrote {target}")
