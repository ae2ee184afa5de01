"""Drawings of a scenario document as SVG or PNG.

Both pictures come from one list of drawing primitives (:mod:`mazegen.runtime.reports._picture`),
so the SVG and the PNG show the same thing. The shapes drawn inside the arena are
clipped to its frame: an SVG ``clipPath`` on their groups, and in the PNG a copy of
the image whose arena region alone is pasted back.
"""

from __future__ import annotations

import io
import itertools
import math
from collections.abc import Callable, Iterable
from pathlib import Path
from xml.sax.saxutils import escape

from PIL import Image, ImageChops, ImageDraw, ImageFont

from mazegen.errors import MazeError
from mazegen.fileio import write_atomic
from mazegen.runtime.reports._picture import layout
from mazegen.runtime.reports._scene import CLIPPED, INK, RGB, WHITE, Point, Shape, parse, rgb
from mazegen.spec import BaseMap

__all__ = ["render_file", "rgb", "scenario_png", "scenario_svg"]

_SUPERSAMPLE = 2
_CLIP_ID = "arena-frame"
_SVG_ANCHORS = {"start": "", "middle": ' text-anchor="middle"', "end": ' text-anchor="end"'}
_PIL_ANCHORS = {"start": "ls", "middle": "ms", "end": "rs"}


def _hex(colour: RGB) -> str:
    return "#{:02x}{:02x}{:02x}".format(*colour)


def _f(value: float) -> str:
    """A number with at most two decimals and no trailing zeros."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def _points(points: tuple[Point, ...]) -> str:
    return " ".join(f"{_f(x)},{_f(y)}" for x, y in points)


def _paint(shape: Shape) -> str:
    """SVG fill/stroke attributes of a shape."""
    attrs = [f'fill="{_hex(shape.fill)}"' if shape.fill else 'fill="none"']
    if shape.fill and shape.opacity < 1:
        attrs.append(f'fill-opacity="{_f(shape.opacity)}"')
    if shape.stroke:
        attrs.append(f'stroke="{_hex(shape.stroke)}" stroke-width="{_f(shape.width)}"')
    return " ".join(attrs)


def _svg_element(shape: Shape) -> str:
    if shape.kind == "rect":
        (x0, y0), (x1, y1) = shape.points
        return (
            f'<rect x="{_f(x0)}" y="{_f(y0)}" width="{_f(x1 - x0)}" height="{_f(y1 - y0)}" {_paint(shape)}/>'
        )
    if shape.kind in ("polygon", "polyline"):
        return f'<{shape.kind} points="{_points(shape.points)}" {_paint(shape)} stroke-linejoin="round"/>'
    if shape.kind == "path":
        rings = " ".join(f"M {_points(ring)} Z" for ring in shape.rings)
        return f'<path d="{rings}" fill-rule="evenodd" {_paint(shape)} stroke-linejoin="round"/>'
    if shape.kind == "circle":
        ((x, y),) = shape.points
        return f'<circle cx="{_f(x)}" cy="{_f(y)}" r="{_f(shape.radius)}" {_paint(shape)}/>'
    if shape.kind == "line":
        (x0, y0), (x1, y1) = shape.points
        return f'<line x1="{_f(x0)}" y1="{_f(y0)}" x2="{_f(x1)}" y2="{_f(y1)}" {_paint(shape)}/>'
    ((x, y),) = shape.points
    return (
        f'<text x="{_f(x)}" y="{_f(y)}" font-size="{_f(shape.width)}" fill="{_hex(shape.fill or INK)}"'
        f"{_SVG_ANCHORS[shape.anchor]}>{escape(shape.text)}</text>"
    )


def _svg_group(group: str, shapes: list[Shape]) -> list[str]:
    """The shapes of a group, in a ``<g>`` clipped to the arena's frame when it is drawn inside it."""
    lines = [_svg_element(shape) for shape in shapes]
    if group not in CLIPPED:
        return lines
    return [f'<g class="{group}" clip-path="url(#{_CLIP_ID})">', *lines, "</g>"]


def scenario_svg(doc: dict, *, base: BaseMap | None = None, pixels: int = 800) -> str:
    """Draw a scenario as a standalone SVG document.

    Args:
        doc: A ``mazegen-scenario`` version 1 document.
        base: The map the floor is built on (its spec's ``arena.base``), for a document that names one.
        pixels: Length of the longer side of the image.

    Returns:
        The SVG text, ending with a newline; the same document gives the same text.

    Raises:
        MazeError: If ``doc`` is not a scenario document, ``base`` is not the map it names, or
            ``pixels`` is below 100.
    """
    scene = parse(doc, base)
    picture = layout(scene, pixels)
    width, height = picture.width, picture.height
    (x0, y0), (x1, y1) = picture.frame
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif">',
        f"<title>{escape(scene.title)}</title>",
        f'<defs><clipPath id="{_CLIP_ID}"><rect x="{_f(x0)}" y="{_f(y0)}" width="{_f(x1 - x0)}" '
        f'height="{_f(y1 - y0)}"/></clipPath></defs>',
    ]
    for group, shapes in itertools.groupby(picture.shapes, key=lambda shape: shape.group):
        lines += _svg_group(group, list(shapes))
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def scenario_png(doc: dict, *, base: BaseMap | None = None, pixels: int = 800) -> bytes:
    """Draw a scenario as a PNG image with Pillow.

    Args:
        doc: A ``mazegen-scenario`` version 1 document.
        base: The map the floor is built on (its spec's ``arena.base``), for a document that names one.
        pixels: Length of the longer side of the image.

    Returns:
        The PNG bytes; the same document gives the same bytes.

    Raises:
        MazeError: If ``doc`` is not a scenario document, ``base`` is not the map it names, or
            ``pixels`` is below 100.
    """
    picture = layout(parse(doc, base), pixels)
    s = _SUPERSAMPLE
    image = Image.new("RGB", (picture.width * s, picture.height * s), WHITE)
    (x0, y0), (x1, y1) = picture.frame
    frame = (round(x0 * s), round(y0 * s), round(x1 * s), round(y1 * s))
    for group, shapes in itertools.groupby(picture.shapes, key=lambda shape: shape.group):
        if group in CLIPPED:  # drawn on a copy, of which only the arena is kept
            canvas = image.copy()
            _draw_png(canvas, shapes)
            image.paste(canvas.crop(frame), frame[:2])
        else:
            _draw_png(image, shapes)
    buffer = io.BytesIO()
    image.resize((picture.width, picture.height), Image.Resampling.LANCZOS).save(buffer, format="PNG")
    return buffer.getvalue()


def _draw_png(image: Image.Image, shapes: Iterable[Shape]) -> None:
    """Draw shapes on a supersampled image."""
    s = _SUPERSAMPLE
    draw = ImageDraw.Draw(image, "RGBA")
    for shape in shapes:
        xy = [(x * s, y * s) for x, y in shape.points]
        fill = None if shape.fill is None else (*shape.fill, round(255 * shape.opacity))
        line = max(1, round(shape.width * s))
        if shape.kind == "rect":
            draw.rectangle(xy, fill=fill, outline=shape.stroke, width=line if shape.stroke else 0)
        elif shape.kind == "polygon":
            draw.polygon(xy, fill=fill, outline=shape.stroke, width=line)
        elif shape.kind == "path":
            _draw_rings(image, draw, shape)
        elif shape.kind == "circle":
            (x, y), r = xy[0], shape.radius * s
            draw.ellipse([(x - r, y - r), (x + r, y + r)], fill=fill, outline=shape.stroke, width=line)
        elif shape.kind in ("line", "polyline"):
            draw.line(xy, fill=shape.stroke, width=line, joint="curve")
        else:
            font = ImageFont.load_default(size=shape.width * s)
            draw.text(xy[0], shape.text, fill=shape.fill, font=font, anchor=_PIL_ANCHORS[shape.anchor])


def _draw_rings(image: Image.Image, draw: ImageDraw.ImageDraw, shape: Shape) -> None:
    """Fill a path's rings even-odd (a ring inside another is a hole) and outline each."""
    s = _SUPERSAMPLE
    rings = [[(x * s, y * s) for x, y in ring] for ring in shape.rings]
    xs, ys = [x for ring in rings for x, _ in ring], [y for ring in rings for _, y in ring]
    left, top = max(0, math.floor(min(xs))), max(0, math.floor(min(ys)))
    right, bottom = min(image.width, math.ceil(max(xs)) + 1), min(image.height, math.ceil(max(ys)) + 1)
    if shape.fill is not None and left < right and top < bottom:  # masks of the path's box alone
        inside = Image.new("1", (right - left, bottom - top))
        for ring in rings:
            one = Image.new("1", inside.size)
            ImageDraw.Draw(one).polygon([(x - left, y - top) for x, y in ring], fill=1)
            inside = ImageChops.logical_xor(inside, one)
        alpha = round(255 * shape.opacity)  # a colour pasted through a mask blends in, as other fills do
        blend = inside.convert("L").point(lambda on: alpha if on else 0)
        image.paste(shape.fill, (left, top, right, bottom), blend)
    for ring in rings:
        draw.line([*ring, ring[0]], fill=shape.stroke, width=max(1, round(shape.width * s)), joint="curve")


_WRITERS: dict[str, Callable[[dict, BaseMap | None], bytes]] = {
    ".svg": lambda doc, base: scenario_svg(doc, base=base).encode("utf-8"),
    ".png": lambda doc, base: scenario_png(doc, base=base),
}


def render_file(doc: dict, path: Path, *, base: BaseMap | None = None) -> None:
    """Draw a scenario into ``path``, as SVG or PNG by its suffix, replacing it atomically.

    Args:
        doc: A ``mazegen-scenario`` version 1 document.
        path: Where to write; the suffix (``.svg`` or ``.png``) picks the format.
        base: The map the floor is built on (its spec's ``arena.base``), for a document that names one.

    Raises:
        MazeError: For another suffix, a bad document or map, or a file that cannot be written.
    """
    path = Path(path)
    writer = _WRITERS.get(path.suffix.lower())
    if writer is None:
        raise MazeError(f"cannot draw into {path.name!r}: the name must end with .svg or .png")
    data = writer(doc, base)
    try:
        write_atomic(path, data)
    except OSError as exc:
        raise MazeError(f"cannot write {path}: {exc.strerror or exc}") from exc
