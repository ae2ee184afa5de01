"""``mazegen run SPEC|BUILD_DIR``: evolve scenarios and write a run directory."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.errors import reports_errors


@click.command()
@click.argument("source", type=click.Path(exists=True, path_type=Path))
@click.option("--seed", type=int, help="Seed of the experiment (overrides the spec).")
@click.option("--runs", type=int, help="Number of runs.")
@click.option("--population", type=int, help="Population size.")
@click.option("--generations", type=int, help="Number of generations.")
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Run directory (default runs/<scenario>-seed<seed>).",
)
@click.option("--force", is_flag=True, help="Replace an existing run directory.")
@click.option("-q", "--quiet", is_flag=True, help="No progress bars.")
@reports_errors
def run(
    source: Path,
    seed: int | None,
    runs: int | None,
    population: int | None,
    generations: int | None,
    out: Path | None,
    force: bool,
    quiet: bool,
) -> None:
    """Run the experiment of a .maze SPEC or of a BUILD_DIR made by `mazegen build`."""
    from mazegen import api
    from mazegen.runtime.experiment import summary_lines
    from mazegen.runtime.progress import QuietReporter, RichReporter

    spec = api.load(source) if source.is_file() else None
    name = spec.name if spec is not None else _build_name(source)
    chosen_seed = seed if seed is not None else (spec.evolution.seed if spec is not None else None)
    target = out or Path("runs") / (f"{name}-seed{chosen_seed}" if chosen_seed is not None else name)
    reporter = QuietReporter() if quiet else RichReporter()
    try:
        outcome = api.run(
            spec if spec is not None else source,
            seed=seed,
            runs=runs,
            population=population,
            generations=generations,
            out_dir=target,
            force=force,
            reporter=reporter,
        )
    finally:
        if isinstance(reporter, RichReporter):
            reporter.close()
    for line in summary_lines(outcome):
        click.echo(line)
    click.echo(f"wrote {target}")


def _build_name(build_dir: Path) -> str:
    from mazegen.errors import MazeError
    from mazegen.spec import Spec

    spec_file = build_dir / "spec.json"
    if not spec_file.is_file():
        raise MazeError("not a .maze file nor a build directory (no spec.json)", filename=str(build_dir))
    spec = Spec.from_json(spec_file.read_text(encoding="utf-8"))
    return f"{spec.name}-seed{spec.evolution.seed}"
