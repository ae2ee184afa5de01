"""Scenarios in the formats navigation is tested in, one module per format.

Every format is a function of a :class:`~mazegen.runtime.documents._floor.Floor` and the
:class:`~mazegen.runtime.exporters._floor.ExportOptions` that returns the files it makes, by name;
the same scenario always gives the same bytes. :data:`mazegen.export_formats.BUNDLED` lists them,
one row each. See ``docs/exports.md``.
"""

from typing import TYPE_CHECKING

from mazegen.lazy import lazy_names

if TYPE_CHECKING:
    from mazegen.runtime.exporters._batch import default_out_dir, export_plan, write_files
    from mazegen.runtime.exporters._floor import ExportOptions

__all__ = [
    "ExportOptions",
    "default_out_dir",
    "export_plan",
    "write_files",
]

__getattr__ = lazy_names(
    __name__,
    {
        "_batch": ["default_out_dir", "export_plan", "write_files"],
        "_floor": ["ExportOptions"],
    },
)
