"""Questions to the results catalog: the runs, and the saved scenarios filtered and sorted.

Users name what to filter and sort by (``difficulty>=20``, ``--sort tortuosity``), and
no name they type reaches the SQL text: a name is either one of the fixed columns of
:data:`COLUMNS` or a metric, whose name is passed as a bound parameter; values are
always bound parameters.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

from mazegen.errors import MazeError
from mazegen.runtime.catalog._catalog import Catalog
from mazegen.spec import PATH_METRICS

COLUMNS = {
    "fitness": "s.fitness",
    "elements": "s.elements",
    "run": "s.run",
    "rank": "s.rank",
    "seed": "e.seed",
    "population": "e.population",
    "generations": "e.generations",
}
"""Sort and filter keys that are columns of the scenarios and experiments tables."""

KNOWN_METRICS = ("solvable", "difficulty", "coverage", *PATH_METRICS)
"""Metrics scenario documents carry; others found in a catalog are accepted too."""

_METRIC = "(SELECT m.value FROM metrics m WHERE m.scenario_id = s.id AND m.name = ?)"
_CONDITION = re.compile(r"\s*([A-Za-z_]\w*)\s*(<=|>=|!=|==|=|<|>)\s*(\S+)\s*")
_BOOLEANS = {"true": 1.0, "yes": 1.0, "false": 0.0, "no": 0.0}


@dataclass(frozen=True)
class Condition:
    """``name operator value``, as in ``difficulty>=20`` or ``solvable=true``."""

    name: str
    operator: str
    value: float

    @classmethod
    def parse(cls, text: str) -> Condition:
        """Read a condition; a one-line error for anything else."""
        match = _CONDITION.fullmatch(text)
        if match is None:
            raise MazeError(f"cannot read condition '{text}' (write NAME OP VALUE, e.g. difficulty>=20)")
        name, operator, raw = match.groups()
        try:
            value = _BOOLEANS[raw.lower()] if raw.lower() in _BOOLEANS else float(raw)
        except ValueError:
            raise MazeError(f"condition '{text}': '{raw}' is not a number") from None
        if not math.isfinite(value):
            raise MazeError(f"condition '{text}': '{raw}' is not a finite number")
        return cls(name, "=" if operator == "==" else operator, value)


@dataclass(frozen=True)
class ScenarioQuery:
    """Which saved scenarios to list, and in which order.

    Attributes:
        conditions: All must hold.
        scenario: Only scenarios of this spec's scenario name.
        sort: Column or metric to sort by.
        ascending: Smallest first (default: largest first); missing values always last.
        limit: At most this many rows.
    """

    conditions: tuple[Condition, ...] = ()
    scenario: str | None = None
    sort: str = "fitness"
    ascending: bool = False
    limit: int | None = None


def _expression(name: str, metrics: set[str], what: str) -> tuple[str, tuple[Any, ...]]:
    if name in COLUMNS:
        return COLUMNS[name], ()
    if name in metrics:
        return _METRIC, (name,)
    known = ", ".join([*COLUMNS, *sorted(metrics)])
    raise MazeError(f"unknown {what} '{name}' (known: {known})")


def scenario_rows(catalog: Catalog, query: ScenarioQuery) -> list[dict[str, Any]]:
    """The saved scenarios that match ``query``, as dicts with their file paths resolved.

    Raises:
        MazeError: for a sort key or condition name that is neither a column nor a metric.
    """
    metrics = set(KNOWN_METRICS) | {row[0] for row in catalog.query("SELECT DISTINCT name FROM metrics")}
    clauses, parameters = ["1 = 1"], []
    for condition in query.conditions:
        expression, bound = _expression(condition.name, metrics, "condition")
        clauses.append(f"{expression} {condition.operator} ?")
        parameters += [*bound, condition.value]
    if query.scenario is not None:
        clauses.append("e.scenario = ?")
        parameters.append(query.scenario)
    order, order_bound = _expression(query.sort, metrics, "sort key")
    direction = "ASC" if query.ascending else "DESC"
    sql = (
        f"SELECT e.scenario, e.run_dir, s.run, s.rank, s.fitness, s.elements, s.path, s.drawing, "
        f"{_METRIC} AS solvable, {_METRIC} AS difficulty, {order} AS sort_value "
        f"FROM scenarios s JOIN experiments e ON e.id = s.experiment_id "
        f"WHERE {' AND '.join(clauses)} "
        f"ORDER BY sort_value IS NULL, sort_value {direction}, e.run_dir, s.run, s.rank"
    )
    bound = ("solvable", "difficulty", *order_bound, *parameters)
    if query.limit is not None:
        sql += " LIMIT ?"
        bound = (*bound, query.limit)
    rows = []
    for row in catalog.query(sql, bound):
        item = dict(row)
        item["path"], item["drawing"] = catalog.resolve(row["path"]), catalog.resolve(row["drawing"])
        item["run_dir"] = catalog.resolve(row["run_dir"])
        rows.append(item)
    return rows


def run_rows(catalog: Catalog, *, scenario: str | None = None) -> list[dict[str, Any]]:
    """Every run the catalog knows, oldest experiment first, with its experiment's settings."""
    sql = (
        "SELECT e.run_dir, e.scenario, e.seed, e.population, e.generations, e.sweep, e.executor, "
        "e.status AS experiment_status, r.run, r.status, r.generation, r.best, r.evaluations, r.seconds "
        "FROM runs r JOIN experiments e ON e.id = r.experiment_id "
    )
    parameters: tuple[Any, ...] = ()
    if scenario is not None:
        sql += "WHERE e.scenario = ? "
        parameters = (scenario,)
    sql += "ORDER BY e.started, e.id, r.run"
    rows = []
    for row in catalog.query(sql, parameters):
        item = dict(row)
        item["run_dir"] = catalog.resolve(row["run_dir"])
        rows.append(item)
    return rows
