"""Scenarios in the formats navigation is tested in, one module per format.

Every format is a function of a :class:`~mazegen.runtime.documents.floor.Floor` and the
:class:`~mazegen.runtime.exporters.floor.ExportOptions` that returns the files it makes, by name;
the same scenario always gives the same bytes. :data:`mazegen.export_formats.BUNDLED` lists them,
one row each. See ``docs/exports.md``.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.exporters.batch import export_plan, write_files
    from mazegen.runtime.exporters.floor import ExportOptions

__all__ = ["ExportOptions", "export_plan", "write_files"]

__getattr__ = lazy_names(
    __name__,
    {"batch": ["export_plan", "write_files"], "floor": ["ExportOptions"]},
)
