"""Export formats: one row each, the one table ``mazegen export``, its option checks and the docs read.

A row names its writer as ``module:function``, imported only when a scenario is exported, so that
the command line lists and checks formats without importing the runtime (and numba). A writer is a
function ``writer(floor, options) -> {file name: bytes or str}`` of a
:class:`~mazegen.runtime.exporters._floor.Floor` and its
:class:`~mazegen.runtime.exporters._floor.ExportOptions`. Installed packages add formats under the
``mazegen.exporters`` entry point group (:mod:`mazegen.plugins`); a bundled name is never replaced.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any

from mazegen import plugins
from mazegen.errors import MazeError

OPTIONS = ("scale", "cell")
"""The export options of the command line (``--scale``, ``--cell``) a format may read."""


@dataclass(frozen=True)
class ExportFormat:
    """One export format: its name, the :data:`OPTIONS` it reads (any other given is refused), what
    it writes in one line, its writer as ``module:function``, and the plug-in it comes from, if any."""

    name: str
    options: tuple[str, ...]
    summary: str
    writer: str
    plugin: plugins.Plugin | None = None

    @property
    def described(self) -> str:
        """The format as messages name it: ``export format 'ros'``, or the plug-in and its package."""
        if self.plugin is None:
            return f"export format '{self.name}'"
        return self.plugin.described

    def check_options(self, given: Iterable[str]) -> None:
        """Refuse an option the format does not read (``--cell`` for an SVG).

        Raises:
            MazeError: naming the option and the bundled formats it applies to.
        """
        for option in given:
            if option not in self.options:
                raise MazeError(
                    f"--{option} does not apply to {self.name} exports (only to {', '.join(takers(option))})"
                )

    def load_writer(self) -> Callable[..., Any]:
        """The writer function, imported now.

        Raises:
            MazeError: for a plug-in that fails to import (one line naming it and its package).
        """
        if self.plugin is not None:
            writer: Callable[..., Any] = self.plugin.load()
            return writer
        module, _, function = self.writer.partition(":")
        writer = getattr(importlib.import_module(module), function)
        return writer


BUNDLED: dict[str, ExportFormat] = {
    row.name: row
    for row in (
        ExportFormat(
            "ros",
            options=("scale", "cell"),
            summary="ROS and ROS 2 map_server occupancy map (PGM image + YAML)",
            writer="mazegen.runtime.exporters._ros:ros_files",
        ),
        ExportFormat(
            "gazebo",
            options=("scale",),
            summary="Gazebo world (SDF)",
            writer="mazegen.runtime.exporters._gazebo:gazebo_files",
        ),
        ExportFormat(
            "irsim",
            options=("scale",),
            summary="IR-SIM world (YAML)",
            writer="mazegen.runtime.exporters._irsim:irsim_files",
        ),
        ExportFormat(
            "movingai",
            options=("cell",),
            summary="MovingAI grid benchmark (.map + .scen)",
            writer="mazegen.runtime.exporters._movingai:movingai_files",
        ),
        ExportFormat(
            "json",
            options=(),
            summary="MazeGen's scenario document (JSON)",
            writer="mazegen.runtime.exporters._documents:json_files",
        ),
        ExportFormat(
            "svg",
            options=(),
            summary="the scenario's picture (SVG)",
            writer="mazegen.runtime.exporters._documents:svg_files",
        ),
        ExportFormat(
            "png",
            options=(),
            summary="the scenario's picture (PNG)",
            writer="mazegen.runtime.exporters._documents:png_files",
        ),
    )
}
"""The formats MazeGen ships, by the name ``mazegen export --format`` takes."""


def takers(option: str) -> list[str]:
    """The bundled formats that read ``option``."""
    return [row.name for row in BUNDLED.values() if option in row.options]


def export_format(name: str) -> ExportFormat:
    """The format ``name``: bundled, or one an installed package registers, its writer imported to
    read the options it declares (its attribute ``options``, a tuple of :data:`OPTIONS`; none if absent).

    A plug-in that registers a bundled name is not used; a :class:`~mazegen.errors.MazeNote` says so.

    Raises:
        MazeError: for an unknown name, a plug-in that fails to import, or one that declares options
            other than :data:`OPTIONS`.
    """
    if name in BUNDLED:
        plugins.note_unused("exporters", name, "format")
        return BUNDLED[name]
    plugin = plugins.find("exporters", name)
    if plugin is None:
        raise MazeError(plugins.unknown("exporters", "export format", name, list(BUNDLED)))
    row = ExportFormat(name, (), "", plugin.value, plugin)
    options = getattr(row.load_writer(), "options", ())  # the plug-in's own row: what it reads
    if not (isinstance(options, (tuple, list)) and all(option in OPTIONS for option in options)):
        raise MazeError(
            f"{row.described} declares the options {options!r}, not a tuple of {' or '.join(OPTIONS)}"
        )
    return replace(row, options=tuple(options))
