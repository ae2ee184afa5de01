"""Write hall.pgm and hall.yaml: the warehouse hall examples/warehouse.maze is built on, as a SLAM
map of it would look (map_server's trinary PGM, 0.1 m cells, unknown beyond the outer walls).

    python examples/maps/make_hall.py      # rewrites the two files beside this script, byte for byte

The hall is 30 m x 20 m inside walls 0.3 m thick: two rows of pillars, an office in the top-left
corner with its door on the hall, and a partition fencing off the charging corner.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

CELL = 0.1
"""Metres per cell."""
FREE, OCCUPIED, UNKNOWN = 254, 0, 205
MARGIN, WALL = 5, 3
"""Unknown cells around the building, and the outer walls' thickness, in cells."""
INSIDE = (300, 200)
"""The hall inside its walls, cells along x and y."""


def hall() -> np.ndarray:
    """The map's pixels, ``uint8[rows, cols]``, row 0 the lowest (y up)."""
    cols, rows = INSIDE[0] + 2 * (MARGIN + WALL), INSIDE[1] + 2 * (MARGIN + WALL)
    pixels = np.full((rows, cols), UNKNOWN, np.uint8)
    outer = MARGIN
    pixels[outer : rows - outer, outer : cols - outer] = OCCUPIED
    x0, y0 = MARGIN + WALL, MARGIN + WALL  # the first free cell inside
    pixels[y0 : y0 + INSIDE[1], x0 : x0 + INSIDE[0]] = FREE

    def block(x: float, y: float, w: float, h: float) -> None:  # metres from the inside corner
        c, r = x0 + round(x / CELL), y0 + round(y / CELL)
        pixels[r : r + round(h / CELL), c : c + round(w / CELL)] = OCCUPIED

    for x in (7.8, 15.8, 23.8):  # pillars, 0.4 m square
        for y in (6.8, 13.2):
            block(x, y, 0.4, 0.4)
    block(0.0, 15.0, 6.0, 0.2)  # the office: its wall on the hall, 5 m deep, 6 m wide
    block(6.0, 15.0, 0.2, 5.0)
    pixels[y0 + 160 : y0 + 172, x0 + 60 : x0 + 62] = FREE  # its door, 1.2 m
    block(26.0, 0.0, 0.2, 4.0)  # the charging corner's partition, 4 m long
    return pixels


def write(folder: Path) -> None:
    """Write hall.pgm (binary P5, top row first) and hall.yaml into ``folder``."""
    pixels = hall()
    rows, cols = pixels.shape
    header = f"P5\n# MazeGen's example hall: examples/maps/make_hall.py\n{cols} {rows}\n255\n"
    (folder / "hall.pgm").write_bytes(header.encode("ascii") + pixels[::-1].tobytes())
    origin = -(MARGIN + WALL) * CELL
    (folder / "hall.yaml").write_text(
        "# The warehouse hall of examples/warehouse.maze (examples/maps/make_hall.py)\n"
        f"image: hall.pgm\nmode: trinary\nresolution: {CELL}\norigin: [{origin:.1f}, {origin:.1f}, 0.0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )


if __name__ == "__main__":
    write(Path(__file__).resolve().parent)
