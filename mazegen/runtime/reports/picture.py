"""The picture of a scenario document as drawing primitives in image pixels.

:mod:`mazegen.runtime.reports.render` writes these primitives as SVG or PNG, so both show
the same thing: the arena (y up, flipped to the image's y down) with axes in the
arena unit, every part of every element as a semi-opaque polygon in the element's
colour, the robot's path when the document has one or a "no path" mark when its
metrics say there is none, each driven controller's trajectory as a line in its own
colour (an × where it collided), the start and goal as circles of the robot radius, a
title, a legend with a count per element type, the path and each controller, and a
scale bar. What is drawn
inside the arena belongs to a group clipped to the arena's frame, so that large
elements never cover the title, legend, axes or scale bar.
"""

from __future__ import annotations

import itertools
import math
import re
from collections import Counter
from dataclasses import dataclass
from typing import Any

from PIL import ImageColor

from mazegen.errors import MazeError
from mazegen.spec import Arena

Point = tuple[float, float]
RGB = tuple[int, int, int]

DEFAULT_COLOUR: RGB = (85, 85, 85)
START: RGB = (44, 160, 44)
GOAL: RGB = (214, 39, 40)
PATH: RGB = (230, 0, 126)  # magenta: no bundled element is drawn in it
NO_PATH: RGB = (0, 0, 0)
INK: RGB = (34, 34, 34)
PAPER: RGB = (244, 244, 244)
WHITE: RGB = (255, 255, 255)
FILL_OPACITY = 0.7
MARKER_OPACITY = 0.85
DRIVE_COLOURS: tuple[RGB, ...] = (
    (31, 119, 180),  # blue
    (255, 127, 14),  # orange
    (148, 103, 189),  # purple
    (23, 190, 207),  # cyan
    (140, 86, 75),  # brown
    (188, 189, 34),  # olive
)
"""The trajectories' colours, none of them the path's, the start's or the goal's."""
CLIPPED = ("elements", "no-path", "drive")
"""The groups drawn inside the arena, clipped to its frame."""
_MIN_FONT = 10.0  # pixels: small pictures (the report's thumbnails) stay readable
# Characters XML 1.0 does not allow, even escaped.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


@dataclass(frozen=True)
class _Element:
    kind: str
    colour: RGB
    parts: tuple[tuple[Point, ...], ...]


@dataclass(frozen=True)
class Driven:
    """One controller's drive through the floor: its trajectory and where it collided."""

    controller: str
    outcome: str
    colour: RGB
    trajectory: tuple[Point, ...]
    collision: Point | None


@dataclass(frozen=True)
class Scene:
    """What the picture shows of a scenario document."""

    name: str
    arena: Arena
    elements: tuple[_Element, ...]
    fitness: str
    path: tuple[Point, ...]
    unsolvable: bool
    drives: tuple[Driven, ...] = ()

    @property
    def title(self) -> str:
        return f"{self.name} | {len(self.elements)} elements | fitness {self.fitness}"


@dataclass(frozen=True)
class Shape:
    """One drawing primitive in image pixels (y down).

    ``points`` holds two corners for a rect, the centre for a circle, the ends of
    a line, every vertex of a polygon or polyline and the anchor point of a text
    (on its baseline; ``anchor`` says whether it starts, centres or ends the text).
    ``group`` names the group a shape belongs to (:data:`CLIPPED` groups are clipped
    to the arena).
    """

    kind: str
    points: tuple[Point, ...]
    fill: RGB | None = None
    stroke: RGB | None = None
    opacity: float = 1.0
    width: float = 1.0
    radius: float = 0.0
    text: str = ""
    anchor: str = "start"
    group: str = ""


@dataclass(frozen=True)
class Picture:
    """A laid-out picture: its size, the arena's frame and the shapes in drawing order."""

    width: int
    height: int
    frame: tuple[Point, Point]
    shapes: tuple[Shape, ...]


def label(value: Any, limit: int = 60) -> str:
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
    """The red, green and blue of a CSS colour, each within 0..255; a colour it cannot read is grey."""
    try:
        channels = ImageColor.getrgb(str(value))[:3]
    except ValueError:
        return DEFAULT_COLOUR
    r, g, b = (min(255, max(0, int(channel))) for channel in channels)  # rgb(300,0,0) reads as 300
    return r, g, b


def parse(doc: dict) -> Scene:
    """Read the parts of a scenario document that the picture needs."""
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
            elements.append(_Element(label(element["type"], 40), rgb(element.get("colour")), parts))
        fitness = doc.get("fitness")
        path = doc.get("path") or ()
        metrics = doc.get("metrics")
        return Scene(
            name=label(doc.get("scenario", "scenario")),
            arena=Arena(
                name=label(arena.get("name", "")),
                width=width,
                height=height,
                unit=label(arena.get("unit", ""), 12),
                start=_point(arena["start"]),
                goal=_point(arena["goal"]),
                robot_radius=max(0.0, _number(arena.get("robot_radius", 0.0))),
            ),
            elements=tuple(elements),
            fitness=f"{fitness:.4g}" if isinstance(fitness, (int, float)) else "n/a",
            path=tuple(_point(p) for p in path) if len(path) >= 2 else (),
            unsolvable=isinstance(metrics, dict) and metrics.get("solvable") is False,
            drives=_drives(doc.get("drive")),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as exc:  # AttributeError: a drive not an object
        raise MazeError(f"bad scenario document: {exc!r}") from exc


def _drives(section: Any) -> tuple[Driven, ...]:
    """The controllers' drives of a document's ``drive`` section, coloured in its order."""
    if not section:
        return ()
    drives = []
    for index, (name, entry) in enumerate(section.items()):
        collision = entry.get("collision")
        drives.append(
            Driven(
                controller=label(name, 40),
                outcome=label(entry.get("outcome", ""), 20),
                colour=DRIVE_COLOURS[index % len(DRIVE_COLOURS)],
                trajectory=tuple(_point(pose[:2]) for pose in entry.get("trajectory") or ()),
                collision=None if collision is None else _point(collision),
            )
        )
    return tuple(drives)


def _nice_length(target: float) -> float:
    """The largest 1, 2 or 5 × 10^k not above ``target``."""
    power = 10.0 ** math.floor(math.log10(target))
    return next(m * power for m in (5, 2, 1) if m * power <= target)


def _decimals(step: float) -> int:
    return max(0, -math.floor(math.log10(step)))


def _with_unit(length: float, unit: str) -> str:
    """``length`` (whole, or to its first significant decimal below 1) and the unit: ``200 cm``."""
    whole = length >= 1 or length <= 0
    number = str(round(length)) if whole else f"{length:.{_decimals(length)}f}"
    return f"{number} {unit}".rstrip()


def _ticks(length: float, scale: float, gap: float) -> list[tuple[float, str]]:
    """Tick positions and labels along an axis of ``length`` units drawn at ``scale`` pixels per
    unit: every multiple of the smallest 1, 2 or 5 × 10^k step at least ``gap`` pixels apart."""
    step = _nice_length(length / 20)
    while step * scale < gap:
        step = _nice_length(step * 2.5)
    count = math.floor(length / step + 1e-9)
    return [(i * step, _coordinate(i * step, step)) for i in range(count + 1)]


def _coordinate(value: float, step: float) -> str:
    """A tick's label: as many decimals as the step needs, or three digits and an exponent when long."""
    text = f"{value:.{_decimals(step)}f}"
    return text if len(text) <= 8 else f"{value:.3g}"


def layout(scene: Scene, pixels: int) -> Picture:
    """Lay the picture out, ``pixels`` along its longer side."""
    if pixels < 100:
        raise MazeError(f"a drawing needs at least 100 pixels, not {pixels}")
    u = pixels / 800
    font = max(13 * u, _MIN_FONT)
    pad, side, tick = 12 * u, 200 / 13 * font, 0.4 * font
    row, title_h = 1.6 * font, pad + 1.8 * font
    char = 0.6 * font  # the width of a digit, about
    digits = len(_coordinate(scene.arena.height, _nice_length(scene.arena.height / 20)))
    ox, oy = pad + tick + 0.3 * font + digits * char, title_h + 0.5 * font
    bottom_h = tick + 1.3 * font + 2.4 * font + pad  # tick labels, then the scale bar
    gap = pad + 3 * char  # room for the last x tick label's right half
    k = min(
        (pixels - ox - gap - side - pad) / scene.arena.width, (pixels - oy - bottom_h) / scene.arena.height
    )
    types = Counter(e.kind for e in scene.elements)
    max_rows = int((pixels - title_h - pad) / row)
    width = round(ox + k * scene.arena.width + gap + side + pad)
    # types, start, goal, path, controllers
    legend_rows = len(types) + 2 + bool(scene.path or scene.unsolvable) + len(scene.drives)
    legend_h = title_h + min(legend_rows, max_rows) * row
    height = min(pixels, round(max(oy + k * scene.arena.height + bottom_h, legend_h)))

    def at(p: Point) -> Point:
        return ox + k * p[0], oy + k * (scene.arena.height - p[1])

    frame = (at((0, scene.arena.height)), at((scene.arena.width, 0)))
    title = label(scene.title, int((width - 2 * pad) / (0.7 * font)))
    shapes = [
        Shape("rect", ((0, 0), (width, height)), fill=PAPER),
        Shape("text", ((pad, pad + 1.15 * font),), fill=INK, width=1.15 * font, text=title),
        Shape("rect", frame, fill=WHITE),
        *_arena_contents(scene, at, k, u, font),
        Shape("rect", frame, stroke=INK, width=2 * u),
        *_axes(scene, at, k, u, font, tick),
        *_legend(scene, types, (width - pad - side, title_h), side, max_rows, u, font),
        *_scale_bar(scene, (ox, oy + k * scene.arena.height + tick + 3.2 * font), frame[1][0], k, u, font),
    ]
    return Picture(width, height, frame, tuple(shapes))


def _arena_contents(scene: Scene, at: Any, k: float, u: float, font: float) -> list[Shape]:
    """The elements, the path or the "no path" mark, the trajectories, start and goal, and the
    collisions: the clipped groups."""
    shapes = [
        Shape(
            "polygon",
            tuple(at(p) for p in part),
            e.colour,
            darker(e.colour),
            FILL_OPACITY,
            u,
            group="elements",
        )
        for e in scene.elements
        for part in e.parts
    ]
    if scene.path:
        shapes.append(
            Shape("polyline", tuple(at(p) for p in scene.path), stroke=PATH, width=2.5 * u, group="elements")
        )
    shapes += _trajectories(scene, at, u)
    radius = max(3.0, k * scene.arena.robot_radius)
    for point, colour in ((scene.arena.start, START), (scene.arena.goal, GOAL)):
        shapes.append(
            Shape(
                "circle",
                (at(point),),
                colour,
                darker(colour),
                MARKER_OPACITY,
                1.5 * u,
                radius,
                group="elements",
            )
        )
    shapes += _collisions(scene, at, radius, u)
    if scene.unsolvable:
        shapes += _no_path_mark(at(scene.arena.start), at(scene.arena.goal), u, font)
    return shapes


def _trajectories(scene: Scene, at: Any, u: float) -> list[Shape]:
    """Each controller's trajectory as a line in its colour."""
    return [
        Shape(
            "polyline",
            tuple(at(p) for p in drive.trajectory),
            stroke=drive.colour,
            width=2 * u,
            group="drive",
        )
        for drive in scene.drives
        if len(drive.trajectory) >= 2
    ]


def _collisions(scene: Scene, at: Any, size: float, u: float) -> list[Shape]:
    """An × of the robot's size in the controller's colour where it collided, over start and goal."""
    shapes = []
    for drive in scene.drives:
        if drive.collision is not None:
            x, y = at(drive.collision)
            shapes += [
                Shape(
                    "line",
                    ((x - a, y - size), (x + a, y + size)),
                    stroke=drive.colour,
                    width=3 * u,
                    group="drive",
                )
                for a in (size, -size)
            ]
    return shapes


def _no_path_mark(start: Point, goal: Point, u: float, font: float) -> list[Shape]:
    """A dashed line from start to goal and a boxed "no path" at its middle."""
    length = math.dist(start, goal)
    dash = 2.5 * font
    shapes = []
    for i in range(math.ceil(length / dash)):
        a, b = i * dash / length, min(1.0, (i + 0.6) * dash / length)
        ends = tuple(
            (start[0] + t * (goal[0] - start[0]), start[1] + t * (goal[1] - start[1])) for t in (a, b)
        )
        shapes.append(Shape("line", ends, stroke=NO_PATH, width=2.5 * u, group="no-path"))
    mx, my = (start[0] + goal[0]) / 2, (start[1] + goal[1]) / 2
    half = 2.6 * font
    box = ((mx - half, my - 0.9 * font), (mx + half, my + 0.7 * font))
    return [
        *shapes,
        Shape("rect", box, WHITE, NO_PATH, 0.9, 1.5 * u, group="no-path"),
        Shape(
            "text",
            ((mx, my + 0.35 * font),),
            fill=NO_PATH,
            width=font,
            text="no path",
            anchor="middle",
            group="no-path",
        ),
    ]


def _axes(scene: Scene, at: Any, k: float, u: float, font: float, tick: float) -> list[Shape]:
    """Ticks and coordinates along the arena's bottom (x) and left (y) edges."""
    shapes = []
    longest = len(_coordinate(scene.arena.width, _nice_length(scene.arena.width / 20))) * 0.6 * font
    for value, text in _ticks(scene.arena.width, k, longest + font):
        x, y = at((value, 0))
        shapes += [
            Shape("line", ((x, y), (x, y + tick)), stroke=INK, width=u),
            Shape("text", ((x, y + tick + font),), fill=INK, width=font, text=text, anchor="middle"),
        ]
    for value, text in _ticks(scene.arena.height, k, 3 * font):
        x, y = at((0, value))
        shapes += [
            Shape("line", ((x - tick, y), (x, y)), stroke=INK, width=u),
            Shape(
                "text",
                ((x - tick - 0.3 * font, y + 0.35 * font),),
                fill=INK,
                width=font,
                text=text,
                anchor="end",
            ),
        ]
    return shapes


def _legend(
    scene: Scene, types: Counter[str], corner: Point, side: float, max_rows: int, u: float, font: float
) -> list[Shape]:
    """One row per element type (sorted), then start, goal and the path (or "no path")."""
    colours = {e.kind: e.colour for e in reversed(scene.elements)}
    chars = int((side - 2 * font) / (0.6 * font))
    entries: list[tuple[str, str, RGB]] = [
        ("rect", f"{label(kind, chars - len(str(count)) - 3)} ({count})", colours[kind])
        for kind, count in sorted(types.items())
    ]
    entries += [("circle", "start", START), ("circle", "goal", GOAL)]
    if scene.path:
        travelled = sum(math.dist(a, b) for a, b in itertools.pairwise(scene.path))
        entries.append(("line", f"path ({_with_unit(travelled, scene.arena.unit)})", PATH))
    elif scene.unsolvable:
        entries.append(("line", "no path", NO_PATH))
    entries += [("line", f"{drive.controller}: {drive.outcome}", drive.colour) for drive in scene.drives]
    if len(entries) > max_rows:
        hidden = len(entries) - max_rows + 1
        entries = [*entries[: max_rows - 1], ("none", f"+{hidden} more", INK)]
    lx, top = corner
    shapes = []
    for i, (swatch, text, colour) in enumerate(entries):
        y = top + i * 1.6 * font
        if swatch == "rect":
            shapes.append(
                Shape("rect", ((lx, y), (lx + font, y + font)), colour, darker(colour), FILL_OPACITY, u)
            )
        elif swatch == "circle":
            centre = (lx + font / 2, y + font / 2)
            shapes.append(Shape("circle", (centre,), colour, darker(colour), MARKER_OPACITY, u, font / 2))
        elif swatch == "line":
            shapes.append(
                Shape("line", ((lx, y + font / 2), (lx + font, y + font / 2)), stroke=colour, width=2.5 * u)
            )
        shapes.append(Shape("text", ((lx + 1.6 * font, y + 0.85 * font),), fill=INK, width=font, text=text))
    return shapes


def _scale_bar(scene: Scene, origin: Point, right: float, k: float, u: float, font: float) -> list[Shape]:
    """A bar a quarter of the arena's width or less, long a round number of units, and the axes' unit
    at the arena's ``right`` edge."""
    length = _nice_length(scene.arena.width / 4)
    (x0, y0), tick = origin, 0.4 * font
    x1 = x0 + k * length
    unit = [
        Shape(
            "text",
            ((right, y0 + 0.35 * font),),
            fill=INK,
            width=font,
            text=f"x, y in {scene.arena.unit}",
            anchor="end",
        )
    ]
    return [
        *(unit if scene.arena.unit else []),
        Shape("line", ((x0, y0), (x1, y0)), stroke=INK, width=2 * u),
        Shape("line", ((x0, y0 - tick), (x0, y0 + tick)), stroke=INK, width=2 * u),
        Shape("line", ((x1, y0 - tick), (x1, y0 + tick)), stroke=INK, width=2 * u),
        Shape(
            "text",
            ((x1 + 0.6 * font, y0 + 0.35 * font),),
            fill=INK,
            width=font,
            text=_with_unit(length, scene.arena.unit),
        ),
    ]


def darker(colour: RGB) -> RGB:
    """The outline of a fill: the same hue, darker."""
    r, g, b = (int(c * 0.6) for c in colour)
    return r, g, b
