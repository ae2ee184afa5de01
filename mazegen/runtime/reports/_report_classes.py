"""A report's best scenarios grouped into the tests they make: their canonical homotopy classes
(docs/classes.md)."""

from __future__ import annotations

from pathlib import Path

from mazegen.errors import MazeError
from mazegen.runtime.documents import equivalence_groups, floor_classes, load_floor
from mazegen.runtime.reports._report_html import Saved, e, link


def classes_table(scenarios: list[Saved], links_from: Path) -> str:
    """A row per group of scenarios with one canonical class: how many, the class, and the scenarios
    (the first one represents them); a paragraph when none could be classified."""
    found, named = [], {}
    for saved in scenarios:
        try:
            classes = floor_classes(load_floor(saved.file))
        except MazeError:  # a folder without its spec, a file changed since: left out of the table
            continue
        found.append((str(saved.file), classes.signature))
        named[str(saved.file)] = saved
    if not found:
        return "<p>No scenario could be classified.</p>"
    groups = equivalence_groups(found)
    head = "<tr><th>scenarios</th><th>canonical class</th><th>which</th></tr>"
    rows = []
    for group in groups:
        which = ", ".join(
            f'<a href="{e(link(named[file].file, links_from))}">{e(named[file].label)}</a>'
            for file in group.files
        )
        rows.append(
            f"<tr><td>{len(group.files)}</td><td><code>{e(group.key)}</code></td><td>{which}</td></tr>"
        )
    summary = f"<p>{len(groups)} distinct tests among {len(found)} scenarios.</p>"
    return f"{summary}<table>{head}{''.join(rows)}</table>"
