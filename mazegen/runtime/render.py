"""Drawings of a scenario document as SVG or PNG.

Both pictures come from one list of drawing primitives laid out in image pixels,
so the SVG and the PNG show the same thing: the arena (y up, flipped to the
image's y down), every part of every element as a semi-opaque polygon in the
element's colour, the robot's path when the document has one, the start and
goal as circles of the robot radius, a title, a legend with a count per element
type and a scale bar in the arena unit.
"""

from __future__ import annotations

import io
import itertools
import math
import re
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape

from PIL import Image, ImageColor, ImageDraw, ImageFont

from mazegen.errors import MazeError
from mazegen.fileio import write_atomic

Point = tuple[float, float]
RGB = tuple[int, int, int]

_DEFAULT_COLOUR: RGB = (85, 85, 85)
_START: RGB = (44, 160, 44)
_GOAL: RGB = (214, 39, 40)
_PATH: RGB = (230, 0, 126)  # magenta: no bundled element is drawn in it
_INK: RGB = (34, 34, 34)
_PAPER: RGB = (244, 244, 244)
_WHITE: RGB = (255, 255, 255)
_FILL_OPACITY = 0.55
_SUPERSAMPLE = 2
# Characters XML 1.0 does not allow, even escaped.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


@dataclass(frozen=True)
class _Element:
    kind: str
    colour: RGB
    parts: tuple[tuple[Point, ...], ...]


@dataclass(frozen=True)
class _Scene:
    name: str
    width: float
    height: float
    unit: str
    start: Point
    goal: Point
    radius: float
    elements: tuple[_Element, ...]
    fitness: str
    path: tuple[Point, ...]


@dataclass(frozen=True)
class _Shape:
    """One drawing primitive in image pixels (y down).

    ``points`` holds two corners for a rect, the centre for a circle, the ends of
    a line, every vertex of a polygon or polyline and the left baseline point of a text.
    """

    kind: str
    points: tuple[Point, ...]
    fill: RGB | None = None
    stroke: RGB | None = None
    opacity: float = 1.0
    width: float = 1.0
    radius: float = 0.0
    text: str = ""


def _label(value: Any, limit: int = 60) -> str:
    """A one-line, XML-safe text of at most ``limit`` characters."""
    text = _NOT_XML.sub("\ufffd", " ".join(str(value).split()))
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _number(value: Any) -> float:
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"{value!r} is not a finite number")
    return number


def _point(value: Any) -> Point:
    x, y = value
    return _number(x), _number(y)


def rgb(value: Any) -> RGB:
    """The red, green and blue of a CSS colour; a colour it cannot read is grey."""
    try:
        r, g, b = ImageColor.getrgb(str(value))[:3]
    except ValueError:
        return _DEFAULT_COLOUR
    return r, g, b


def _parse(doc: dict) -> _Scene:
    """Read the parts of a scenario document that the drawing needs."""
    if doc.get("format") != "mazegen-scenario" or doc.get("version") != 1:
        raise MazeError("not a scenario document (want format 'mazegen-scenario', version 1)")
    try:
        arena = doc["arena"]
        width, height = _number(arena["width"]), _number(arena["height"])
        if width <= 0 or height <= 0:
            raise ValueError("the arena must have a positive width and height")
        elements = []
        for element in doc["elements"]:
            parts = tuple(tuple(_point(p) for p in part) for part in element["parts"])
            if any(len(part) < 3 for part in parts):
                raise ValueError("a part has fewer than three vertices")
            elements.append(_Element(_label(element["type"], 40), rgb(element.get("colour")), parts))
        fitness = doc.get("fitness")
        path = doc.get("path") or ()
        return _Scene(
            name=_label(doc.get("scenario", "scenario")),
            width=width,
            height=height,
            unit=_label(arena.get("unit", ""), 12),
            start=_point(arena["start"]),
            goal=_point(arena["goal"]),
            radius=max(0.0, _number(arena.get("robot_radius", 0.0))),
            elements=tuple(elements),
            fitness=f"{fitness:.4g}" if isinstance(fitness, (int, float)) else "n/a",
            path=tuple(_point(p) for p in path) if len(path) >= 2 else (),
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise MazeError(f"bad scenario document: {exc!r}") from exc


def _nice_length(target: float) -> float:
    """The largest 1, 2 or 5 × 10^k not above ``target``."""
    power = 10.0 ** math.floor(math.log10(target))
    return next(m * power for m in (5, 2, 1) if m * power <= target)


def _with_unit(length: float, unit: str) -> str:
    """``length`` (whole, or to its first significant decimal below 1) and the unit: ``200 cm``."""
    whole = length >= 1 or length <= 0
    number = str(round(length)) if whole else f"{length:.{-math.floor(math.log10(length))}f}"
    return f"{number} {unit}".rstrip()


def _layout(scene: _Scene, pixels: int) -> tuple[int, int, list[_Shape]]:
    """Lay the picture out: image width, height and the shapes in drawing order."""
    if pixels < 100:
        raise MazeError(f"a drawing needs at least 100 pixels, not {pixels}")
    u = pixels / 800
    pad, font, side = 12 * u, 13 * u, 200 * u
    row, title_h, bottom_h = 1.6 * font, pad + 1.8 * font, 2.6 * font + pad
    k = min((pixels - 3 * pad - side) / scene.width, (pixels - title_h - bottom_h) / scene.height)
    types = Counter(e.kind for e in scene.elements)
    rows = len(types) + 2 + bool(scene.path)  # the types, start, goal and the path
    max_rows = int((pixels - title_h - pad) / row)
    width = round(3 * pad + side + k * scene.width)
    legend_h = title_h + min(rows, max_rows) * row
    height = min(pixels, round(max(title_h + bottom_h + k * scene.height, legend_h)))
    ox, oy = pad, title_h

    def at(p: Point) -> Point:
        return ox + k * p[0], oy + k * (scene.height - p[1])

    title = _label(_title(scene), int((width - 2 * pad) / (0.7 * font)))
    shapes = [
        _Shape("rect", ((0, 0), (width, height)), fill=_PAPER),
        _Shape("text", ((pad, pad + 1.15 * font),), fill=_INK, width=1.15 * font, text=title),
        _Shape("rect", (at((0, scene.height)), at((scene.width, 0))), _WHITE, _INK, width=2 * u),
    ]
    for element in scene.elements:
        shapes += [
            _Shape(
                "polygon",
                tuple(at(p) for p in part),
                element.colour,
                _darker(element.colour),
                _FILL_OPACITY,
                width=u,
            )
            for part in element.parts
        ]
    if scene.path:
        shapes.append(_Shape("polyline", tuple(at(p) for p in scene.path), stroke=_PATH, width=2.5 * u))
    radius = max(3.0, k * scene.radius)
    for point, colour in ((scene.start, _START), (scene.goal, _GOAL)):
        shapes.append(_Shape("circle", (at(point),), colour, _darker(colour), 0.85, 1.5 * u, radius))

    # Legend: one row per element type (sorted), then start, goal and the path.
    colours = {e.kind: e.colour for e in reversed(scene.elements)}
    chars = int((side - 2 * font) / (0.6 * font))
    entries: list[tuple[str, str, RGB]] = [
        ("rect", f"{_label(kind, chars - len(str(count)) - 3)} ({count})", colours[kind])
        for kind, count in sorted(types.items())
    ]
    entries += [("circle", "start", _START), ("circle", "goal", _GOAL)]
    if scene.path:
        travelled = sum(math.dist(a, b) for a, b in itertools.pairwise(scene.path))
        entries.append(("line", f"path ({_with_unit(travelled, scene.unit)})", _PATH))
    if len(entries) > max_rows:
        hidden = len(entries) - max_rows + 1
        entries = [*entries[: max_rows - 1], ("none", f"+{hidden} more", _INK)]
    lx = width - pad - side
    for i, (swatch, text, colour) in enumerate(entries):
        y = title_h + i * row
        if swatch == "rect":
            shapes.append(
                _Shape("rect", ((lx, y), (lx + font, y + font)), colour, _darker(colour), _FILL_OPACITY, u)
            )
        elif swatch == "circle":
            shapes.append(
                _Shape("circle", ((lx + font / 2, y + font / 2),), colour, _darker(colour), 0.85, u, font / 2)
            )
        elif swatch == "line":
            shapes.append(
                _Shape("line", ((lx, y + font / 2), (lx + font, y + font / 2)), stroke=colour, width=2.5 * u)
            )
        shapes.append(_Shape("text", ((lx + 1.6 * font, y + 0.85 * font),), fill=_INK, width=font, text=text))

    # Scale bar under the arena.
    length = _nice_length(scene.width / 4)
    x0, y0 = ox, oy + k * scene.height + 1.3 * font
    x1, tick = x0 + k * length, 0.4 * font
    shapes += [
        _Shape("line", ((x0, y0), (x1, y0)), stroke=_INK, width=2 * u),
        _Shape("line", ((x0, y0 - tick), (x0, y0 + tick)), stroke=_INK, width=2 * u),
        _Shape("line", ((x1, y0 - tick), (x1, y0 + tick)), stroke=_INK, width=2 * u),
        _Shape(
            "text",
            ((x1 + 0.6 * font, y0 + 0.35 * font),),
            fill=_INK,
            width=font,
            text=_with_unit(length, scene.unit),
        ),
    ]
    return width, height, shapes


def _title(scene: _Scene) -> str:
    return f"{scene.name} | {len(scene.elements)} elements | fitness {scene.fitness}"


def _darker(colour: RGB) -> RGB:
    r, g, b = (int(c * 0.6) for c in colour)
    return r, g, b


def _hex(colour: RGB) -> str:
    return "#{:02x}{:02x}{:02x}".format(*colour)


def _f(value: float) -> str:
    """A number with at most two decimals and no trailing zeros."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def _paint(shape: _Shape) -> str:
    """SVG fill/stroke attributes of a shape."""
    attrs = [f'fill="{_hex(shape.fill)}"' if shape.fill else 'fill="none"']
    if shape.fill and shape.opacity < 1:
        attrs.append(f'fill-opacity="{_f(shape.opacity)}"')
    if shape.stroke:
        attrs.append(f'stroke="{_hex(shape.stroke)}" stroke-width="{_f(shape.width)}"')
    return " ".join(attrs)


def _svg_element(shape: _Shape) -> str:
    if shape.kind == "rect":
        (x0, y0), (x1, y1) = shape.points
        return (
            f'<rect x="{_f(x0)}" y="{_f(y0)}" width="{_f(x1 - x0)}" height="{_f(y1 - y0)}" {_paint(shape)}/>'
        )
    if shape.kind in ("polygon", "polyline"):
        points = " ".join(f"{_f(x)},{_f(y)}" for x, y in shape.points)
        return f'<{shape.kind} points="{points}" {_paint(shape)} stroke-linejoin="round"/>'
    if shape.kind == "circle":
        ((x, y),) = shape.points
        return f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(shape.radius)}" {_paint(shape)}/>'
    if shape.kind == "line":
        (x0, y0), (x1, y1) = shape.points
        return f'<line x1="{_f(x0)}" y1="{_f(y0)}" x2="{_f(x1)}" y2="{_f(y1)}" {_paint(shape)}/>'
    ((x, y),) = shape.points
    return (
        f'<text x="{_f(x)}" y="{_f(y)}" font-size="{_f(shape.width)}" fill="{_hex(shape.fill or _INK)}">'
        f"{escape(shape.text)}</text>"
    )


def scenario_svg(doc: dict, *, pixels: int = 800) -> str:
    """Draw a scenario as a standalone SVG document.

    Args:
        doc: A ``mazegen-scenario`` version 1 document.
        pixels: Length of the longer side of the image.

    Returns:
        The SVG text, ending with a newline; the same document gives the same text.

    Raises:
        MazeError: If ``doc`` is not a scenario document or ``pixels`` is below 100.
    """
    scene = _parse(doc)
    width, height, shapes = _layout(scene, pixels)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif">',
        f"<title>{escape(_title(scene))}</title>",
        *(_svg_element(shape) for shape in shapes),
        "</svg>",
    ]
    return "\n".join(lines) + "\n"


def scenario_png(doc: dict, *, pixels: int = 800) -> bytes:
    """Draw a scenario as a PNG image with Pillow.

    Args:
        doc: A ``mazegen-scenario`` version 1 document.
        pixels: Length of the longer side of the image.

    Returns:
        The PNG bytes; the same document gives the same bytes.

    Raises:
        MazeError: If ``doc`` is not a scenario document or ``pixels`` is below 100.
    """
    width, height, shapes = _layout(_parse(doc), pixels)
    s = _SUPERSAMPLE
    image = Image.new("RGB", (width * s, height * s), _WHITE)
    draw = ImageDraw.Draw(image, "RGBA")
    for shape in shapes:
        xy = [(x * s, y * s) for x, y in shape.points]
        fill = None if shape.fill is None else (*shape.fill, round(255 * shape.opacity))
        line = max(1, round(shape.width * s))
        if shape.kind == "rect":
            draw.rectangle(xy, fill=fill, outline=shape.stroke, width=line if shape.stroke else 0)
        elif shape.kind == "polygon":
            draw.polygon(xy, fill=fill, outline=shape.stroke, width=line)
        elif shape.kind == "circle":
            (x, y), r = xy[0], shape.radius * s
            draw.ellipse([(x - r, y - r), (x + r, y + r)], fill=fill, outline=shape.stroke, width=line)
        elif shape.kind in ("line", "polyline"):
            draw.line(xy, fill=shape.stroke, width=line, joint="curve")
        else:
            font = ImageFont.load_default(size=shape.width * s)
            draw.text(xy[0], shape.text, fill=shape.fill, font=font, anchor="ls")
    buffer = io.BytesIO()
    image.resize((width, height), Image.Resampling.LANCZOS).save(buffer, format="PNG")
    return buffer.getvalue()


_WRITERS: dict[str, Callable[[dict], bytes]] = {
    ".svg": lambda doc: scenario_svg(doc).encode("utf-8"),
    ".png": scenario_png,
}


def render_file(doc: dict, path: Path) -> None:
    """Draw a scenario into ``path``, as SVG or PNG by its suffix, replacing it atomically.

    Args:
        doc: A ``mazegen-scenario`` version 1 document.
        path: Where to write; the suffix (``.svg`` or ``.png``) picks the format.

    Raises:
        MazeError: For another suffix, a bad document, or a file that cannot be written.
    """
    path = Path(path)
    writer = _WRITERS.get(path.suffix.lower())
    if writer is None:
        raise MazeError(f"cannot draw into {path.name!r}: the name must end with .svg or .png")
    data = writer(doc)
    try:
        write_atomic(path, data)
    except OSError as exc:
        raise MazeError(f"cannot write {path}: {exc.strerror or exc}") from exc
