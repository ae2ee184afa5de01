"""Plain-text tables for listings: aligned columns, numbers to the right, nothing for missing values.

Every cell is made printable (:func:`mazegen.text.printable`): a file name or a controller's name
with a control character would otherwise drive the terminal, or break a row in two.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from mazegen.text import printable


def _text(value: Any, digits: int) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return printable(str(value))


def text_table(rows: Sequence[dict[str, Any]], columns: Sequence[tuple[str, str]], *, digits: int = 6) -> str:
    """``rows`` as lines of aligned columns under a heading; ``columns`` are (key, heading) pairs."""
    headings = [printable(heading) for _, heading in columns]
    cells = [[_text(row.get(key), digits) for key, _ in columns] for row in rows]
    numeric = [all(isinstance(row.get(key), (int, float, type(None))) for row in rows) for key, _ in columns]
    widths = [max([len(heading)] + [len(line[i]) for line in cells]) for i, heading in enumerate(headings)]
    lines = []
    for line in [headings, *cells]:
        padded = [
            text.rjust(width) if right else text.ljust(width)
            for text, width, right in zip(line, widths, numeric)
        ]
        lines.append("  ".join(padded).rstrip())
    return "\n".join(lines)
