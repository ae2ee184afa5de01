"""``mazegen resume RUN_DIR``: continue an interrupted run directory from its checkpoints."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from mazegen.cli.errors import reports_errors
from mazegen.cli.launching import launch_options, launch_settings, reports_interruption


@click.command()
@click.argument("run_dir", type=click.Path(exists=True, file_okay=False, path_type=Path))
@launch_options
@reports_errors
@reports_interruption
def resume(run_dir: Path, quiet: bool, **options: Any) -> None:
    """Continue RUN_DIR after a kill or Ctrl-C; it ends as if never interrupted.

    Each run goes on from its newest readable checkpoint (a damaged one is reported and
    the one before it used); finished runs are written again, identically.
    """
    from mazegen import api
    from mazegen.errors import MazeError
    from mazegen.runtime.runs import NO_SCENARIO, closing_lines, reporter_for, summary_lines

    reporter = reporter_for(quiet=quiet)
    try:
        outcome = api.resume(run_dir, reporter=reporter, keep_populations=False, **launch_settings(options))
    finally:
        reporter.close()
    for line in [*summary_lines(outcome), *closing_lines(outcome, run_dir)]:
        click.echo(line)
    if not any(outcome.best):
        raise MazeError(NO_SCENARIO)
