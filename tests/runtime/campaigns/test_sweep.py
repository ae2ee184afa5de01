"""Sweeps: settings grids, cell names and specs, and a whole sweep into one catalog, continued when rerun."""

from __future__ import annotations

import dataclasses
import json

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.campaigns._sweep import (
    MAX_CELLS,
    Axis,
    apply_cell,
    cell_name,
    grid,
    parse_axes,
    plan_cells,
    sweep_name,
)
from mazegen.runtime.catalog._catalog import Catalog
from mazegen.runtime.catalog._catalog_query import run_rows
from tests.conftest import EXAMPLES

FACTORY = mazegen.load(EXAMPLES / "factory.maze")


def test_axes_grid_and_cell_names():
    axes = [Axis.parse("population=500,1000"), Axis.parse("seed=1..3"), Axis.parse("fitness.overlap=0.25")]
    assert axes[1].values == (1, 2, 3) and axes[2].values == (0.25,)
    cells = grid(axes)
    assert len(cells) == 6 and cells[0] == {"population": 500, "seed": 1, "fitness.overlap": 0.25}
    assert cells[-1]["population"] == 1000 and cells[-1]["seed"] == 3
    assert cell_name("factory", cells[1]) == "factory-population500-seed2-overlap0.25"


def test_a_cell_changes_the_spec_it_names():
    spec = apply_cell(FACTORY, {"population": 2, "tournament": 2, "fitness.overlap": 2.0})
    assert spec.evolution.population == 2 and spec.evolution.selection == "tournament"
    assert spec.evolution.elitism == 1  # clamped below the population, as mazegen run does
    assert [t.weight for t in spec.fitness if t.key == "overlap"] == [2.0]
    assert FACTORY.fitness != spec.fitness and FACTORY.evolution.population == 1000


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("population", "cannot read --set 'population'"),
        ("speed=1,2", "cannot sweep 'speed' (known: population"),
        ("population=0,10", "--set population: 0 must be from 1 to 1000000"),
        ("mutation=1.5", "--set mutation: 1.5 must be within [0, 1]"),
        ("seed=1..x", "--set seed: '1..x' is not a valid value"),
        ("seed=3..1", "--set seed: empty range '3..1'"),
        ("seed=1,1", "--set seed: a value is given twice"),
        ("seed=1..10001", "--set seed: 1..10001 holds 10001 values; a sweep has at most 10000 cells"),
        ("seed=1..5000,5001..10000,0", "--set seed: more than 10000 values"),
        ("fitness.overlap=1e400", "--set fitness.overlap: inf must be a finite number, at least 0"),
        ("truncation=nan", "--set truncation: nan must be a finite number, within (0, 1]"),
    ],
)
def test_bad_settings_are_one_line_errors(text, message):
    with pytest.raises(MazeError) as error:
        Axis.parse(text)
    assert str(error.value).startswith(message)


def test_unknown_fitness_term():
    with pytest.raises(MazeError, match="spec 'factory' has no fitness term 'size_limit'"):
        apply_cell(FACTORY, {"fitness.size_limit": 1.0})


def test_sweep_command_fills_one_catalog_and_continues_when_rerun(tmp_path):
    out = tmp_path / "sweep"
    args = [
        "sweep",
        str(EXAMPLES / "factory.maze"),
        str(EXAMPLES / "table1" / "exp3.maze"),
        "--set",
        "population=30,40",
        "--set",
        "generations=1",
        "--runs",
        "2",
        "--executor",
        "serial",
        "-q",
        "-o",
        str(out),
    ]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    names = [line.split(":")[0] for line in result.output.splitlines()[:-1]]
    assert names == [
        "factory-population30-generations1",
        "factory-population40-generations1",
        "table1_exp3-population30-generations1",
        "table1_exp3-population40-generations1",
    ]
    for name in names:
        record = json.loads((out / name / "experiment.json").read_text())
        assert record["evolution"]["runs"] == 2 and (out / name / "stats.csv").is_file()
    catalog = Catalog.open(out / "catalog.sqlite", create=False)
    rows = run_rows(catalog)
    assert len(rows) == 8 and {row["status"] for row in rows} == {"finished"}
    assert {json.loads(row["sweep"])["population"] for row in rows} == {30, 40}
    catalog.close()

    (out / names[1] / "stats.csv").unlink()  # as if killed before its end: resumed from its checkpoints
    again = CliRunner().invoke(main, args)
    assert again.exit_code == 0, again.output
    assert again.output.splitlines()[0] == f"{names[0]}: finished earlier, skipped"
    assert again.output.splitlines()[1].startswith(f"{names[1]}: 2 runs, best fitness")
    changed = CliRunner().invoke(main, [*args[:4], "population=30,50", *args[5:]])
    assert changed.exit_code == 0, changed.output  # a new cell beside the old ones
    clash = CliRunner().invoke(main, [*args[:8], "3", *args[9:]])  # --runs 3: same names, other experiments
    assert clash.exit_code == 1 and "holds another experiment (use --force" in clash.stderr


def test_a_sweep_is_named_after_every_spec_it_runs():
    named = [dataclasses.replace(FACTORY, name=name) for name in ("factory", "hall", "factory", "yard")]
    assert sweep_name(named[:1]) == "factory"
    assert sweep_name(named) == "factory+hall+yard"  # a fitness variant of one scenario adds nothing
    many = [dataclasses.replace(FACTORY, name=f"scenario_{n:03d}") for n in range(40)]
    assert sweep_name(many) == "scenario_000+39-more"  # not a name longer than a folder may be


def test_a_setting_is_given_in_one_set():
    with pytest.raises(MazeError, match=r"^--set seed is given twice \(give all its values in one --set\)$"):
        parse_axes(["seed=1,2", "population=10", "seed=3"])
    assert [axis.name for axis in parse_axes(["seed=1,2", "population=10"])] == ["seed", "population"]


def test_cells_are_counted_before_they_are_made(tmp_path):
    axes = [Axis("seed", tuple(range(MAX_CELLS))), Axis("generations", (1, 2))]
    with pytest.raises(MazeError, match=r"^--set: 20000 cells; a sweep has at most 10000 cells$"):
        plan_cells([FACTORY], axes, tmp_path, force=False)
    with pytest.raises(MazeError, match=r"^--set: 2 specs x 10000 cells; a sweep has at most 10000 cells$"):
        plan_cells([FACTORY, FACTORY], axes[:1], tmp_path, force=False)
    assert len(Axis.parse(f"seed=1..{MAX_CELLS}").values) == MAX_CELLS


def test_a_setting_that_changes_nothing_is_refused(tmp_path):
    """The weight of a term that rejects (``solvable required``) is in no fitness: the cells would be one."""
    for values in ((0.0, 1.0), (5.0,)):
        with pytest.raises(MazeError) as error:
            plan_cells(
                [FACTORY], [Axis("seed", (1, 2)), Axis("fitness.solvable", values)], tmp_path, force=False
            )
        assert str(error.value) == (
            f"--set fitness.solvable={values[0]:g} changes nothing in spec 'factory' "
            "(it runs the same experiment as without it)"
        )
    cells = plan_cells([FACTORY], [Axis("fitness.overlap", (0.0, 0.5))], tmp_path, force=False)
    assert [cell.run_dir.name for cell in cells] == ["factory-overlap0", "factory-overlap0.5"]
    same = plan_cells(
        [FACTORY], [Axis("population", (1000, 2000)), Axis("seed", (1, 2))], tmp_path, force=False
    )
    assert (
        len(same) == 4 and same[0].spec == FACTORY
    )  # the spec's own values change nothing, and are no mistake
    needed = [Axis("population", (2000,)), Axis("elitism", (1500,))]  # elitism 1500 needs the population
    assert plan_cells([FACTORY], needed, tmp_path, force=False)[0].spec.evolution.elitism == 1500


def test_two_cells_that_run_one_experiment_are_refused(tmp_path, monkeypatch):
    """Whatever the reason: here an experiment that depends on the sum of the seed and the generations."""
    import mazegen.runtime.campaigns._sweep as sweep

    monkeypatch.setattr(sweep, "_what_runs", lambda spec: spec.evolution.seed + spec.evolution.generations)
    with pytest.raises(MazeError) as error:
        plan_cells([FACTORY], [Axis("seed", (1, 2)), Axis("generations", (2, 1))], tmp_path, force=False)
    assert str(error.value) == (
        "--set seed, generations: cells factory-seed1-generations2 and factory-seed2-generations1 "
        "would run the same experiment"
    )


def test_a_cell_too_large_for_the_genome_is_one_line():
    big = FACTORY.with_evolution(genome=10_000)
    with pytest.raises(MazeError, match=r"^factory-population20000: population x genome must be at most"):
        apply_cell(big, {"population": 20_000})
