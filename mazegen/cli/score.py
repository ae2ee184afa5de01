"""``mazegen score SPEC SCENARIO.json``: the fitness of a scenario under a spec."""

from __future__ import annotations

import tempfile
from pathlib import Path

import click

from mazegen.cli.errors import reports_errors


@click.command()
@click.argument("spec", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("scenario", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@reports_errors
def score(spec: Path, scenario: Path) -> None:
    """Print the fitness of SCENARIO under SPEC and each term's value."""
    from mazegen.dsl.loader import load_spec
    from mazegen.generator.build import build
    from mazegen.runtime.problem import Problem
    from mazegen.runtime.progress import QuietReporter, note_first_compile
    from mazegen.runtime.scenario import population_from_document, read_document

    resolved = load_spec(spec)
    document = read_document(scenario)
    note_first_compile(QuietReporter())  # on standard error: the table on standard output stays clean
    with tempfile.TemporaryDirectory(prefix="mazegen-score-") as temp:
        build(resolved, Path(temp))
        problem = Problem.from_build_dir(Path(temp))
        population = population_from_document(resolved, problem.table, document, str(scenario))
        fitness, terms = problem.score(population)
        measured = population.survey.summary(0)
    value = float(fitness[0])
    click.echo(f"fitness\t{value:g}" if value != float("-inf") else "fitness\tinvalid (rejected by the spec)")
    click.echo(f"elements\t{int(population.n_elements[0])}")
    for key, values in terms.items():
        click.echo(f"{key}\t{float(values[0]) + 0.0:g}")  # + 0.0 turns -0.0 into 0.0
    for line in metric_lines(measured, resolved.arena.unit, resolved.arena.cell):
        click.echo(line)


def metric_lines(measured: dict[str, bool | float | None], unit: str, cell: float) -> list[str]:
    """The solvability, coverage and difficulty metrics of a scenario, one tab-separated line each."""
    lines = [
        f"solvable\t{'yes' if measured['solvable'] else 'no'}",
        f"occupied fraction\t{measured['coverage']:.3f}",
    ]
    if not measured["solvable"]:
        return lines
    length = float(measured["path_length"])  # type: ignore[arg-type]
    lines.append(f"path length\t{length:.1f} {unit} ({length / cell:.1f} cells)")
    for key, label, suffix in (
        ("tortuosity", "tortuosity", ""),
        ("path_ratio", "path-length ratio", ""),
        ("clearance", "closest obstacle", f" {unit}"),
        ("visibility", "visibility", f" {unit}"),
        ("dispersion", "dispersion", ""),
        ("dimension", "characteristic dimension", f" {unit}"),
        ("narrowest", "narrowest passage", f" {unit}"),
        ("difficulty", "difficulty", " / 100"),
    ):
        value = measured[key]
        lines.append(f"{label}\t{'n/a' if value is None else format(value, '.3f')}{suffix}")
    return lines
