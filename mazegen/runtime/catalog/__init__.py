"""The catalog: one SQLite file that records every experiment, run and saved scenario, and
the queries of ``mazegen runs`` and ``mazegen scenarios``.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.catalog._catalog import Catalog, default_catalog
    from mazegen.runtime.catalog._catalog_query import Condition, ScenarioQuery, run_rows, scenario_rows

__all__ = [
    "Catalog",
    "Condition",
    "ScenarioQuery",
    "default_catalog",
    "run_rows",
    "scenario_rows",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_catalog": ["Catalog", "default_catalog"],
        "_catalog_query": ["Condition", "run_rows", "scenario_rows", "ScenarioQuery"],
    },
)
