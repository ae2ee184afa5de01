"""Many runs at once: sweeps over settings, and suites that fill a MAP-Elites archive.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.campaigns._suite import SuiteSettings, fill_archive, suite_documents, write_suite
    from mazegen.runtime.campaigns._sweep import MAX_CELLS, Axis, parse_axes, plan_cells, sweep_name

__all__ = [
    "MAX_CELLS",
    "Axis",
    "SuiteSettings",
    "fill_archive",
    "parse_axes",
    "plan_cells",
    "suite_documents",
    "sweep_name",
    "write_suite",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_suite": ["fill_archive", "suite_documents", "SuiteSettings", "write_suite"],
        "_sweep": ["Axis", "MAX_CELLS", "parse_axes", "plan_cells", "sweep_name"],
    },
)
