"""Scenarios in the formats navigation is tested in, one module per format.

Every format is a function of a :class:`~mazegen.runtime.exporters.floor.Floor` and the
:class:`~mazegen.runtime.exporters.floor.ExportOptions` that returns the files it makes, by name;
the same scenario always gives the same bytes. :data:`mazegen.export_formats.BUNDLED` lists them,
one row each. See ``docs/exports.md``.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.exporters.batch import export_plan, write_files
    from mazegen.runtime.exporters.floor import ExportOptions, Floor, load_floor

__all__ = ["ExportOptions", "Floor", "export_plan", "load_floor", "write_files"]

__getattr__ = lazy_names(
    __name__,
    {"batch": ["export_plan", "write_files"], "floor": ["ExportOptions", "Floor", "load_floor"]},
)
