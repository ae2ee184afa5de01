"""The scenario as MazeGen itself writes it: its JSON document, and its picture (SVG, PNG)."""

from __future__ import annotations

from mazegen.runtime.documents import Floor, dumps
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.reports import scenario_png, scenario_svg


def json_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.json``: the scenario document, MazeGen's canonical format."""
    name = f"{floor.name}.json"
    return {name: dumps(floor.document, name).encode("utf-8")}


def svg_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.svg``: the drawing of the scenario (with its map's walls)."""
    return {f"{floor.name}.svg": scenario_svg(floor.document, base=floor.base("its picture")).encode("utf-8")}


def png_files(floor: Floor, options: ExportOptions) -> dict[str, bytes]:
    """``NAME.png``: the drawing of the scenario (with its map's walls)."""
    return {f"{floor.name}.png": scenario_png(floor.document, base=floor.base("its picture"))}
