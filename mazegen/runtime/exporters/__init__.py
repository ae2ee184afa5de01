"""Scenarios in the formats navigation is tested in, one module per format.

Every format is a function of a :class:`~mazegen.runtime.documents.floor.Floor` and
the :class:`~mazegen.runtime.exporters.floor.ExportOptions` that returns the files
it makes, by name; the same scenario always gives the same bytes.
See ``docs/exports.md``.
"""

from __future__ import annotations

from collections.abc import Callable

from mazegen.errors import MazeError
from mazegen.runtime.documents.floor import Floor
from mazegen.runtime.documents.scenario import dumps
from mazegen.runtime.exporters.floor import ExportOptions
from mazegen.runtime.exporters.gazebo import gazebo_files
from mazegen.runtime.exporters.irsim import irsim_files
from mazegen.runtime.exporters.movingai import movingai_files
from mazegen.runtime.exporters.ros import ros_files
from mazegen.runtime.reports.render import scenario_png, scenario_svg

__all__ = ["FORMATS", "ExportOptions", "Files", "Floor"]

Files = dict[str, bytes]
"""Exported files: name (``best-01.pgm``) to content."""


def json_files(floor: Floor, options: ExportOptions) -> Files:
    """``NAME.json``: the scenario document, MazeGen's canonical format."""
    name = f"{floor.name}.json"
    return {name: dumps(floor.document, name).encode("utf-8")}


def svg_files(floor: Floor, options: ExportOptions) -> Files:
    """``NAME.svg``: the drawing of the scenario."""
    return {f"{floor.name}.svg": scenario_svg(floor.document).encode("utf-8")}


def png_files(floor: Floor, options: ExportOptions) -> Files:
    """``NAME.png``: the drawing of the scenario."""
    return {f"{floor.name}.png": scenario_png(floor.document)}


FORMATS: dict[str, Callable[[Floor, ExportOptions], Files]] = {
    "ros": ros_files,
    "gazebo": gazebo_files,
    "irsim": irsim_files,
    "movingai": movingai_files,
    "json": json_files,
    "svg": svg_files,
    "png": png_files,
}
"""Every export format by the name ``mazegen export --format`` takes."""

FORMAT_OPTIONS: dict[str, tuple[str, ...]] = {
    "ros": ("scale", "cell"),
    "gazebo": ("scale",),
    "irsim": ("scale",),
    "movingai": ("cell",),
    "json": (),
    "svg": (),
    "png": (),
}
"""The :class:`ExportOptions` each format reads: any other given is a mistake, not ignored."""


def check_options(fmt: str, options: ExportOptions) -> None:
    """Refuse an option the format ``fmt`` does not read (``--cell`` for an SVG).

    Raises:
        MazeError: Naming the option and the formats it applies to.
    """
    for name in options.given():
        if name not in FORMAT_OPTIONS[fmt]:
            takers = ", ".join(other for other, names in FORMAT_OPTIONS.items() if name in names)
            raise MazeError(f"--{name} does not apply to {fmt} exports (only to {takers})")
