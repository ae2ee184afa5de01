"""``mazegen fit MEASURED.csv --controller NAME [--params a,b,c] -o ROBOT.maze``: a bundled controller's
parameters fitted to runs measured on a real stack, written as a robot block a spec imports."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from mazegen.cli.bounds import Bounded, BoundedOption, setting, within
from mazegen.cli.errors import reports_errors
from mazegen.cli.table import text_table
from mazegen.errors import MazeError
from mazegen.text import printable

if TYPE_CHECKING:
    from mazegen.runtime.documents import Agreement


AGREEMENT_COLUMNS = [
    ("parameters", "parameters"),
    ("rho", "Spearman rho"),
    ("agreement", "agreement %"),
    ("simulated", "simulated success %"),
    ("measured", "measured success %"),
    ("error", "mean abs error s/m"),
]


def _agreement_row(name: str, agreement: Agreement) -> dict:
    return {
        "parameters": name,
        "rho": agreement.rho,
        "agreement": 100 * agreement.agreement,
        "simulated": 100 * agreement.simulated_success,
        "measured": 100 * agreement.measured_success,
        "error": agreement.error,
    }


@click.command("fit")
@click.argument("measured", type=click.Path(path_type=Path, dir_okay=False))
@click.option("-c", "--controller", required=True, help="The bundled controller to fit.")
@click.option("--params", help="Parameters to fit, comma-separated (default: all but the sample counts).")
@click.option(
    "--folds",
    type=within(1, 20),
    cls=BoundedOption,
    default=5,
    help="Folds of the cross-validation over scenarios, 1 for none (default 5).",
)
@click.option(
    "--budget",
    type=within(1, 100_000),
    cls=BoundedOption,
    default=160,
    help="Drives of every scenario one fit may make (default 160).",
)
@click.option(
    "--seed",
    type=setting("seed"),
    cls=BoundedOption,
    default=1,
    help="Seed of the search and the folds (default 1).",
)
@click.option(
    "--failure-time",
    type=Bounded(float, lambda value: 0 <= value <= 1e9, "from 0 to 1e9 seconds"),
    cls=BoundedOption,
    default=30.0,
    help="Seconds a failed run counts as (default 30, BARN's).",
)
@click.option("-o", "--out", type=click.Path(path_type=Path, dir_okay=False), required=True,
              help="The robot block to write (a .maze file a spec imports).")  # fmt: skip
@click.option("--force", is_flag=True, help="Replace the file if it exists.")
@reports_errors
def fit(
    measured: Path,
    controller: str,
    params: str | None,
    folds: int,
    budget: int,
    seed: int,
    failure_time: float,
    out: Path,
    force: bool,
) -> None:
    """Fit a bundled controller's parameters to measured runs (a CSV of scenario, outcome, time[, length])."""
    from mazegen.runtime.documents import FitProblem, SearchSpace, fit_controller, read_measured, robot_block
    from mazegen.runtime.exporters import write_files

    names = [name.strip() for name in params.split(",") if name.strip()] if params is not None else None
    if names is not None and not names:
        raise MazeError("--params names no parameter")
    space = SearchSpace.of(controller, names)
    runs = read_measured(measured)
    if folds > len(runs):
        raise MazeError(f"--folds {folds} is more than the {len(runs)} scenarios measured")
    problem = FitProblem(runs, controller, failure_time)
    units = sorted({floors.spec.arena.unit for floors in problem.floors})
    if len(units) > 1:
        raise MazeError(
            f"the scenarios' arenas are in {' and '.join(units)}: one robot block sets lengths in one unit"
        )
    if not force and out.exists():
        raise MazeError("already exists (use --force to replace it)", filename=str(out))
    found = fit_controller(problem, space, folds=folds, budget=budget, seed=seed)
    click.echo(
        f"fitted {controller}'s {', '.join(space.names)} to {len(runs)} scenarios "
        f"({sum(len(r.arrived) for r in runs)} measured runs; seed {seed}, {budget} drives a fit)\n"
    )
    rows = [("defaults", found.default), ("fitted, all scenarios", found.result)]
    rows += [(f"fitted on the others, held-out fold {k + 1}", a) for k, a in enumerate(found.held_out)]
    click.echo(text_table([_agreement_row(name, a) for name, a in rows], AGREEMENT_COLUMNS, digits=3))
    click.echo()
    parameters = [
        {"parameter": name, "default": d, "fitted": v}
        for name, d, v in zip(space.names, space.default, found.fitted)
    ]
    click.echo(
        text_table(
            parameters, [("parameter", "parameter"), ("default", "default (SI)"), ("fitted", "fitted (SI)")]
        )
    )
    text = robot_block(controller, space, found.fitted, problem.spec, measured.name)
    write_files({out: text.encode("utf-8")}, force=True)
    click.echo(f"\nwrote {printable(str(out))}")
