"""The catalog: one SQLite file that records every experiment, run and saved scenario, and
the queries of ``mazegen runs`` and ``mazegen scenarios``.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.catalog.catalog import Catalog, default_catalog
    from mazegen.runtime.catalog.catalog_query import ScenarioQuery, run_rows, scenario_rows

__all__ = ["Catalog", "ScenarioQuery", "default_catalog", "run_rows", "scenario_rows"]

__getattr__ = lazy_names(
    __name__,
    {
        "catalog": ["Catalog", "default_catalog"],
        "catalog_query": ["ScenarioQuery", "run_rows", "scenario_rows"],
    },
)
