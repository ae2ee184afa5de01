"""A run directory as one self-contained HTML page.

The page shows the run's settings as the spec writes them, a table of its runs,
the best scenario of each run (a drawing linked to the full picture and the JSON
file, its metrics and its phenotype), a table of every best scenario, the fitness
per generation (best, mean and median; their mean and range across runs when
there are several) and the difficulty and element-count distributions of the best
scenarios. Drawings and charts are inlined as ``data:`` URIs (charts drawn with
matplotlib); the other best scenarios are one table row each, so that a page of
many runs stays small. The same run directory always gives the same page.
"""

from __future__ import annotations

import csv
import io
import math
import warnings
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from mazegen.errors import MazeError
from mazegen.fileio import json_value, read_text
from mazegen.runtime.documents import RunDirectory, read_document
from mazegen.runtime.reports._report_classes import classes_table
from mazegen.runtime.reports._report_html import (
    Saved,
    data_uri,
    e,
    gallery,
    page,
    scenarios_table,
    spec_html,
    table,
)
from mazegen.spec import Spec

STATISTICS = ("best", "mean", "median")
"""The fitness columns of ``stats.csv`` the report plots."""
_COLOURS = {"best": "#1b4f72", "mean": "#b9770e", "median": "#7d3c98"}
_RUN_SECONDS = "seconds: wall-clock time of the run's generations, compiling the kernels included"
"""What the runs table's seconds are (``timing.csv``)."""


@dataclass(frozen=True)
class RunContents:
    """What the report reads from a run directory (laid out as
    :class:`~mazegen.runtime.documents._folders.RunDirectory` says).

    Attributes:
        path: The run directory.
        experiment: ``experiment.json``: settings, seeds and versions.
        spec: ``experiment/spec.json``, or None when absent.
        stats: ``stats.csv``: one dict per run and generation.
        seconds: Wall-clock seconds of each run, when recorded (``stats.csv`` or ``timing.csv``).
        scenarios: ``(run number, scenario)`` of every ``run-NN/best-KK.json``, in run and rank order.
    """

    path: Path
    experiment: dict[str, Any]
    spec: Spec | None
    stats: list[dict[str, str]]
    seconds: dict[int, float]
    scenarios: list[tuple[int, Saved]]

    @property
    def runs(self) -> list[int]:
        """The run numbers of ``stats.csv``, in order."""
        return sorted({int(row["run"]) for row in self.stats})


def _json(path: Path, what: str) -> dict[str, Any]:
    try:
        data = json_value(read_text(path, what))
    except ValueError as error:  # JSONDecodeError among them
        raise MazeError(f"damaged {what}: {getattr(error, 'msg', error)}", filename=str(path)) from None
    if not isinstance(data, dict):
        raise MazeError(f"damaged {what}: not a JSON object", filename=str(path))
    return data


def read_run(path: Path) -> RunContents:
    """Read a run directory written by ``mazegen run``.

    Raises:
        MazeError: For a directory that is not a run directory, or a damaged file in it.
    """
    layout = RunDirectory(path)
    if not layout.record.is_file():
        raise MazeError("not a run directory (no experiment.json)", filename=str(path))
    if not layout.stats.is_file():
        raise MazeError("not a finished run directory (no stats.csv)", filename=str(path))
    experiment = _json(layout.record, "experiment.json")
    wanted = RunDirectory.RECORD_FORMAT
    if experiment.get("format") != wanted:
        raise MazeError(f'not a run record (expected "format": "{wanted}")', filename=str(layout.record))
    spec = read_spec(layout.spec) if layout.spec.is_file() else None
    stats = _rows(layout.stats)
    needed = {"run", "generation", *STATISTICS}
    counted = all(row["run"].isdigit() and row["generation"].isdigit() for row in stats)
    if not stats or not needed <= set(stats[0]) or not counted:
        raise MazeError(
            f"damaged stats.csv (want the columns {', '.join(sorted(needed))})", filename=str(path)
        )
    scenarios = []
    base = spec.arena.base if spec is not None else None
    for file in layout.best_files():
        ranked = RunDirectory.best_rank(file)
        if ranked is not None:
            number, rank = ranked
            scenarios.append((number, Saved(f"run {number}, #{rank}", file, read_document(file), base)))
    return RunContents(path, experiment, spec, stats, _seconds(layout, stats), scenarios)


def read_spec(path: Path) -> Spec:
    """A ``spec.json`` written by ``mazegen build``, ``run`` or ``suite``.

    Raises:
        MazeError: For a damaged file.
    """
    try:
        return Spec.from_json(read_text(path, "spec.json"))
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        raise MazeError(f"damaged spec.json: {error}", filename=str(path)) from None


def _rows(path: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(read_text(path, path.name))))


def _seconds(layout: RunDirectory, stats: list[dict[str, str]]) -> dict[int, float]:
    """Wall-clock seconds of each run: the ``seconds`` of ``stats.csv``, or else of ``timing.csv``."""
    if "seconds" in stats[0]:
        rows = stats
    elif layout.timing.is_file():
        rows = _rows(layout.timing)
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


def statistic_table(run: RunContents, statistic: str) -> np.ndarray:
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


def fitness_chart(run: RunContents) -> bytes:
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
    for counted in (right.xaxis, right.yaxis, left.yaxis):
        # One tick will do: by default a single count (16 elements in every scenario) got 15.6 … 16.4.
        counted.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))
    figure.suptitle(f"{len(documents)} best scenarios")
    figure.tight_layout()
    return _svg_bytes(figure)


def _settings(run: RunContents) -> str:
    record = run.experiment
    versions = sorted(record.get("versions", {}).items())
    rows = [("scenario", record.get("scenario")), ("source", record.get("source")), ("runs", len(run.runs))]
    experiment = table([*rows, *((f"{name} version", version) for name, version in versions)], "experiment")
    spec = (
        spec_html(run.spec) if run.spec is not None else "<p>No experiment/spec.json: settings unknown.</p>"
    )
    return f'<div class="tables">{experiment}</div>{spec}'


def _runs_table(run: RunContents) -> str:
    head = "<tr><th>run</th><th>final best</th><th>final mean</th><th>scenarios</th><th>with a path</th>"
    head += "<th>seconds</th></tr>"
    rows = []
    for number in run.runs:
        stats = [row for row in run.stats if int(row["run"]) == number]
        last = max(stats, key=lambda row: int(row["generation"]))
        documents = [saved.document for n, saved in run.scenarios if n == number]
        solvable = sum(bool(d.get("metrics", {}).get("solvable")) for d in documents)
        best, mean = (_number(last[key]) for key in ("best", "mean"))
        seconds = _duration(run.seconds[number]) if number in run.seconds else "-"
        cells = [number, f"{best:.4g}", f"{mean:.4g}", len(documents), solvable, seconds]
        rows.append("<tr>" + "".join(f"<td>{e(cell)}</td>" for cell in cells) + "</tr>")
    return f"<table><caption>{_RUN_SECONDS}</caption>{head}{''.join(rows)}</table>"


def _duration(seconds: float) -> str:
    """Seconds to three significant digits (a sweep's small runs take milliseconds), whole from 100."""
    return f"{seconds:.0f}" if seconds >= 100 else f"{seconds:.3g}"


def best_of_each_run(run: RunContents) -> list[Saved]:
    """The first-ranked scenario of every run that wrote one."""
    firsts: dict[int, Saved] = {}
    for number, saved in run.scenarios:
        firsts.setdefault(number, saved)
    return list(firsts.values())


def _fitness(saved: Saved) -> float:
    fitness = saved.document.get("fitness")
    return float(fitness) if isinstance(fitness, (int, float)) else -math.inf


def run_sections(
    run: RunContents, links_from: Path, *, level: int = 2, one_drawing: bool = False
) -> list[str]:
    """The runs, the best scenario of each (or, with ``one_drawing``, the fittest of all: a sweep's
    page draws one per cell), every best scenario, fitness and distributions."""
    h = f"h{level}"
    scenarios = [saved for _, saved in run.scenarios]
    documents = [saved.document for saved in scenarios]
    firsts = best_of_each_run(run)
    drawn = [max(firsts, key=_fitness)] if one_drawing and firsts else firsts
    return [
        _runs_table(run),
        f"<{h}>{'Fittest scenario' if one_drawing else 'Best scenario of each run'}</{h}>",
        gallery(drawn, links_from),
        f"<{h}>Every best scenario</{h}>",
        scenarios_table(scenarios, links_from) if scenarios else "<p>No valid scenario was written.</p>",
        f"<{h}>Distinct tests: the best scenarios by canonical class</{h}>",
        classes_table(scenarios, links_from) if scenarios else "<p>No scenario to classify.</p>",
        f"<{h}>Fitness per generation</{h}>",
        f'<img class="chart" alt="fitness per generation" src="{data_uri(fitness_chart(run))}">',
        f"<{h}>Difficulty and elements of the best scenarios</{h}>",
        f'<img class="chart" alt="distributions" src="{data_uri(distribution_chart(documents))}">'
        if documents
        else "<p>No scenario to count.</p>",
    ]


def report_html(run: RunContents, *, links_from: Path | None = None) -> str:
    """The whole report page of a run directory, its links relative to ``links_from`` (default: the run)."""
    name = run.experiment.get("scenario", run.path.name)
    sections = [
        f"<h1>MazeGen run: {e(name)}</h1>",
        f"<p>{len(run.runs)} run(s), {len(run.scenarios)} best scenarios, "
        f"from <code>{e(run.path.name)}</code>.</p>",
        "<h2>Settings</h2>",
        _settings(run),
        *run_sections(run, links_from or run.path),
    ]
    return page(f"MazeGen run: {name}", sections)
