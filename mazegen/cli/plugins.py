"""``mazegen plugins``: every controller, metric, export format and library, bundled or registered.

Registered plug-ins are listed as installed packages name them, without importing any: a broken
plug-in is listed too, and fails only where it is used. Nothing here imports the runtime.
"""

from __future__ import annotations

import json
from typing import Any

import click

from mazegen.cli.errors import reports_errors
from mazegen.plugins import GROUPS, installed

COLUMNS = (("kind", "kind"), ("name", "name"), ("value", "value"), ("origin", "origin"))


def _bundled(kind: str) -> dict[str, str | None]:
    """The bundled ones of ``kind`` by name, each with what it names where that is a file or a writer."""
    if kind == "controllers":
        from mazegen.controllers import BUNDLED as CONTROLLERS

        return dict.fromkeys(CONTROLLERS)
    if kind == "metrics":
        from mazegen.spec import PATH_METRICS

        return dict.fromkeys(PATH_METRICS)
    if kind == "exporters":
        from mazegen.export_formats import BUNDLED as FORMATS

        return {name: row.writer for name, row in FORMATS.items()}
    from mazegen.dsl.loader import LIBRARY_DIR, bundled_libraries

    return {name: str(LIBRARY_DIR / f"{name}.maze") for name in bundled_libraries()}


def plugin_rows() -> list[dict[str, Any]]:
    """One row per bundled or registered controller, metric, export format and library, by kind."""
    rows: list[dict[str, Any]] = []
    for kind in GROUPS:
        rows += [
            {"kind": kind, "name": name, "value": value, "origin": "bundled", "bundled": True}
            for name, value in _bundled(kind).items()
        ]
        rows += [
            {"kind": kind, "name": p.name, "value": p.value, "origin": p.origin, "bundled": False}
            for p in installed(kind)
        ]
    return rows


@click.command()
@click.option("--json", "as_json", is_flag=True, help="One JSON object per line: kind, name, value, origin.")
@reports_errors
def plugins(as_json: bool) -> None:
    """List the controllers, metrics, export formats and libraries: bundled, and those installed
    packages register (mazegen.controllers, .metrics, .exporters, .libraries entry points)."""
    rows = plugin_rows()
    if as_json:
        for row in rows:
            click.echo(json.dumps(row))
        return
    from mazegen.cli.table import text_table

    click.echo(text_table(rows, COLUMNS))
