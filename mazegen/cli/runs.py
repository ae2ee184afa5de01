"""``mazegen runs``: the runs a results catalog knows, with their settings and outcome."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors

DEFAULT_CATALOG = Path("runs") / "catalog.sqlite"
"""Where ``mazegen run`` puts the catalog with its default run directories."""

COLUMNS = (
    ("run_dir", "experiment"),
    ("run", "run"),
    ("status", "status"),
    ("seed", "seed"),
    ("population", "population"),
    ("generations", "generations"),
    ("best", "best"),
    ("evaluations", "evaluations"),
    ("seconds", "seconds"),
)


catalog_option = click.option(
    "--catalog",
    type=click.Path(path_type=Path),
    default=DEFAULT_CATALOG,
    show_default=True,
    help="The results catalog.",
)
"""The ``--catalog`` option of the commands that read a catalog."""


@click.command()
@catalog_option
@click.option("--scenario", help="Only runs of this scenario.")
@reports_errors
def runs(catalog: Path, scenario: str | None) -> None:
    """List every run of the catalog: experiment directory, status, settings, best fitness, time."""
    from mazegen.cli.table import text_table
    from mazegen.runtime.catalog import Catalog, run_rows

    with Catalog.open(catalog, create=False) as opened:
        rows = run_rows(opened, scenario=scenario)
    if not rows:
        click.echo("no runs in the catalog", err=True)
        return
    click.echo(text_table(rows, COLUMNS))
