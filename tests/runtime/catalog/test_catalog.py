"""The results catalog: what runs store is what queries return; concurrent writers; safe filters."""

from __future__ import annotations

import json
import multiprocessing
import sqlite3
from pathlib import Path
from types import SimpleNamespace

import pytest
from click.testing import CliRunner

import mazegen
from mazegen.cli.main import main
from mazegen.errors import MazeError
from mazegen.runtime.catalog._catalog import Catalog
from mazegen.runtime.catalog._catalog_query import Condition, ScenarioQuery, run_rows, scenario_rows
from tests.conftest import EXAMPLES
from tests.runtime.catalog_writer import write_experiments


@pytest.fixture(scope="module")
def catalogued(tmp_path_factory):
    """Two experiments of two runs each, in one catalog beside their run directories."""
    root = tmp_path_factory.mktemp("runs")
    results = {
        name: mazegen.run(
            EXAMPLES / "factory.maze", seed=seed, runs=2, population=80, generations=3, out_dir=root / name
        )
        for name, seed in (("a", 3), ("b", 4))
    }
    return root / "catalog.sqlite", results


def documents_of(results):
    return [(name, run, d) for name, r in results.items() for run, docs in enumerate(r.best, 1) for d in docs]


def test_runs_and_generations_are_stored_as_run(catalogued):
    path, results = catalogued
    catalog = Catalog.open(path, create=False)
    rows = run_rows(catalog)
    assert [(row["run_dir"].name, row["run"], row["status"]) for row in rows] == [
        ("a", 1, "finished"), ("a", 2, "finished"), ("b", 1, "finished"), ("b", 2, "finished")
    ]  # fmt: skip
    for row in rows:
        stats = results[row["run_dir"].name].runs[row["run"] - 1].stats
        assert row["best"] == max(s.best for s in stats)
        assert row["evaluations"] == sum(s.evaluations for s in stats) and row["generation"] == 3
        assert row["population"] == 80 and row["experiment_status"] == "finished"
    stored = catalog.query("SELECT * FROM generations WHERE run = 2 ORDER BY experiment_id, generation")
    expected = [s for name in ("a", "b") for s in results[name].runs[1].stats]
    assert [(r["evaluations"], r["best"], r["mean"], r["unique_genomes"]) for r in stored] == [
        (s.evaluations, s.best, s.mean, s.unique) for s in expected
    ]
    catalog.close()


def test_scenarios_come_back_sorted_and_filtered(catalogued):
    path, results = catalogued
    catalog = Catalog.open(path, create=False)
    documents = documents_of(results)
    rows = scenario_rows(catalog, ScenarioQuery())
    assert len(rows) == len(documents)
    assert [row["fitness"] for row in rows] == sorted((d["fitness"] for _, _, d in documents), reverse=True)
    for row in rows:
        stored = json.loads(row["path"].read_text())
        assert row["fitness"] == stored["fitness"] and row["elements"] == len(stored["elements"])
        assert row["difficulty"] == stored["metrics"]["difficulty"] and row["drawing"].is_file()

    difficulty = sorted(d["metrics"]["difficulty"] or 0 for _, _, d in documents)[len(documents) // 2]
    elements = sorted(len(d["elements"]) for _, _, d in documents)[len(documents) // 3]
    where = (Condition.parse(f"difficulty >= {difficulty}"), Condition("elements", ">=", elements))
    chosen = scenario_rows(catalog, ScenarioQuery(where, sort="difficulty"))
    expected = [
        d["metrics"]["difficulty"]
        for _, _, d in documents
        if (d["metrics"]["difficulty"] or 0) >= difficulty and len(d["elements"]) >= elements
    ]
    assert 0 < len(chosen) < len(documents)
    assert [row["difficulty"] for row in chosen] == sorted(expected, reverse=True)

    fewest = scenario_rows(
        catalog, ScenarioQuery(sort="elements", ascending=True, limit=3, scenario="factory")
    )
    assert [row["elements"] for row in fewest] == sorted(len(d["elements"]) for _, _, d in documents)[:3]
    assert scenario_rows(catalog, ScenarioQuery(scenario="elsewhere")) == []
    catalog.close()


@pytest.mark.parametrize(
    ("query", "message"),
    [
        (ScenarioQuery(sort="speed"), "unknown sort key 'speed' (known: fitness, elements"),
        (
            ScenarioQuery(sort="fitness; DROP TABLE scenarios"),
            "unknown sort key 'fitness; DROP TABLE scenarios'",
        ),
        (ScenarioQuery((Condition("s.fitness) OR (1", "=", 1.0),)), "unknown condition"),
    ],
)
def test_names_outside_the_whitelist_are_refused(catalogued, query, message):
    catalog = Catalog.open(catalogued[0], create=False)
    with pytest.raises(MazeError, match=message.replace("(", r"\(")):
        scenario_rows(catalog, query)
    assert catalog.query("SELECT count(*) FROM scenarios")[0][0] > 0
    catalog.close()


def test_commands_print_tables_and_paths(catalogued):
    path = catalogued[0]
    runner = CliRunner()
    table = runner.invoke(main, ["runs", "--catalog", str(path)]).output.splitlines()
    assert table[0].split() == ["experiment", "run", "status", "seed", "population", "generations", "best",
                                "evaluations", "seconds"]  # fmt: skip
    assert len(table) == 5
    args = ["scenarios", "--catalog", str(path), "--solvable", "--min-elements", "3", "--sort", "tortuosity"]
    listed = runner.invoke(main, args).output.splitlines()
    assert listed[0].split()[:5] == ["fitness", "elements", "solvable", "difficulty", "tortuosity"]
    paths = runner.invoke(main, [*args, "--paths"]).output.split()
    assert len(paths) == len(listed) - 1 and all(Path(p).is_file() for p in paths)
    assert all(json.loads(Path(p).read_text())["metrics"]["solvable"] for p in paths)
    bad = runner.invoke(main, ["scenarios", "--catalog", str(path), "--where", "difficulty ~ 2"])
    assert bad.exit_code == 1 and bad.stderr.startswith("cannot read condition 'difficulty ~ 2'")


def test_catalog_paths_that_are_not_catalogs(tmp_path):
    (tmp_path / "notes.txt").write_text("hello, not SQLite" * 100)
    sqlite3.connect(tmp_path / "other.sqlite").execute("CREATE TABLE t (x)").connection.close()
    cases = {
        tmp_path / "missing.sqlite": "no catalog here",
        tmp_path / "nowhere" / "c.sqlite": "the catalog's folder does not exist",
        tmp_path: "the catalog path is a folder",
        tmp_path / "notes.txt": "not a MazeGen catalog (file is not a database)",
        tmp_path / "other.sqlite": "not a MazeGen catalog",
    }
    for path, message in cases.items():
        result = CliRunner().invoke(main, ["runs", "--catalog", str(path)])
        assert result.exit_code == 1 and message in result.stderr, (path, result.output)
    with pytest.raises(MazeError, match="not a MazeGen catalog"):
        Catalog.open(tmp_path / "other.sqlite", create=True)


@pytest.mark.parametrize(
    ("damage", "message"),
    [
        ("DROP TABLE metrics", "the catalog is damaged: it has no table 'metrics'"),
        ("DROP TABLE runs", "the catalog is damaged: it has no table 'runs'"),
        ("ALTER TABLE scenarios DROP COLUMN fitness", "the catalog is damaged: no such column: s.fitness"),
        ("ALTER TABLE runs DROP COLUMN best", "the catalog is damaged: no such column: r.best"),
    ],
)
def test_a_damaged_catalog_is_one_line(tmp_path, damage, message):
    path = tmp_path / "catalog.sqlite"
    Catalog.open(path, create=True).close()
    with sqlite3.connect(path) as db:
        db.execute(damage)
    db.close()
    command = "runs" if "runs" in damage else "scenarios"
    result = CliRunner().invoke(main, [command, "--catalog", str(path)])
    assert not isinstance(result.exception, Exception), result.exception
    assert result.exit_code == 1 and result.stderr.splitlines() == [f"{path}: {message}"]


def test_concurrent_writers_lose_nothing(tmp_path):
    path = str(tmp_path / "catalog.sqlite")
    context = multiprocessing.get_context("spawn")
    writers = [context.Process(target=write_experiments, args=(path, writer, 12)) for writer in range(3)]
    for process in writers:
        process.start()
    for process in writers:
        process.join(timeout=120)
        assert process.exitcode == 0
    catalog = Catalog.open(Path(path), create=False)
    assert catalog.query("PRAGMA integrity_check")[0][0] == "ok"
    assert catalog.query("PRAGMA journal_mode")[0][0] == "wal"
    counts = [
        catalog.query(f"SELECT count(*) FROM {table}")[0][0]
        for table in ("experiments", "runs", "generations")
    ]
    assert counts == [36, 72, 360]
    assert len(scenario_rows(catalog, ScenarioQuery((Condition("difficulty", "=", 2.0),)))) == 12 * 2 * 3
    catalog.close()


def test_the_unfinished_runs_of_a_failed_experiment_are_failed_until_it_resumes(tmp_path):
    catalog = Catalog.open(tmp_path / "catalog.sqlite", create=True)
    settings = {"seed": 1, "runs": 3, "population": 10, "generations": 4}
    record = {"scenario": "s", "source": "-", "evolution": settings}
    experiment = catalog.start_experiment(
        run_dir=tmp_path / "x", record=record, sweep=None, executor="serial", resumed=False
    )
    counts = {"evaluations": 10, "mean": 1.0, "median": 1.0, "invalid": 0, "unique": 10, "cache_hits": 0}
    stats = (SimpleNamespace(generation=0, best=1.0, seconds=0.1, **counts),)
    catalog.record_run(experiment, 1, SimpleNamespace(stats=stats), (), tmp_path / "x" / "run-01")  # type: ignore[arg-type]
    catalog.run_stopped(experiment, 2, 3)
    catalog.finish_experiment(experiment, status="failed")

    def run_statuses() -> list[tuple[str, str]]:
        return [(row["experiment_status"], row["status"]) for row in run_rows(catalog)]

    assert run_statuses() == [("failed", "finished"), ("failed", "failed"), ("failed", "failed")]
    catalog.start_experiment(
        run_dir=tmp_path / "x", record=record, sweep=None, executor="serial", resumed=True
    )
    assert run_statuses() == [("running", "finished"), ("running", "pending"), ("running", "pending")]
    catalog.close()
