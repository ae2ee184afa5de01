"""``mazegen run SPEC|BUILD_DIR``: evolve scenarios and write a run directory."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from mazegen.cli.bounds import BoundedOption, setting
from mazegen.cli.errors import reports_errors
from mazegen.cli.launching import compile_first, launch_options, launch_settings, reports_interruption


@click.command()
@click.argument("source", type=click.Path(exists=True, path_type=Path))
@click.option(
    "--seed", type=setting("seed"), cls=BoundedOption, help="Seed of the experiment (overrides the spec)."
)
@click.option("--runs", type=setting("runs"), cls=BoundedOption, help="Number of runs.")
@click.option("--population", type=setting("population"), cls=BoundedOption, help="Population size.")
@click.option("--generations", type=setting("generations"), cls=BoundedOption, help="Number of generations.")
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Run directory (default runs/<scenario>-seed<seed>).",
)
@click.option("--force", is_flag=True, help="Replace an existing run directory.")
@launch_options
@reports_errors
@reports_interruption
def run(
    source: Path,
    seed: int | None,
    runs: int | None,
    population: int | None,
    generations: int | None,
    out: Path | None,
    force: bool,
    quiet: bool,
    **options: Any,
) -> None:
    """Run the experiment of a .maze SPEC or of a BUILD_DIR made by `mazegen build`.

    Runs spread over the local cores (or a Dask cluster); each checkpoints as it goes, so
    `mazegen resume` continues a run directory that was killed or stopped with Ctrl-C.
    """
    from mazegen import api
    from mazegen.errors import MazeError
    from mazegen.runtime.engine import read_build_spec
    from mazegen.runtime.runs import (
        NO_SCENARIO,
        closing_lines,
        default_run_dir,
        reporter_for,
        summary_lines,
        with_overrides,
    )

    spec = api.load(source) if source.is_file() else read_build_spec(source)
    what = spec if source.is_file() else source  # a spec, or the build directory to run as it is
    overridden = with_overrides(spec, seed=seed, runs=runs, population=population, generations=generations)
    target = out or default_run_dir(overridden)
    reporter = reporter_for(quiet=quiet)
    try:
        compile_seconds = compile_first(what, options["executor"], reporter)
        outcome = api.run(
            what,
            seed=seed,
            runs=runs,
            population=population,
            generations=generations,
            out_dir=target,
            force=force,
            reporter=reporter,
            keep_populations=False,  # the summary needs the best scenarios only
            compile_seconds=compile_seconds,
            **launch_settings(options),
        )
    finally:
        reporter.close()
    for line in [*summary_lines(outcome), *closing_lines(outcome, target)]:
        click.echo(line)
    if not any(outcome.best):
        raise MazeError(NO_SCENARIO)
