"""A run directory as one self-contained HTML page.

The page shows the run's settings, a gallery of its best scenarios, the fitness
per generation (best, mean and median; their mean and range across runs when
there are several) and the difficulty and element-count distributions of the best
scenarios. Pictures are inlined as ``data:`` URIs, charts are drawn with
matplotlib, and the same run directory always gives the same page.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import warnings
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.runtime.render import scenario_svg
from mazegen.runtime.scenario import read_document

STATISTICS = ("best", "mean", "median")
"""The fitness columns of ``stats.csv`` the report plots."""
_COLOURS = {"best": "#1b4f72", "mean": "#b9770e", "median": "#7d3c98"}
_GALLERY_PIXELS = 360
_STYLE = """
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1200px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.5em 1.5em 0.5em 0; font-size: 0.9em; vertical-align: top; }
td, th { border: 1px solid #ddd; padding: 0.2em 0.6em; text-align: left; }
th { background: #f3f3f3; } .tables { display: flex; flex-wrap: wrap; align-items: flex-start; }
.gallery { display: grid; grid-template-columns: repeat(auto-fill, minmax(290px, 1fr)); gap: 1em; }
figure { margin: 0; border: 1px solid #ddd; padding: 0.4em; background: #fafafa; }
figure img { width: 100%; height: auto; display: block; }
figcaption { font-size: 0.85em; margin-top: 0.3em; overflow-wrap: anywhere; }
.chart { max-width: 100%; height: auto; }
"""


@dataclass(frozen=True)
class RunDirectory:
    """What the report reads from a run directory.

    Attributes:
        path: The run directory.
        experiment: ``experiment.json``: settings, seeds and versions.
        spec: ``experiment/spec.json`` as plain JSON, or None when absent.
        stats: ``stats.csv``: one dict per run and generation.
        seconds: Wall-clock seconds of each run, when recorded (``stats.csv`` or ``timing.csv``).
        scenarios: ``(run number, document)`` of every ``run-NN/best-KK.json``, in run and rank order.
    """

    path: Path
    experiment: dict[str, Any]
    spec: dict[str, Any] | None
    stats: list[dict[str, str]]
    seconds: dict[int, float]
    scenarios: list[tuple[int, dict[str, Any]]]

    @property
    def runs(self) -> list[int]:
        """The run numbers of ``stats.csv``, in order."""
        return sorted({int(row["run"]) for row in self.stats})


def _json(path: Path, what: str) -> dict[str, Any]:
    try:
        data = json.loads(read_text(path, what))
    except json.JSONDecodeError as error:
        raise MazeError(f"damaged {what}: {error.msg}", filename=str(path)) from None
    if not isinstance(data, dict):
        raise MazeError(f"damaged {what}: not a JSON object", filename=str(path))
    return data


def read_run(path: Path) -> RunDirectory:
    """Read a run directory written by ``mazegen run``.

    Raises:
        MazeError: For a directory that is not a run directory, or a damaged file in it.
    """
    if not (path / "experiment.json").is_file():
        raise MazeError("not a run directory (no experiment.json)", filename=str(path))
    if not (path / "stats.csv").is_file():
        raise MazeError("not a finished run directory (no stats.csv)", filename=str(path))
    experiment = _json(path / "experiment.json", "experiment.json")
    if experiment.get("format") != "mazegen-run":
        raise MazeError(
            'not a run record (expected "format": "mazegen-run")', filename=str(path / "experiment.json")
        )
    spec_path = path / "experiment" / "spec.json"
    spec = _json(spec_path, "spec.json") if spec_path.is_file() else None
    stats = _rows(path / "stats.csv")
    needed = {"run", "generation", *STATISTICS}
    counted = all(row["run"].isdigit() and row["generation"].isdigit() for row in stats)
    if not stats or not needed <= set(stats[0]) or not counted:
        raise MazeError(
            f"damaged stats.csv (want the columns {', '.join(sorted(needed))})", filename=str(path)
        )
    scenarios = [
        (int(file.parent.name.removeprefix("run-")), read_document(file))
        for file in sorted(path.glob("run-*/best-*.json"))
        if file.parent.name.removeprefix("run-").isdigit()
    ]
    return RunDirectory(path, experiment, spec, stats, _seconds(path, stats), scenarios)


def _rows(path: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(read_text(path, path.name))))


def _seconds(path: Path, stats: list[dict[str, str]]) -> dict[int, float]:
    """Wall-clock seconds of each run: the ``seconds`` of ``stats.csv``, or else of ``timing.csv``."""
    if "seconds" in stats[0]:
        rows = stats
    elif (path / "timing.csv").is_file():
        rows = _rows(path / "timing.csv")
    else:
        return {}
    totals: dict[int, float] = {}
    for row in rows:
        totals[int(row["run"])] = totals.get(int(row["run"]), 0.0) + _number(row.get("seconds", ""))
    return totals


def _number(text: str) -> float:
    """A ``stats.csv`` cell as a number; empty (no valid individual) is NaN."""
    try:
        return float(text) if text else float("nan")
    except ValueError:
        raise MazeError(f"damaged statistics: {text!r} is not a number") from None


def statistic_table(run: RunDirectory, statistic: str) -> np.ndarray:
    """``float64[runs, generations]`` of one statistic, NaN where a run has no value."""
    runs = run.runs
    generations = 1 + max(int(row["generation"]) for row in run.stats)
    table = np.full((len(runs), generations), np.nan)
    for row in run.stats:
        table[runs.index(int(row["run"])), int(row["generation"])] = _number(row[statistic])
    return table


def _svg_bytes(figure: Figure) -> bytes:
    buffer = io.BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "mazegen-report", "svg.fonttype": "none"}):
        figure.savefig(buffer, format="svg", metadata={"Date": None})
    return buffer.getvalue()


def fitness_chart(run: RunDirectory) -> bytes:
    """SVG chart of best, mean and median fitness per generation (mean and range across runs)."""
    figure = Figure(figsize=(8, 4), dpi=100)
    axes = figure.subplots()
    several = len(run.runs) > 1
    for statistic in STATISTICS:
        table = statistic_table(run, statistic)
        generations = np.arange(table.shape[1])
        with warnings.catch_warnings():  # a generation where no run has a value stays empty
            warnings.simplefilter("ignore", RuntimeWarning)
            centre = np.nanmean(table, axis=0)
            low, high = np.nanmin(table, axis=0), np.nanmax(table, axis=0)
        colour = _COLOURS[statistic]
        axes.plot(generations, centre, color=colour, marker="o", markersize=3, label=statistic)
        if several:
            axes.fill_between(generations, low, high, color=colour, alpha=0.15, linewidth=0)
    axes.set_xlabel("generation")
    axes.set_ylabel("fitness of valid individuals")
    runs = len(run.runs)
    axes.set_title(f"mean of {runs} runs, shaded: range across runs" if several else "one run")
    axes.grid(alpha=0.3)
    axes.legend()
    figure.tight_layout()
    return _svg_bytes(figure)


def distribution_chart(documents: list[dict[str, Any]]) -> bytes:
    """SVG histograms of the difficulty score and the element count of scenarios."""
    figure = Figure(figsize=(8, 3.4), dpi=100)
    left, right = figure.subplots(1, 2)
    scores = [d.get("metrics", {}).get("difficulty") for d in documents]
    scores = [s for s in scores if isinstance(s, (int, float))]
    if scores:
        left.hist(scores, bins=np.arange(0, 105, 5), color=_COLOURS["best"], edgecolor="white")
    else:
        left.text(0.5, 0.5, "no scenario with a path", ha="center", va="center", transform=left.transAxes)
    left.set_xlim(0, 100)
    left.set_xlabel("difficulty score (0 to 100)")
    left.set_ylabel("scenarios")
    counts = Counter(len(d["elements"]) for d in documents)
    right.bar(list(counts), list(counts.values()), width=0.8, color=_COLOURS["median"])
    right.set_xlabel("elements")
    right.set_ylabel("scenarios")
    right.xaxis.get_major_locator().set_params(integer=True)
    right.yaxis.get_major_locator().set_params(integer=True)
    left.yaxis.get_major_locator().set_params(integer=True)
    figure.suptitle(f"{len(documents)} best scenarios")
    figure.tight_layout()
    return _svg_bytes(figure)


def _data_uri(svg: bytes) -> str:
    return "data:image/svg+xml;base64," + base64.b64encode(svg).decode("ascii")


def _e(value: Any) -> str:
    return html.escape(str(value))


def _table(rows: list[tuple[str, Any]], caption: str) -> str:
    body = "".join(f"<tr><th>{_e(key)}</th><td>{_e(value)}</td></tr>" for key, value in rows)
    return f"<table><caption>{_e(caption)}</caption>{body}</table>"


def _settings(run: RunDirectory) -> str:
    record = run.experiment
    tables = [
        _table(
            [
                ("scenario", record.get("scenario")),
                ("source", record.get("source")),
                ("runs", len(run.runs)),
                *(
                    (f"{name} version", version)
                    for name, version in sorted(record.get("versions", {}).items())
                ),
            ],
            "experiment",
        ),
        _table(sorted(record.get("evolution", {}).items()), "evolution"),
    ]
    if run.spec is not None:
        arena = run.spec.get("arena", {})
        unit = arena.get("unit", "")
        rows = [
            ("size", f"{arena.get('width')} x {arena.get('height')} {unit}"),
            ("start", arena.get("start")),
            ("goal", arena.get("goal")),
            ("robot radius", f"{arena.get('robot_radius')} {unit}"),
            ("elements", ", ".join(run.spec.get("scenario", {}).get("elements", []))),
        ]
        rows += [(f"fitness: {term.get('kind')}", _term(term)) for term in run.spec.get("fitness", [])]
        tables.append(_table(rows, f"arena {arena.get('name', '')}"))
    return f'<div class="tables">{"".join(tables)}</div>'


def _term(term: dict[str, Any]) -> str:
    """A fitness term's settings that differ from a plain term: ``weight 0.5, reject``."""
    parts = [] if term.get("weight") == 1.0 else [f"weight {term.get('weight')}"]
    parts += [f"{key} {term[key]}" for key in ("limit", "target", "metric") if term.get(key) is not None]
    return ", ".join(parts + (["reject"] if term.get("reject") else [])) or "-"


def _runs_table(run: RunDirectory) -> str:
    head = "<tr><th>run</th><th>final best</th><th>final mean</th><th>scenarios</th><th>with a path</th>"
    head += "<th>seconds</th></tr>"
    rows = []
    for number in run.runs:
        stats = [row for row in run.stats if int(row["run"]) == number]
        last = max(stats, key=lambda row: int(row["generation"]))
        documents = [d for n, d in run.scenarios if n == number]
        solvable = sum(bool(d.get("metrics", {}).get("solvable")) for d in documents)
        best, mean = (_number(last[key]) for key in ("best", "mean"))
        seconds = f"{run.seconds[number]:.2f}" if number in run.seconds else "-"
        cells = [number, f"{best:.4g}", f"{mean:.4g}", len(documents), solvable, seconds]
        rows.append("<tr>" + "".join(f"<td>{_e(cell)}</td>" for cell in cells) + "</tr>")
    return f"<table>{head}{''.join(rows)}</table>"


def _caption(number: int, document: dict[str, Any]) -> str:
    metrics = document.get("metrics", {})
    rank = document.get("origin", {}).get("rank", "?")
    fitness = document.get("fitness")
    parts = [
        f"run {number}, #{rank}",
        f"fitness {fitness:g}" if isinstance(fitness, (int, float)) else "no fitness",
        f"{len(document['elements'])} elements",
    ]
    if metrics.get("solvable"):
        parts.append(f"difficulty {metrics.get('difficulty', 0):.1f}")
    elif "solvable" in metrics:
        parts.append("no path")
    return " · ".join(parts)


def _gallery(run: RunDirectory) -> str:
    if not run.scenarios:
        return "<p>No valid scenario was written.</p>"
    figures = []
    for number, document in run.scenarios:
        caption, picture = _e(_caption(number, document)), scenario_svg(document, pixels=_GALLERY_PIXELS)
        figures.append(
            f'<figure><img alt="{caption}" src="{_data_uri(picture.encode("utf-8"))}"><figcaption>{caption}'
            f"<br><code>{_e(document.get('phenotype') or '')}</code></figcaption></figure>"
        )
    return f'<div class="gallery">{"".join(figures)}</div>'


def report_html(run: RunDirectory) -> str:
    """The whole report page of a run directory."""
    name = run.experiment.get("scenario", run.path.name)
    documents = [d for _, d in run.scenarios]
    sections = [
        f"<h1>MazeGen run: {_e(name)}</h1>",
        f"<p>{len(run.runs)} run(s), {len(documents)} best scenarios, "
        f"from <code>{_e(run.path.name)}</code>.</p>",
        "<h2>Settings</h2>",
        _settings(run),
        _runs_table(run),
        "<h2>Best scenarios</h2>",
        _gallery(run),
        "<h2>Fitness per generation</h2>",
        f'<img class="chart" alt="fitness per generation" src="{_data_uri(fitness_chart(run))}">',
        "<h2>Difficulty and elements of the best scenarios</h2>",
        f'<img class="chart" alt="distributions" src="{_data_uri(distribution_chart(documents))}">'
        if documents
        else "<p>No scenario to count.</p>",
    ]
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>MazeGen run: {_e(name)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
        + "\n".join(sections)
        + "\n</body>\n</html>\n"
    )
