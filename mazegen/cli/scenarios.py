"""``mazegen scenarios``: the saved scenarios of a results catalog, filtered and sorted."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.bounds import BoundedOption, within
from mazegen.cli.errors import reports_errors
from mazegen.cli.runs import catalog_option
from mazegen.text import printable

COLUMNS = (
    ("fitness", "fitness"),
    ("elements", "elements"),
    ("solvable", "solvable"),
    ("difficulty", "difficulty"),
    ("scenario", "scenario"),
    ("run", "run"),
    ("rank", "rank"),
    ("path", "path"),
)


@click.command()
@catalog_option
@click.option(
    "--where",
    "conditions",
    multiple=True,
    metavar="NAME OP VALUE",
    help="Keep scenarios where it holds, e.g. 'difficulty>=20' (repeatable; all must hold).",
)
@click.option(
    "--min-elements",
    type=within(0, 1_000_000),
    cls=BoundedOption,
    help="Keep scenarios with at least this many elements.",
)
@click.option("--solvable", is_flag=True, help="Keep solvable scenarios only.")
@click.option("--scenario", help="Only scenarios of this scenario name.")
@click.option(
    "--sort",
    default="fitness",
    show_default=True,
    metavar="KEY",
    help="fitness, elements, run, rank, seed, population, generations, or a metric (difficulty, ...).",
)
@click.option("--ascending", is_flag=True, help="Smallest first (default: largest first).")
@click.option(
    "--limit",
    type=within(1, 2**63 - 1),
    cls=BoundedOption,
    help="At most this many scenarios (SQLite's integers).",
)
@click.option("--paths", is_flag=True, help="Print only the scenario files' paths, one per line.")
@reports_errors
def scenarios(
    catalog: Path,
    conditions: tuple[str, ...],
    min_elements: int | None,
    solvable: bool,
    scenario: str | None,
    sort: str,
    ascending: bool,
    limit: int | None,
    paths: bool,
) -> None:
    """List saved scenarios, best first: a table, or their paths for scripts."""
    from mazegen.cli.table import text_table
    from mazegen.runtime.catalog import Catalog, Condition, ScenarioQuery, scenario_rows

    parsed = [Condition.parse(text) for text in conditions]
    if min_elements is not None:
        parsed.append(Condition("elements", ">=", float(min_elements)))
    if solvable:
        parsed.append(Condition("solvable", "=", 1.0))
    query = ScenarioQuery(tuple(parsed), scenario, sort, ascending, limit)
    with Catalog.open(catalog, create=False) as opened:
        rows = scenario_rows(opened, query)
    if paths:
        for row in rows:
            click.echo(printable(str(row["path"])))  # one line each, whatever the name holds
        return
    if not rows:
        click.echo("no scenario matches", err=True)
        return
    for row in rows:
        row["solvable"] = None if row["solvable"] is None else bool(row["solvable"])
    columns = list(COLUMNS)
    if sort not in dict(COLUMNS):
        columns.insert(4, ("sort_value", sort))  # show what the rows are sorted by
    click.echo(text_table(rows, columns))
