"""``mazegen export SCENARIO.json|RUN_DIR --format FORMAT [-o DIR]``: scenarios for other tools."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors
from mazegen.export_formats import BUNDLED, takers
from mazegen.text import printable


def _applies(option: str) -> str:
    """``ros, movingai: `` for an option's help: the formats that read it, from their rows."""
    return f"{', '.join(takers(option))}: "


@click.command()
@click.argument("source", type=click.Path(exists=True, path_type=Path))
@click.option(
    "-f",
    "--format",
    "fmt",
    required=True,
    metavar="FORMAT",
    help="; ".join(f"{row.name}: {row.summary}" for row in BUNDLED.values())
    + "; or one an installed package registers (mazegen plugins).",
)
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Directory to write into (default exports/FORMAT/ beside the scenario, or in RUN_DIR).",
)
@click.option(
    "--spec",
    type=click.Path(exists=True, dir_okay=False, path_type=Path),
    help="The scenarios' spec, when it is not in their run or suite directory.",
)
@click.option(
    "--cell",
    type=float,
    help=_applies("cell") + "cell size in arena units (default the spec's navigation grid cell).",
)
@click.option(
    "--scale",
    type=float,
    help=_applies("scale") + "metres per arena unit, 1e-06 to 1000 (default from the unit; 1 px = 1 cm).",
)
@click.option("--force", is_flag=True, help="Replace files that exist already.")
@reports_errors
def export(
    source: Path,
    fmt: str,
    out: Path | None,
    spec: Path | None,
    cell: float | None,
    scale: float | None,
    force: bool,
) -> None:
    """Export SOURCE (a scenario JSON file, or every best scenario of a run or suite directory)."""
    from mazegen.export_formats import export_format
    from mazegen.runtime.exporters import ExportOptions, default_out_dir, export_plan, write_files

    options = ExportOptions(scale=scale, cell=cell)  # options and format checked before anything is read
    row = export_format(fmt)
    resolved = None
    if spec is not None:
        from mazegen.dsl.loader import load_spec

        resolved = load_spec(spec)
    target = out or default_out_dir(source, fmt)
    files = export_plan(source, row, target, spec=resolved, options=options)
    write_files(files, force=force)
    click.echo(f"wrote {len(files)} files to {printable(str(target))}")
