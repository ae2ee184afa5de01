"""Small map_server maps written for tests: a PGM in P2 and its YAML."""

from __future__ import annotations

from pathlib import Path

import numpy as np

FREE, OCCUPIED, UNKNOWN = 254, 0, 205
"""Pixels of a trinary map as map_saver writes them (negate 0)."""


def write_map(
    folder: Path,
    pixels: np.ndarray,
    *,
    name: str = "hall",
    resolution: float = 0.1,
    origin: tuple[float, float] = (0.0, 0.0),
    negate: int = 0,
) -> Path:
    """Write ``pixels`` (``int[rows, cols]``, top row first, as an image) as ``NAME.pgm`` and ``NAME.yaml``
    in ``folder``; return the YAML's path."""
    rows, cols = pixels.shape
    lines = [" ".join(str(int(v)) for v in row) for row in pixels]
    (folder / f"{name}.pgm").write_text(f"P2\n{cols} {rows}\n255\n" + "\n".join(lines) + "\n")
    yaml = folder / f"{name}.yaml"
    yaml.write_text(
        f"image: {name}.pgm\nmode: trinary\nresolution: {resolution}\n"
        f"origin: [{origin[0]}, {origin[1]}, 0.0]\nnegate: {negate}\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return yaml


def hall_pixels(cols: int = 40, rows: int = 30, *, gap: tuple[int, int] | None = (2, 8)) -> np.ndarray:
    """A hall (top row first): walls around, and a wall across its middle column with a gap of rows
    ``gap`` (counted from the top row; none: closed), free elsewhere."""
    pixels = np.full((rows, cols), FREE)
    pixels[[0, -1], :] = OCCUPIED
    pixels[:, [0, -1]] = OCCUPIED
    pixels[:, cols // 2] = OCCUPIED
    if gap is not None:
        pixels[gap[0] : gap[1], cols // 2] = FREE
    return pixels


def hall_spec(map_name: str = "hall.yaml", *, extra: str = "", elements: int = 6) -> str:
    """A spec of boxes on the hall of :func:`hall_pixels` (400 x 300 cm), start at the left, goal at
    the right, both low: the straight line between them crosses the middle wall."""
    return f"""
element box {{ shape square size 20..40 }}
arena hall {{ map "{map_name}" cm  start (60, 60)  goal (340, 60)  robot radius 15  grid 5 {extra} }}
scenario boxes on hall {{ elements box  max elements {elements} }}
fitness {{ count  solvable required }}
evolution {{ population 60  generations 2  genome 24  seed 3 }}
"""
