"""``mazegen sweep SPEC... --set NAME=VALUES``: a grid of settings, each cell a set of runs, one catalog."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from mazegen.cli.bounds import BoundedOption, setting
from mazegen.cli.errors import reports_errors
from mazegen.cli.launching import launch_options, launch_settings, reports_interruption
from mazegen.text import printable


@click.command()
@click.argument(
    "specs", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False, path_type=Path)
)
@click.option(
    "--set",
    "axes",
    multiple=True,
    metavar="NAME=VALUES",
    help="A swept setting: population=500,1000  seed=1..3  fitness.overlap=0.25,0.5 (repeatable).",
)
@click.option("--runs", type=setting("runs"), cls=BoundedOption, help="Runs per cell (overrides the specs).")
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Folder of the cells and their catalog (default sweeps/<scenario>+<scenario>..., every spec's).",
)
@click.option("--force", is_flag=True, help="Replace existing cell directories.")
@launch_options
@reports_errors
@reports_interruption
def sweep(
    specs: tuple[Path, ...],
    axes: tuple[str, ...],
    runs: int | None,
    out: Path | None,
    force: bool,
    quiet: bool,
    **options: Any,
) -> None:
    """Run every combination of the --set values for every SPEC (a fitness variant is a spec).

    Each cell writes OUT/<scenario>-<setting><value>...; all cells are recorded in one
    catalog (OUT/catalog.sqlite). Run the same command again to continue: finished cells
    are skipped and interrupted ones resumed.
    """
    from mazegen import api
    from mazegen.errors import MazeError
    from mazegen.runtime.campaigns import parse_axes, sweep_name
    from mazegen.runtime.runs import NO_SCENARIO, reporter_for, summary_lines

    parsed = parse_axes(axes)
    resolved = [api.load(path) for path in specs]
    target = out or Path("sweeps") / sweep_name(resolved)
    reporter = reporter_for(quiet=quiet)
    try:
        cells = api.sweep(
            resolved,
            {axis.name: axis.values for axis in parsed},
            out_dir=target,
            runs=runs,
            force=force,
            reporter=reporter,
            **launch_settings(options),
        )
    finally:
        reporter.close()
    for run_dir, outcome in cells:
        if outcome is None:
            click.echo(f"{printable(run_dir.name)}: finished earlier, skipped")
            continue
        bests = [documents[0]["fitness"] for documents in outcome.best if documents]
        if bests:
            click.echo(f"{printable(run_dir.name)}: {len(outcome.best)} runs, best fitness {max(bests):g}")
            continue
        click.echo(f"{printable(run_dir.name)}: {len(outcome.best)} runs, no valid scenario")
        for line in summary_lines(outcome):  # why, run by run
            click.echo(f"  {line}")
    click.echo(f"wrote {printable(str(target))}")
    ran = [outcome for _, outcome in cells if outcome is not None]
    if ran and not any(any(outcome.best) for outcome in ran):
        raise MazeError(NO_SCENARIO)
