"""``mazegen score SPEC SCENARIO.json|DIR...``: the fitness of scenarios under a spec.

One scenario prints each number on a line of its own; several print a table, one row per
file; ``--json`` prints one object per scenario and line. Each controller of ``--controller``,
or else each the spec names (its robot block's and drive terms'), drives every scenario too.
A file that cannot be read or scored is reported on one line of standard error and skipped;
the others are scored, and the command ends with exit status 1.
"""

from __future__ import annotations

import json
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import click

from mazegen.cli.drive import controller_names, controller_option
from mazegen.cli.errors import reports_errors, skip_file
from mazegen.errors import MazeError
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.documents import Scored


@click.command()
@click.argument("spec", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("scenarios", nargs=-1, required=True, type=click.Path(exists=True, path_type=Path))
@click.option(
    "--json", "as_json", is_flag=True, help="One JSON object per scenario and line: every term and metric."
)
@controller_option
@reports_errors
def score(spec: Path, scenarios: tuple[Path, ...], as_json: bool, controllers: tuple[str, ...]) -> None:
    """Print the fitness of each SCENARIO under SPEC, its terms, solvability and difficulty metrics.

    A folder stands for every scenario file below it (a run directory's best scenarios).
    A scenario whose arena gives a start and goal is scored on them (a note says so when
    they are not the spec's). A file that cannot be scored is reported on one line and
    skipped; the exit status is then 1. Each --controller (default: those the spec names) drives
    each scenario: its outcome, time, distance, closest approach and BARN's score.
    """
    names = controller_names(controllers) if controllers else None
    from mazegen.dsl.loader import load_spec
    from mazegen.runtime.compiling import DRIVE_SECONDS, noting_compiles
    from mazegen.runtime.documents import Scorer, driving_robot, scenario_files, spec_controllers

    resolved = load_spec(spec)
    names = spec_controllers(resolved) if names is None else names
    if names:
        driving_robot(resolved, str(spec))
    files = [file for path in scenarios for file, _ in scenario_files(path, any_folder=True)]
    scored: list[Scored] = []
    failed = False
    say = partial(click.echo, err=True)
    with Scorer.built(resolved) as scorer, noting_compiles(say, "score", DRIVE_SECONDS):
        for path in files:
            try:
                result = scorer.score(path, note=say, controllers=names)
            except MazeError as error:
                skip_file(error, alone=len(files) == 1)
                failed = True
                continue
            if as_json:
                click.echo(json.dumps(result.record(), allow_nan=False))
            scored.append(result)
    if not as_json and len(files) == 1:
        for line in scenario_lines(scored[0], resolved.arena.unit, resolved.arena.cell):
            click.echo(line)
        for drive in scored[0].drives:
            task = "" if drive.task is None else f" (task {printable(drive.task)})"
            click.echo(f"drive {drive.controller}{task}\t{drive.line(resolved.arena.unit)}")
    elif not as_json and scored:
        click.echo(score_table(scored))
    if failed:
        raise SystemExit(1)


def score_table(scored: list[Scored]) -> str:
    """One row per scenario: file, fitness, elements, solvability, difficulty and each term."""
    from mazegen.cli.table import text_table

    keys = list(scored[0].terms)
    rows = [
        {
            "file": result.file,
            "fitness": result.fitness if result.valid else "invalid",
            "elements": result.elements,
            "solvable": "yes" if result.measured["solvable"] else "no",
            "difficulty": result.measured["difficulty"],
            **{f"term {key}": value + 0.0 for key, value in result.terms.items()},
            **{f"drive {drive.controller}": drive.outcome for drive in result.drives if drive.task is None},
        }
        for result in scored
    ]
    columns = [(name, name) for name in ("file", "fitness", "elements", "solvable", "difficulty")]
    columns += [(f"term {key}", f"term {key}") for key in keys]
    columns += [
        (f"drive {drive.controller}", f"drive {drive.controller}")
        for drive in scored[0].drives
        if drive.task is None
    ]
    return text_table(rows, columns, digits=4)


def scenario_lines(result: Scored, unit: str, cell: float) -> list[str]:
    """A scenario's fitness, element count and terms (labelled ``term``), then its metrics, one
    tab-separated line each."""
    lines = [
        f"fitness\t{result.fitness:g}" if result.valid else "fitness\tinvalid (rejected by the spec)",
        f"elements\t{result.elements}",
    ]
    lines += [f"term {key}\t{value + 0.0:g}" for key, value in result.terms.items()]  # + 0.0: no -0
    return lines + metric_lines(result.measured, unit, cell) + task_lines(result, unit)


def task_lines(result: Scored, unit: str) -> list[str]:
    """One line per task of a floor of several: its path's length and difficulty, or no path."""
    lines = []
    for name, measured in result.tasks:
        if not measured["solvable"]:
            lines.append(f"task {printable(name)}\tno path")
            continue
        length, difficulty = measured["path_length"], measured["difficulty"]
        lines.append(f"task {printable(name)}\tpath {length:.1f} {unit}, difficulty {difficulty:.3f} / 100")
    return lines


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
