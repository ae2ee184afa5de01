"""HTML pieces of the report pages (runs, suites, sweeps): settings, scenario figures, tables.

A figure is a readable drawing of one scenario, linked to its full picture and its
JSON file, with a table of its fitness terms and metrics, a table of its drive when robots
drove it (``mazegen drive -o``), and its phenotype (folded when long). Links are relative to the
folder the page is written into.
"""

from __future__ import annotations

import base64
import html
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mazegen.runtime.reports._render import scenario_svg
from mazegen.runtime.reports._spec_words import block_text, spec_blocks
from mazegen.spec import BaseMap, Spec

THUMBNAIL_PIXELS = 480
"""Longer side of a drawing in a page: its labels stay readable (at least 10 pixels)."""
_FOLD = 80  # phenotypes longer than this many characters are folded
STYLE = """
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1200px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.5em 1.5em 0.5em 0; font-size: 0.9em; vertical-align: top; }
td, th { border: 1px solid #ddd; padding: 0.2em 0.6em; text-align: left; }
th { background: #f3f3f3; } .tables { display: flex; flex-wrap: wrap; align-items: flex-start; gap: 1em; }
pre.spec { background: #f7f7f7; border: 1px solid #ddd; padding: 0.5em 0.8em; margin: 0; font-size: 0.9em; }
.gallery { display: grid; grid-template-columns: repeat(auto-fill, minmax(480px, 1fr)); gap: 1em; }
figure { margin: 0; border: 1px solid #ddd; padding: 0.4em; background: #fafafa; }
figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 0.9em; margin-top: 0.3em; overflow-wrap: anywhere; }
figcaption table { margin: 0.3em 0; font-size: 0.85em; } td.n { text-align: right; }
.chart { max-width: 100%; height: auto; }
"""


@dataclass(frozen=True)
class Saved:
    """A scenario file of a run or suite folder and its document.

    Attributes:
        label: How the page names it: ``run 2, #1`` or ``scenario 05``.
        file: The JSON file; its drawing is the ``.svg`` beside it, when there is one.
        document: The scenario document.
        base: The map the floor is built on, from the folder's spec (None for none).
    """

    label: str
    file: Path
    document: dict[str, Any]
    base: BaseMap | None = None


def e(value: Any) -> str:
    """HTML-escaped text."""
    return html.escape(str(value))


def data_uri(data: bytes, kind: str = "image/svg+xml") -> str:
    return f"data:{kind};base64," + base64.b64encode(data).decode("ascii")


def table(rows: list[tuple[str, Any]], caption: str) -> str:
    body = "".join(f"<tr><th>{e(key)}</th><td>{e(value)}</td></tr>" for key, value in rows)
    return f"<table><caption>{e(caption)}</caption>{body}</table>"


def page(title: str, sections: list[str]) -> str:
    """A whole self-contained page."""
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{e(title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
        + "\n".join(sections)
        + "\n</body>\n</html>\n"
    )


def spec_html(spec: Spec, *, evolution: tuple[str, ...] | None = None) -> str:
    """The spec's arena, scenario, fitness and evolution blocks, written as the language writes them
    (the evolution block with only the settings ``evolution`` names, when given)."""
    blocks = "".join(
        f'<pre class="spec">{e(block_text(head, words))}</pre>'
        for head, words in spec_blocks(spec, evolution=evolution)
    )
    return f'<div class="tables">{blocks}</div>'


def link(target: Path, links_from: Path) -> str:
    """``target`` as a link relative to the folder of the page."""
    return Path(os.path.relpath(target.resolve(), links_from.resolve())).as_posix()


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return f"{value:.4g}"
    return "-" if value is None else str(value)


def metrics_table(document: dict[str, Any]) -> str:
    """The scenario's fitness, each term (as a term) and each metric."""
    rows = [("fitness", _value(document.get("fitness")))]
    terms = document.get("terms") or {}
    rows += [(f"term {name}", _value(value)) for name, value in terms.items()]
    metrics = document.get("metrics") or {}
    rows += [(f"metric {name}", _value(value)) for name, value in metrics.items()]
    body = "".join(f'<tr><th>{e(key)}</th><td class="n">{e(value)}</td></tr>' for key, value in rows)
    return f'<table class="metrics">{body}</table>'


def drive_table(document: dict[str, Any]) -> str:
    """A row per controller that drove the floor: outcome, time, distance, closest approach and BARN's
    score; nothing when the document carries no drive."""
    drive = document.get("drive") or {}
    if not drive:
        return ""
    names = ("controller", "outcome", "time s", "distance", "closest", "score")
    head = "<tr>" + "".join(f"<th>{name}</th>" for name in names) + "</tr>"
    rows = []
    for name, entry in drive.items():
        cells = [e(name), e(entry.get("outcome"))]
        cells += [
            f'<td class="n">{e(_value(entry.get(key)))}</td>'
            for key in ("time", "distance", "clearance", "score")
        ]
        rows.append(f"<tr><td>{cells[0]}</td><td>{cells[1]}</td>{''.join(cells[2:])}</tr>")
    return f'<table class="drive">{head}{"".join(rows)}</table>'


def phenotype_html(phenotype: str | None) -> str:
    """The phenotype in full, folded in a ``<details>`` when long."""
    text = phenotype or ""
    if len(text) <= _FOLD:
        return f"<code>{e(text)}</code>"
    return f"<details><summary>phenotype, {len(text)} characters</summary><code>{e(text)}</code></details>"


def caption(saved: Saved) -> str:
    """One line about a scenario: ``run 1, #1 · fitness 5 · 5 elements · difficulty 12.8``."""
    document = saved.document
    metrics = document.get("metrics") or {}
    fitness = document.get("fitness")
    parts = [
        saved.label,
        f"fitness {_value(fitness)}" if isinstance(fitness, (int, float)) else "no fitness",
        f"{len(document['elements'])} elements",
    ]
    if metrics.get("solvable"):
        parts.append(f"difficulty {metrics.get('difficulty', 0):.1f}")
    elif "solvable" in metrics:
        parts.append("no path")
    return " · ".join(parts)


def file_links(saved: Saved, links_from: Path) -> str:
    """Links to a scenario's full picture (when written) and its JSON file."""
    picture = saved.file.with_suffix(".svg")
    links = [f'<a href="{e(link(picture, links_from))}">picture</a>'] if picture.is_file() else []
    links.append(f'<a href="{e(link(saved.file, links_from))}">JSON</a>')
    return " · ".join(links)


def figure(saved: Saved, links_from: Path) -> str:
    """A scenario's drawing (linked to its full picture), caption, links, metrics and phenotype."""
    text = e(caption(saved))
    drawing = scenario_svg(saved.document, base=saved.base, pixels=THUMBNAIL_PIXELS).encode("utf-8")
    picture = saved.file.with_suffix(".svg")
    target = picture if picture.is_file() else saved.file
    return (
        f'<figure><a href="{e(link(target, links_from))}"><img alt="{text}" src="{data_uri(drawing)}"></a>'
        f"<figcaption>{text} · {file_links(saved, links_from)}{metrics_table(saved.document)}"
        f"{drive_table(saved.document)}"
        f"{phenotype_html(saved.document.get('phenotype'))}</figcaption></figure>"
    )


def gallery(scenarios: list[Saved], links_from: Path) -> str:
    if not scenarios:
        return "<p>No valid scenario was written.</p>"
    return f'<div class="gallery">{"".join(figure(saved, links_from) for saved in scenarios)}</div>'


def scenarios_table(scenarios: list[Saved], links_from: Path) -> str:
    """A row per scenario: fitness, elements, path and difficulty, and links to its files."""
    names = ("scenario", "fitness", "elements", "path", "difficulty", "files")
    head = "<tr>" + "".join(f"<th>{name}</th>" for name in names) + "</tr>"
    rows = []
    for saved in scenarios:
        metrics = saved.document.get("metrics") or {}
        cells = [
            e(saved.label),
            e(_value(saved.document.get("fitness"))),
            e(len(saved.document["elements"])),
            e(_value(metrics.get("solvable"))),
            e(_value(metrics.get("difficulty"))),
            file_links(saved, links_from),
        ]
        rows.append("<tr>" + "".join(f"<td>{cell}</td>" for cell in cells) + "</tr>")
    return f"<table>{head}{''.join(rows)}</table>"
