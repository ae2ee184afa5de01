"""``mazegen suite SPEC --size N``: a graded suite of scenarios from a MAP-Elites archive."""

from __future__ import annotations

from pathlib import Path

import click

from mazegen.cli.bounds import BoundedOption, setting, within
from mazegen.cli.errors import reports_errors
from mazegen.cli.launching import compile_first
from mazegen.errors import MazeError
from mazegen.text import printable


@click.command()
@click.argument("spec", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "--size",
    type=within(1, 10_000),
    cls=BoundedOption,
    default=20,
    show_default=True,
    help="Scenarios to write.",
)
@click.option("--seed", type=setting("seed"), cls=BoundedOption, help="Seed (default: the spec's).")
@click.option(
    "--iterations",
    type=setting("generations"),
    cls=BoundedOption,
    help="Batches bred from the archive (default: the spec's generations).",
)
@click.option(
    "--batch",
    type=within(2, 1_000_000),
    cls=BoundedOption,
    help="Scenarios per batch (default: the spec's population).",
)
@click.option(
    "--measure",
    type=click.Choice(["elements", "classes"]),
    default="elements",
    show_default=True,
    help="The archive's second axis: element count, or number of homotopy classes (docs/classes.md).",
)
@click.option(
    "--distinct-classes",
    is_flag=True,
    help="Write one scenario per canonical class: an elite of a class already written gives way.",
)
@click.option(
    "-o",
    "--out",
    type=click.Path(file_okay=False, path_type=Path),
    help="Suite directory (default suites/<scenario>-seed<seed>).",
)
@click.option("--force", is_flag=True, help="Replace an existing suite directory.")
@click.option("-q", "--quiet", is_flag=True, help="No progress bar.")
@reports_errors
def suite(
    spec: Path,
    size: int,
    seed: int | None,
    iterations: int | None,
    batch: int | None,
    measure: str,
    distinct_classes: bool,
    out: Path | None,
    force: bool,
    quiet: bool,
) -> None:
    """Fill a MAP-Elites archive (difficulty x element count, or number of classes), write SIZE scenarios
    spread over it."""
    import tempfile

    from mazegen.dsl.loader import load_spec
    from mazegen.generator.build import build
    from mazegen.runtime.campaigns import SuiteSettings, fill_archive, suite_documents, write_suite
    from mazegen.runtime.engine import Problem
    from mazegen.runtime.runs import reporter_for

    resolved = load_spec(spec)
    settings = resolved.evolution
    if batch is not None:  # a batch is bred as a population: it holds as many codons
        try:
            resolved.with_evolution(population=batch)
        except ValueError as error:
            raise MazeError(f"--batch {batch}: {error}") from None
    seed = settings.seed if seed is None else seed
    iterations = settings.generations if iterations is None else iterations
    batch = settings.population if batch is None else batch
    target = out or Path("suites") / f"{resolved.name}-seed{seed}"
    reporter = reporter_for(quiet=quiet)
    with tempfile.TemporaryDirectory(prefix="mazegen-suite-") as temp:
        build(resolved, Path(temp))
        problem = Problem.from_build_dir(Path(temp))
        try:
            compile_first(problem, "serial", reporter)
            reporter.add_run("suite", "archive", iterations)
            archive = fill_archive(
                problem,
                seed=seed,
                iterations=iterations,
                batch=batch,
                measure=measure,
                on_iteration=lambda stats: reporter.generation("suite", stats),
            )
        finally:
            reporter.close()
        documents = suite_documents(problem, archive, size, seed=seed, distinct=distinct_classes)
        chosen = SuiteSettings(seed=seed, iterations=iterations, batch=batch, size=size)
        write_suite(target, problem, archive, documents, chosen, force=force)
    cells = archive.bins.difficulty * archive.bins.elements
    click.echo(f"archive: {archive.filled.size} of {cells} cells filled")
    if len(documents) < size:
        more = "distinct classes" if distinct_classes else "scenarios"
        click.echo(
            f"only {len(documents)} scenarios: the archive holds no more {more} (try more --iterations)"
        )
    click.echo(f"wrote {len(documents)} scenarios to {printable(str(target))}")
