"""``mazegen scenarios``: the saved scenarios of a results catalog, filtered and sorted."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from mazegen.cli.bounds import BoundedOption, within
from mazegen.cli.errors import reports_errors
from mazegen.cli.runs import catalog_option
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.catalog import Catalog

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
        if "classes" in {sort, *(condition.name for condition in parsed)}:
            find_classes(opened)
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


def find_classes(catalog: Catalog) -> None:
    """Find and record the homotopy classes of the catalog's scenarios that have none recorded yet
    (once: the catalog keeps them); a scenario that cannot be read is reported and left without."""
    from functools import partial

    from mazegen.cli.errors import skip_file
    from mazegen.errors import MazeError
    from mazegen.runtime.compiling import DRIVE_SECONDS, noting_compiles
    from mazegen.runtime.documents import floor_classes, load_floor

    missing = catalog.without_metric("classes")
    if not missing:
        return
    say = partial(click.echo, err=True)
    plural = "s" * (len(missing) != 1)
    say(f"finding the homotopy classes of {len(missing)} scenario{plural} (once: the catalog keeps them)")
    found = {}
    with noting_compiles(say, "classification", DRIVE_SECONDS):
        for path in missing:
            try:
                classes = floor_classes(load_floor(path))
            except MazeError as error:
                skip_file(error, alone=False)
                continue
            found[path] = (classes.count, classes.signature)
    catalog.record_classes(found)
