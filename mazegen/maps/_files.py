"""The files an occupancy map comes in, read without new dependencies: map_server's YAML, PGM images
(binary P5 and ASCII P2, 8 or 16 bits), other images through Pillow, and grids of cells as text.

Each reader returns plain values and raises a one-line :class:`~mazegen.errors.MazeError` naming the
file (and its line where it has lines); what the values mean is
:mod:`~mazegen.maps._occupancy`' business.
"""

from __future__ import annotations

import io
import re
from pathlib import Path
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.fileio import read_bytes, read_text

MAX_MAP_BYTES = 256 * 1024 * 1024
"""Largest image read: far beyond the 1024-cell sides a floor may have, and still bounded."""

_KEY = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*:\s*(.*)")
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


def _scalar(text: str) -> Any:
    """A YAML scalar as map_server's files write them: a number, a boolean or a (quoted) string."""
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "'\"":
        return text[1:-1]
    if _NUMBER.fullmatch(text):
        return float(text)
    return {"true": True, "false": False}.get(text.lower(), text)


def _without_comment(text: str) -> str:
    """``text`` up to a ``#`` that is not inside quotes."""
    quote = None
    for index, char in enumerate(text):
        if char in "'\"" and quote in (None, char):
            quote = None if quote else char
        elif char == "#" and quote is None and (index == 0 or text[index - 1].isspace()):
            return text[:index].rstrip()
    return text.rstrip()


def read_map_yaml(path: Path) -> dict[str, Any]:
    """The ``key: value`` lines of a map_server YAML: scalars, and flow lists (``[x, y, yaw]``) of numbers.

    Raises:
        MazeError: For a line of another shape, a key given twice, or a list item that is no number.
    """
    values: dict[str, Any] = {}
    for number, line in enumerate(read_text(path, "map").splitlines(), start=1):
        text = _without_comment(line).strip()
        if not text or text == "---":
            continue
        found = _KEY.fullmatch(text)
        if found is None:
            raise MazeError("not valid map YAML: expected 'key: value'", filename=str(path), line=number)
        key, value = found[1], found[2].strip()
        if key in values:
            raise MazeError(f"'{key}' is given twice", filename=str(path), line=number)
        if value.startswith("["):
            items = [item.strip() for item in value.strip("[]").split(",")]
            if not value.endswith("]") or not all(_NUMBER.fullmatch(item) for item in items):
                raise MazeError(f"'{key}' must be a list of numbers", filename=str(path), line=number)
            values[key] = [float(item) for item in items]
        else:
            values[key] = _scalar(value)
    return values


def _pgm_header(data: bytes, path: Path) -> tuple[bytes, list[int], int]:
    """The magic number, width, height and maxval of a PGM, and where its pixels begin."""
    fields: list[bytes] = []
    position = 0
    while len(fields) < 4:
        while position < len(data) and data[position : position + 1].isspace():
            position += 1
        if data[position : position + 1] == b"#":
            end = data.find(b"\n", position)
            position = len(data) if end < 0 else end + 1
            continue
        start = position
        while position < len(data) and not data[position : position + 1].isspace():
            position += 1
        if start == position:
            raise MazeError("not a PGM image: its header ends early", filename=str(path))
        fields.append(data[start:position])
    if fields[0] not in (b"P5", b"P2") or not all(field.isdigit() for field in fields[1:]):
        raise MazeError("not a PGM image (P5 or P2 with width, height and maxval)", filename=str(path))
    width, height, maxval = (int(field) for field in fields[1:])
    if not (width > 0 and height > 0 and 0 < maxval < 65536):
        raise MazeError(
            f"PGM size {width} x {height} with maxval {maxval}: each must be positive, maxval below 65536",
            filename=str(path),
        )
    return fields[0], [width, height, maxval], position + 1


def read_pgm(path: Path) -> tuple[np.ndarray, int]:
    """The pixels of a PGM (``int[height, width]``, top row first) and its maxval.

    Raises:
        MazeError: For a file that is no PGM, or whose pixels are fewer or more than its header says.
    """
    data = read_bytes(path, "map image", limit=MAX_MAP_BYTES)
    magic, (width, height, maxval), start = _pgm_header(data, path)
    count = width * height
    if magic == b"P5":
        width_bytes = 2 if maxval > 255 else 1  # 16-bit pixels are big-endian
        found = (len(data) - start) // width_bytes
        pixels = None
        if len(data) - start == count * width_bytes:
            pixels = np.frombuffer(data, dtype=">u2" if width_bytes == 2 else np.uint8, offset=start)
    else:
        tokens = data[start:].split()
        found = len(tokens)
        if not all(token.isdigit() and int(token) <= maxval for token in tokens):
            raise MazeError(f"a pixel is not a whole number from 0 to {maxval}", filename=str(path))
        pixels = np.array([int(token) for token in tokens], dtype=np.int64) if found == count else None
    if pixels is None:
        raise MazeError(
            f"image size mismatch: the header says {width} x {height} = {count} pixels, "
            f"the file holds {found}",
            filename=str(path),
        )
    return pixels.astype(np.int64).reshape(height, width), maxval


def read_image(path: Path) -> tuple[np.ndarray, np.ndarray | None, int]:
    """An image Pillow reads (PNG...): its grey levels (``int[height, width]``, the mean of its colour
    channels, top row first), its alpha (0..1) when it has one, and its maxval.

    Raises:
        MazeError: For a file Pillow cannot read as an image.
    """
    from PIL import Image, UnidentifiedImageError

    data = read_bytes(path, "map image", limit=MAX_MAP_BYTES)
    try:
        with Image.open(io.BytesIO(data)) as image:
            if image.mode.startswith("I"):  # 16 or 32-bit grey
                return np.asarray(image, dtype=np.int64), None, 65535
            has_alpha = "A" in image.getbands() or "transparency" in image.info
            rgba = np.asarray(image.convert("RGBA"), dtype=np.int64)
    except (OSError, UnidentifiedImageError, ValueError) as error:
        raise MazeError(f"cannot read map image: {error}", filename=str(path)) from None
    grey = np.rint(rgba[..., :3].mean(axis=2)).astype(np.int64)
    return grey, (rgba[..., 3] / 255.0 if has_alpha else None), 255


_CELLS = {"0": False, ".": False, "1": True, "#": True}


def read_cell_text(path: Path) -> np.ndarray:
    """``bool[rows, cols]`` of a text grid, first line first: ``1`` or ``#`` an obstacle, ``0`` or ``.``
    free, spaces between cells allowed, blank lines skipped.

    Raises:
        MazeError: At the first other character, or a row of another length than the first.
    """
    rows: list[list[bool]] = []
    for number, line in enumerate(read_text(path, "grid").splitlines(), start=1):
        row = []
        for column, char in enumerate(line, start=1):
            if char in " \t":
                continue
            if char not in _CELLS:
                raise MazeError(
                    f"{char!r} is not a cell: write 0 or . for free, 1 or # for an obstacle",
                    filename=str(path),
                    line=number,
                    col=column,
                )
            row.append(_CELLS[char])
        if not row:
            continue
        if rows and len(row) != len(rows[0]):
            raise MazeError(
                f"a row of {len(row)} cells, the first row has {len(rows[0])}",
                filename=str(path),
                line=number,
            )
        rows.append(row)
    if not rows:
        raise MazeError("the grid has no cells", filename=str(path))
    return np.array(rows, dtype=bool)


def read_cell_array(path: Path) -> np.ndarray:
    """``bool[rows, cols]`` of a NumPy ``.npy`` grid, row 0 first: nonzero an obstacle.

    Raises:
        MazeError: For a file NumPy cannot read, or an array that is not a 2-D array of booleans or integers.
    """
    try:
        array = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError) as error:
        raise MazeError(f"cannot read grid: {error}", filename=str(path)) from None
    if not isinstance(array, np.ndarray) or array.ndim != 2 or array.dtype.kind not in "biu":
        shape = getattr(array, "shape", ())
        raise MazeError(
            f"a grid is a 2-D array of booleans or integers, got {getattr(array, 'dtype', 'an archive')} "
            f"of shape {shape}",
            filename=str(path),
        )
    return array != 0
