"""The results catalog: an SQLite file indexing experiments, runs, generations and saved scenarios.

Its schema is documented in ``docs/catalog.md``. One process writes for each experiment:
the launcher, never its workers, so the runs of an experiment never contend. Several
experiments may still write one catalog at once (two ``mazegen run`` commands, a
sweep beside a run): the file is in WAL mode, so readers never block the writer, and
each write is one short ``BEGIN IMMEDIATE`` transaction that waits up to
:data:`BUSY_SECONDS` for another writer's lock instead of failing.
"""

from __future__ import annotations

import json
import os
import sqlite3
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mazegen.errors import MazeError
from mazegen.runtime.documents import RunDirectory

if TYPE_CHECKING:  # the catalog itself needs neither NumPy nor numba
    from mazegen.runtime.engine import RunResult

FILENAME = "catalog.sqlite"
SCHEMA_VERSION = 1
BUSY_SECONDS = 60.0

SCHEMA = """
CREATE TABLE IF NOT EXISTS experiments (
    id INTEGER PRIMARY KEY,
    run_dir TEXT NOT NULL UNIQUE,
    scenario TEXT NOT NULL,
    source TEXT NOT NULL,
    seed INTEGER NOT NULL,
    runs INTEGER NOT NULL,
    population INTEGER NOT NULL,
    generations INTEGER NOT NULL,
    settings TEXT NOT NULL,
    sweep TEXT,
    executor TEXT NOT NULL,
    status TEXT NOT NULL,
    started TEXT NOT NULL,
    finished TEXT
);
CREATE TABLE IF NOT EXISTS runs (
    experiment_id INTEGER NOT NULL REFERENCES experiments(id) ON DELETE CASCADE,
    run INTEGER NOT NULL,
    status TEXT NOT NULL,
    generation INTEGER,
    best REAL,
    evaluations INTEGER,
    seconds REAL,
    PRIMARY KEY (experiment_id, run)
);
CREATE TABLE IF NOT EXISTS generations (
    experiment_id INTEGER NOT NULL REFERENCES experiments(id) ON DELETE CASCADE,
    run INTEGER NOT NULL,
    generation INTEGER NOT NULL,
    evaluations INTEGER NOT NULL,
    best REAL,
    mean REAL,
    median REAL,
    invalid INTEGER NOT NULL,
    unique_genomes INTEGER NOT NULL,
    cache_hits INTEGER NOT NULL,
    seconds REAL NOT NULL,
    PRIMARY KEY (experiment_id, run, generation)
);
CREATE TABLE IF NOT EXISTS scenarios (
    id INTEGER PRIMARY KEY,
    experiment_id INTEGER NOT NULL REFERENCES experiments(id) ON DELETE CASCADE,
    run INTEGER NOT NULL,
    rank INTEGER NOT NULL,
    path TEXT NOT NULL,
    drawing TEXT NOT NULL,
    fitness REAL,
    elements INTEGER NOT NULL,
    valid INTEGER NOT NULL,
    phenotype TEXT,
    terms TEXT NOT NULL,
    UNIQUE (experiment_id, run, rank)
);
CREATE TABLE IF NOT EXISTS metrics (
    scenario_id INTEGER NOT NULL REFERENCES scenarios(id) ON DELETE CASCADE,
    name TEXT NOT NULL,
    value REAL,
    PRIMARY KEY (scenario_id, name)
);
CREATE INDEX IF NOT EXISTS metrics_by_name ON metrics (name, value);
"""
CLASSES = """
CREATE TABLE IF NOT EXISTS classes (
    scenario_id INTEGER PRIMARY KEY REFERENCES scenarios(id) ON DELETE CASCADE,
    signature TEXT NOT NULL
);
"""
"""The canonical homotopy class of each scenario whose classes were found (docs/classes.md): made
when the first are recorded, so that catalogs written before it are still read (and read it)."""
TABLES = ("experiments", "runs", "generations", "scenarios", "metrics")
"""The tables of :data:`SCHEMA`: a catalog without one of them is damaged."""


def default_catalog(run_dir: Path) -> Path:
    """The catalog of a run directory unless told otherwise: beside it, in the folder of runs."""
    return run_dir.parent / FILENAME


def _now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


def task_metrics(document: dict[str, Any]) -> dict[str, float | None]:
    """What the catalog records of a floor of several tasks beside its metrics (theirs together):
    ``tasks``, how many; ``tasks_solvable``, how many have a path; ``difficulty_worst``, the hardest
    one's difficulty (null when one has no path). None for a floor of one task: nothing."""
    tasks = [task.get("metrics") or {} for task in document.get("tasks", ())]
    if not tasks:
        return {}
    scores = [task.get("difficulty") for task in tasks]
    worst = max(float(score) for score in scores if score is not None) if None not in scores else None
    return {
        "tasks": float(len(tasks)),
        "tasks_solvable": float(sum(bool(task.get("solvable")) for task in tasks)),
        "difficulty_worst": worst,
    }


def _number(value: Any) -> float | None:
    """A metric as SQLite stores it: booleans as 0/1, non-finite values as NULL."""
    if isinstance(value, bool):
        return float(value)
    if isinstance(value, (int, float)) and value == value and abs(value) != float("inf"):
        return float(value)
    return None


class Catalog:
    """An open catalog file. Paths in it are relative to its folder, so the folder can move."""

    def __init__(self, connection: sqlite3.Connection, path: Path) -> None:
        self._db = connection
        self.path = path

    @classmethod
    def open(cls, path: Path, *, create: bool) -> Catalog:
        """Open (or, with ``create``, make) the catalog at ``path``.

        Raises:
            MazeError: for a missing file (without ``create``), a missing folder, or a file
                that is not a MazeGen catalog.
        """
        if path.is_dir():
            raise MazeError(
                "the catalog path is a folder (give a file, e.g. catalog.sqlite)", filename=str(path)
            )
        if not path.parent.is_dir():
            raise MazeError("the catalog's folder does not exist", filename=str(path))
        if not create and not path.is_file():
            raise MazeError("no catalog here (runs write one beside their run directory)", filename=str(path))
        existed = path.exists()
        try:
            connection = sqlite3.connect(path, timeout=BUSY_SECONDS, isolation_level=None)
            connection.row_factory = sqlite3.Row
            connection.execute("PRAGMA foreign_keys = ON")
            version = connection.execute("PRAGMA user_version").fetchone()[0]
            if version == 0 and create and _has_tables(connection):
                raise sqlite3.DatabaseError("an SQLite file of something else")
            if version == 0 and create:
                connection.execute("PRAGMA journal_mode = WAL")
                connection.executescript(
                    f"BEGIN IMMEDIATE;{SCHEMA}PRAGMA user_version = {SCHEMA_VERSION};COMMIT;"
                )
            elif version != SCHEMA_VERSION:
                raise sqlite3.DatabaseError(f"schema version {version}, this MazeGen reads {SCHEMA_VERSION}")
            missing = [name for name in TABLES if name not in _table_names(connection)]
        except sqlite3.Error as error:
            if not existed and getattr(error, "sqlite_errorname", "") == "SQLITE_CANTOPEN":
                raise MazeError("cannot write in this folder", filename=str(path.parent)) from None
            raise _disk_error(error, path, "use") or MazeError(
                f"not a MazeGen catalog ({error})", filename=str(path)
            ) from None
        if missing:
            connection.close()
            raise MazeError(f"the catalog is damaged: it has no table '{missing[0]}'", filename=str(path))
        return cls(connection, path)

    def close(self) -> None:
        """Close the file."""
        self._db.close()

    def __enter__(self) -> Catalog:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def relative(self, path: Path) -> str:
        """``path`` as stored: relative to the catalog's folder."""
        return os.path.relpath(path.resolve(), self.path.parent.resolve())

    def resolve(self, stored: str) -> Path:
        """A stored path as a path to open from here."""
        return Path(os.path.normpath(self.path.parent / stored))

    @contextmanager
    def _write(self) -> Iterator[sqlite3.Connection]:
        try:
            with _transaction(self._db, immediate=True):
                yield self._db
        except sqlite3.Error as error:
            raise _disk_error(error, self.path, "write") or error from None

    def start_experiment(
        self,
        *,
        run_dir: Path,
        record: dict[str, Any],
        sweep: dict[str, Any] | None,
        executor: str,
        resumed: bool,
    ) -> int:
        """Record an experiment starting (or resuming) in ``run_dir``; return its id.

        A fresh start replaces whatever the catalog held for that directory (``--force``).
        """
        evolution = record["evolution"]
        key = self.relative(run_dir)
        with self._write() as db:
            row = db.execute("SELECT id FROM experiments WHERE run_dir = ?", (key,)).fetchone()
            if row is not None and resumed:
                db.execute(
                    "UPDATE experiments SET status = 'running', executor = ?, finished = NULL WHERE id = ?",
                    (executor, row["id"]),
                )
                db.execute(  # the runs a failure ended go again
                    "UPDATE runs SET status = 'pending' WHERE experiment_id = ? AND status = 'failed'",
                    (row["id"],),
                )
                return int(row["id"])
            if row is not None:
                db.execute("DELETE FROM experiments WHERE id = ?", (row["id"],))
            cursor = db.execute(
                "INSERT INTO experiments (run_dir, scenario, source, seed, runs, population, generations, "
                "settings, sweep, executor, status, started) "
                "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 'running', ?)",
                (
                    key,
                    record["scenario"],
                    record["source"],
                    evolution["seed"],
                    evolution["runs"],
                    evolution["population"],
                    evolution["generations"],
                    json.dumps(evolution, sort_keys=True),
                    None if sweep is None else json.dumps(sweep, sort_keys=True),
                    executor,
                    _now(),
                ),
            )
            experiment = int(cursor.lastrowid or 0)
            db.executemany(
                "INSERT INTO runs (experiment_id, run, status) VALUES (?, ?, 'pending')",
                [(experiment, run) for run in range(1, evolution["runs"] + 1)],
            )
            return experiment

    def record_run(
        self,
        experiment: int,
        run: int,
        result: RunResult,
        documents: tuple[dict[str, Any], ...],
        run_path: Path,
    ) -> None:
        """Record a finished run: its statistics per generation and its saved scenarios."""
        stats = result.stats
        valid = [row.best for row in stats if row.best == row.best]
        with self._write() as db:
            db.execute("DELETE FROM generations WHERE experiment_id = ? AND run = ?", (experiment, run))
            db.execute("DELETE FROM scenarios WHERE experiment_id = ? AND run = ?", (experiment, run))
            db.execute(
                "UPDATE runs SET status = 'finished', generation = ?, best = ?, evaluations = ?, seconds = ? "
                "WHERE experiment_id = ? AND run = ?",
                (
                    stats[-1].generation,
                    max(valid) if valid else None,
                    sum(row.evaluations for row in stats),
                    sum(row.seconds for row in stats),
                    experiment,
                    run,
                ),
            )
            db.executemany(
                "INSERT INTO generations VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                [
                    (experiment, run, row.generation, row.evaluations, _number(row.best), _number(row.mean),
                     _number(row.median), row.invalid, row.unique, row.cache_hits, row.seconds)
                    for row in stats
                ],
            )  # fmt: skip
            for rank, document in enumerate(documents, start=1):
                self._insert_scenario(db, experiment, run, rank, document, run_path)

    def _insert_scenario(
        self,
        db: sqlite3.Connection,
        experiment: int,
        run: int,
        rank: int,
        document: dict[str, Any],
        run_path: Path,
    ) -> None:
        cursor = db.execute(
            "INSERT INTO scenarios (experiment_id, run, rank, path, drawing, fitness, elements, valid, "
            "phenotype, terms) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (
                experiment,
                run,
                rank,
                self.relative(run_path / RunDirectory.best_name(rank, ".json")),
                self.relative(run_path / RunDirectory.best_name(rank, ".svg")),
                document["fitness"],
                len(document["elements"]),
                int(document["valid"]),
                document["phenotype"],
                json.dumps(document["terms"], sort_keys=True),
            ),
        )
        measured = {**document.get("metrics", {}), **task_metrics(document)}
        db.executemany(
            "INSERT INTO metrics VALUES (?, ?, ?)",
            [(cursor.lastrowid, name, _number(value)) for name, value in measured.items()],
        )

    def record_classes(self, found: dict[Path, tuple[int, str]]) -> int:
        """Record each scenario file's number of homotopy classes (the metric ``classes``) and canonical
        class; files the catalog does not hold are left out. Returns how many it holds."""
        held = 0
        with self._write() as db:
            db.execute(CLASSES)
            for path, (count, signature) in found.items():
                row = db.execute("SELECT id FROM scenarios WHERE path = ?", (self.relative(path),)).fetchone()
                if row is None:
                    continue
                db.execute("INSERT OR REPLACE INTO metrics VALUES (?, 'classes', ?)", (row[0], float(count)))
                db.execute("INSERT OR REPLACE INTO classes VALUES (?, ?)", (row[0], signature))
                held += 1
        return held

    def without_metric(self, name: str) -> list[Path]:
        """The files of the scenarios that have no value of metric ``name``."""
        rows = self.query(
            "SELECT path FROM scenarios s WHERE NOT EXISTS "
            "(SELECT 1 FROM metrics m WHERE m.scenario_id = s.id AND m.name = ?) ORDER BY s.id",
            (name,),
        )
        return [self.resolve(row[0]) for row in rows]

    def run_stopped(self, experiment: int, run: int, generation: int | None) -> None:
        """Record a run interrupted after ``generation``."""
        with self._write() as db:
            db.execute(
                "UPDATE runs SET status = 'interrupted', generation = ? WHERE experiment_id = ? AND run = ?",
                (generation, experiment, run),
            )

    def finish_experiment(self, experiment: int, *, status: str) -> None:
        """Record an experiment ``finished``, ``interrupted`` or ``failed``; a failed one's unfinished
        runs are ``failed`` too (its directory may be gone, and nothing will finish them)."""
        with self._write() as db:
            db.execute(
                "UPDATE experiments SET status = ?, finished = ? WHERE id = ?",
                (status, _now() if status == "finished" else None, experiment),
            )
            if status == "failed":
                db.execute(
                    "UPDATE runs SET status = 'failed' WHERE experiment_id = ? AND status != 'finished'",
                    (experiment,),
                )

    def query(self, sql: str, parameters: tuple[Any, ...] = ()) -> list[sqlite3.Row]:
        """Rows of a read-only query (see :mod:`mazegen.runtime.catalog._catalog_query`).

        Raises:
            MazeError: for a catalog whose tables lack what the query reads (edited or damaged).
        """
        try:
            return self._db.execute(sql, parameters).fetchall()
        except sqlite3.DatabaseError as error:
            raise MazeError(f"the catalog is damaged: {error}", filename=str(self.path)) from None


_DISK_ERRORS = ("SQLITE_FULL", "SQLITE_READONLY", "SQLITE_IOERR", "SQLITE_CANTOPEN", "SQLITE_PERM")
"""SQLite's errors of the disk beneath (full, read-only…), not of the file's contents."""


def _disk_error(error: sqlite3.Error, path: Path, doing: str) -> MazeError | None:
    """A one-line error for a catalog its disk refuses (``None`` for an error of its contents)."""
    if not getattr(error, "sqlite_errorname", "").startswith(_DISK_ERRORS):
        return None
    return MazeError(f"cannot {doing} the catalog ({error})", filename=str(path))


def _has_tables(connection: sqlite3.Connection) -> bool:
    return connection.execute("SELECT count(*) FROM sqlite_master").fetchone()[0] > 0


def _table_names(connection: sqlite3.Connection) -> set[str]:
    return {row[0] for row in connection.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}


@contextmanager
def _transaction(connection: sqlite3.Connection, *, immediate: bool = False) -> Iterator[None]:
    """One transaction; ``immediate`` takes the write lock up front (waiting for it), so it never has
    to upgrade a read lock halfway, which SQLite cannot wait for."""
    if immediate:
        connection.execute("BEGIN IMMEDIATE")
    try:
        yield
    except BaseException:
        if connection.in_transaction:
            connection.execute("ROLLBACK")
        raise
    if connection.in_transaction:
        connection.execute("COMMIT")
