"""An export format as a plug-in: the floor's layout as a table a plant engineer opens in a spreadsheet."""

from __future__ import annotations

import csv
import io


def layout_csv(floor, options) -> dict[str, bytes]:
    """``NAME.csv``: one row per element, its type, class, centre, size and rotation, in metres."""
    document = floor.document
    scale = floor.metres_per_unit(options)
    out = io.StringIO()
    table = csv.writer(out, lineterminator="\n")
    table.writerow(["type", "class", "x_m", "y_m", "width_m", "depth_m", "rotation_deg"])
    for element in document["elements"]:
        width = element.get("width", element.get("size", 0.0))
        depth = element.get("depth", element.get("size", 0.0))
        row = [element["x"] * scale, element["y"] * scale, width * scale, depth * scale]
        sizes = (f"{value:.3f}" for value in row)
        table.writerow([element["type"], element["class"], *sizes, element["rotation"]])
    return {f"{floor.name}.csv": out.getvalue().encode("utf-8")}


layout_csv.options = ("scale",)  # type: ignore[attr-defined]  # the export options it reads
