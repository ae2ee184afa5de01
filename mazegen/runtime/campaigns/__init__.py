"""Many runs at once: sweeps over settings, and suites that fill a MAP-Elites archive.

See ``docs/architecture.md`` for where this sits among the runtime's rooms.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.campaigns.suite import fill_archive, write_suite
    from mazegen.runtime.campaigns.sweep import plan_cells

__all__ = ["fill_archive", "plan_cells", "write_suite"]

__getattr__ = lazy_names(
    __name__,
    {
        "suite": ["fill_archive", "write_suite"],
        "sweep": ["plan_cells"],
    },
)
