"""Report pages of the folders ``mazegen report`` reads: a run, a suite, or a sweep.

* A run directory (``experiment.json``): :func:`mazegen.runtime.reports._report.report_html`.
* A suite folder (``archive.json`` and ``scenario-NN.json``, from ``mazegen suite``): the
  spec, the archive's heatmap and every scenario of the suite.
* A sweep folder (run directories side by side, one per cell, and the catalog they share,
  from ``mazegen sweep``; also a ``runs/`` folder of several runs): one page with a table of
  the cells, then a section per cell (what sets it apart, its runs, its fittest scenario
  drawn, every best scenario a linked table row, its fitness and distributions).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mazegen.errors import MazeError
from mazegen.fileio import json_value, read_text
from mazegen.runtime.documents import RunDirectory, SuiteDirectory, read_document
from mazegen.runtime.reports._report import (
    RunContents,
    read_run,
    read_spec,
    report_html,
    run_sections,
    statistic_table,
)
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
from mazegen.runtime.reports._spec_words import SUITE_EVOLUTION, spec_blocks


def folder_report(path: Path, *, links_from: Path) -> str:
    """The report page of a run, suite or sweep folder, its links relative to ``links_from``.

    Raises:
        MazeError: For a folder that is none of these, or a damaged file in it.
    """
    if RunDirectory(path).record.is_file():
        return report_html(read_run(path), links_from=links_from)
    if SuiteDirectory(path).archive.is_file():
        return suite_html(path, links_from=links_from)
    cells = sorted(child for child in path.iterdir() if RunDirectory(child).record.is_file())
    if cells:
        return sweep_html(path, cells, links_from=links_from)
    raise MazeError(
        "not a run, suite or sweep folder (no experiment.json, archive.json or run directories)",
        filename=str(path),
    )


def suite_html(path: Path, *, links_from: Path) -> str:
    """The page of a suite folder: the settings it used, the archive's heatmap, every scenario."""
    suite = SuiteDirectory(path)
    spec = read_spec(suite.spec)
    try:
        archive = json_value(read_text(suite.archive, "archive.json"))
        filled = f"{int(archive['filled'])} archive cells filled"
        settings = [(name, int(value)) for name, value in archive.get("settings", {}).items()]  # older: none
    except (ValueError, KeyError, TypeError, AttributeError):
        raise MazeError("damaged archive.json", filename=str(suite.archive)) from None
    scenarios = [
        Saved(f"scenario {SuiteDirectory.number(file)}", file, read_document(file), spec.arena.base)
        for file in suite.scenario_files()
    ]
    heatmap = suite.heatmap
    sections = [
        f"<h1>MazeGen suite: {e(spec.name)}</h1>",
        f"<p>{len(scenarios)} scenarios, {e(filled)}, from <code>{e(path.name)}</code>.</p>",
        "<h2>Settings</h2>",
        f'<div class="tables">{table(settings, "suite")}</div>' if settings else "",
        spec_html(spec, evolution=SUITE_EVOLUTION),
    ]
    if heatmap.is_file():
        picture = data_uri(heatmap.read_bytes(), "image/png")
        sections += ["<h2>Archive</h2>", f'<img class="chart" alt="archive" src="{picture}">']
    sections += [
        "<h2>Scenarios</h2>",
        scenarios_table(scenarios, links_from) if scenarios else "",
        gallery(scenarios, links_from),
        "<h2>Distinct tests: the scenarios by canonical class</h2>",
        classes_table(scenarios, links_from) if scenarios else "<p>No scenario to classify.</p>",
    ]
    return page(f"MazeGen suite: {spec.name}", sections)


def _words(run: RunContents) -> set[str]:
    """Every setting of a run's spec, as the language writes it."""
    if run.spec is None:
        return set()
    return {f"{head}: {words}" for head, block in spec_blocks(run.spec) for words in block}


def sweep_html(path: Path, cells: list[Path], *, links_from: Path) -> str:
    """One page about a sweep: a table of its cells, then a section per finished cell."""
    runs: list[RunContents] = []
    unfinished = []
    for cell in cells:
        if RunDirectory(cell).stats.is_file():
            runs.append(read_run(cell))
        else:
            unfinished.append(cell.name)
    shared = set.intersection(*(_words(run) for run in runs)) if runs else set()
    head = "<tr><th>cell</th><th>settings</th><th>runs</th><th>best fitness</th><th>mean final best</th></tr>"
    rows, sections = [], []
    for number, run in enumerate(runs, start=1):
        own = sorted(_words(run) - shared)
        final = statistic_table(run, "best")[:, -1]
        final = final[~np.isnan(final)]  # runs with no valid individual at the end
        anchor = f"cell-{number}"
        cells_html = [
            f'<a href="#{anchor}">{e(run.path.name)}</a>',
            e("; ".join(words.split(": ", 1)[1] for words in own) or "-"),
            e(len(run.runs)),
            e(f"{final.max():.4g}" if final.size else "-"),
            e(f"{final.mean():.4g}" if final.size else "-"),
        ]
        rows.append("<tr>" + "".join(f"<td>{cell}</td>" for cell in cells_html) + "</tr>")
        sections += [
            f'<h2 id="{anchor}">{e(run.path.name)}</h2>',
            f"<p>{e('; '.join(own) or 'the shared settings')}</p>",
            *run_sections(run, links_from, level=3, one_drawing=True),
        ]
    firsts: dict[str, RunContents] = {}  # the first cell of each scenario, in cell order
    for run in runs:
        firsts.setdefault(str(run.experiment.get("scenario", run.path.name)), run)
    scenarios = list(firsts)
    summary = [
        f"<h1>MazeGen sweep: {e(path.name)}</h1>",
        f"<p>{len(runs)} finished cells"
        + (f" of the scenario{'s' if len(scenarios) > 1 else ''} {e(', '.join(scenarios))}" if runs else "")
        + (f", unfinished: {e(', '.join(unfinished))}" if unfinished else "")
        + f", from <code>{e(path.name)}</code>.</p>",
        f"<table>{head}{''.join(rows)}</table>",
    ]
    for scenario in scenarios:  # every spec of the sweep, not the first one's alone
        spec = firsts[scenario].spec
        if spec is not None:
            summary += [f"<h2>Settings of the first cell of {e(scenario)}</h2>", spec_html(spec)]
    return page(f"MazeGen sweep: {path.name}", summary + sections)
