"""What the picture of a scenario document shows, read from the document, and the drawing primitives
(:class:`Shape`) it is laid out in (:mod:`mazegen.runtime.reports._picture`).

An element is drawn by its outline: the union of its convex parts, so that a non-convex element
(an L, a frame) is one shape, without seams or darker overlaps where its parts meet. A drive ends
in a mark of how it ended: an × where the robot collided, a square where it ran out of time. A floor
built on a map shows the map's walls under its elements; the document names the map, the spec
holds its cells, so its picture is drawn with the spec's map (:func:`parse`'s ``base``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import shapely
from PIL import ImageColor

from mazegen.errors import MazeError
from mazegen.maps import base_digest, wall_boxes
from mazegen.spec import Arena, BaseMap
from mazegen.text import quoted

Point = tuple[float, float]
RGB = tuple[int, int, int]

DEFAULT_COLOUR: RGB = (85, 85, 85)
WALL_COLOUR: RGB = (61, 61, 61)
"""A base map's walls: the dark grey of the bundled walls (``vwall``)."""
START_COLOUR: RGB = (44, 160, 44)
GOAL_COLOUR: RGB = (214, 39, 40)
PATH_COLOUR: RGB = (230, 0, 126)  # magenta: no bundled element is drawn in it
NO_PATH_COLOUR: RGB = (0, 0, 0)
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
ZONE_COLOURS: dict[str, RGB] = {
    "clear": (229, 115, 115),
    "accepts": (100, 181, 246),
    "holds": (129, 199, 132),
}
"""An arena's zones by rule: keep clear red, accepts blue, holds green (drawn faint, under the walls)."""
ZONE_OPACITY = 0.22
CLIPPED = ("zones", "walls", "elements", "no-path", "drive")
"""The groups drawn inside the arena, clipped to its frame."""
ENDINGS = ("collision", "timeout")
"""The outcomes of a drive whose end is marked (:func:`end_mark`)."""
# Characters XML 1.0 does not allow, even escaped.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


@dataclass(frozen=True)
class Element:
    """An element as drawn: its type, colour and outline (rings filled even-odd, see :func:`outline`)."""

    kind: str
    colour: RGB
    outline: tuple[tuple[Point, ...], ...]


@dataclass(frozen=True)
class Driven:
    """One controller's drive through the floor: its trajectory and where it collided."""

    controller: str
    outcome: str
    colour: RGB
    trajectory: tuple[Point, ...]
    collision: Point | None

    @property
    def ending(self) -> tuple[str, Point] | None:
        """How its end is marked (one of :data:`ENDINGS`, see :func:`end_mark`) and where: at its last
        pose when it ran out of time, where it collided; ``None`` when it arrived."""
        if self.outcome == "timeout" and self.trajectory:
            return "timeout", self.trajectory[-1]
        return None if self.collision is None else ("collision", self.collision)


@dataclass(frozen=True)
class ZoneMark:
    """A zone as drawn: its name, rule (``clear``, ``accepts``, ``holds``), types named and outline."""

    name: str
    rule: str
    types: tuple[str, ...]
    outline: tuple[Point, ...]

    @property
    def words(self) -> str:
        """The rule as the language writes it (``holds shelfRack``)."""
        return "keep clear" if self.rule == "clear" else f"{self.rule} {', '.join(self.types)}"


@dataclass(frozen=True)
class TaskMark:
    """One task of a floor of several, as the picture shows it: its ends, its path, or no path."""

    start: Point
    goal: Point
    path: tuple[Point, ...]
    unsolvable: bool


@dataclass(frozen=True)
class Scene:
    """What the picture shows of a scenario document.

    ``map_source`` names the map the floor is built on ("" for none), and ``walls`` are its walls:
    disjoint rectangles, each its lower-left and upper-right corners; ``zones`` the arena's zones;
    ``tasks`` the tasks after the first of a floor of several (the first is ``arena``'s start and
    goal, ``path`` and ``unsolvable``).
    """

    name: str
    arena: Arena
    elements: tuple[Element, ...]
    fitness: str
    path: tuple[Point, ...]
    unsolvable: bool
    drives: tuple[Driven, ...] = ()
    map_source: str = ""
    walls: tuple[tuple[Point, Point], ...] = ()
    zones: tuple[ZoneMark, ...] = ()
    tasks: tuple[TaskMark, ...] = ()

    @property
    def title(self) -> str:
        return f"{self.name} | {len(self.elements)} elements | fitness {self.fitness}"


@dataclass(frozen=True)
class Shape:
    """One drawing primitive in image pixels (y down).

    ``points`` holds two corners for a rect, the centre for a circle, the ends of
    a line, every vertex of a polygon or polyline and the anchor point of a text
    (on its baseline; ``anchor`` says whether it starts, centres or ends the text).
    A path has ``rings`` instead, filled even-odd: a hole inside a ring is not filled.
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
    rings: tuple[tuple[Point, ...], ...] = ()


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


def parse(doc: dict, base: BaseMap | None = None) -> Scene:
    """Read the parts of a scenario document that the picture needs; ``base`` is the map the floor is
    built on, from its spec (the document names it, see :func:`_walls`)."""
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
            elements.append(Element(label(element["type"], 40), rgb(element.get("colour")), outline(parts)))
        fitness = doc.get("fitness")
        path = doc.get("path") or ()
        tasks = _tasks(arena.get("tasks", ()), doc.get("tasks", ()))
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
            unsolvable=tasks[0].unsolvable
            if tasks
            else isinstance(metrics, dict) and metrics.get("solvable") is False,
            drives=_drives(doc.get("drive")),
            map_source=label(base.source) if base is not None else "",
            walls=_walls(arena.get("map"), base),
            zones=tuple(
                ZoneMark(
                    label(zone["name"], 40),
                    zone["rule"] if zone["rule"] in ZONE_COLOURS else "clear",
                    tuple(label(t, 40) for t in zone["types"]),
                    tuple(_point(p) for p in zone["outline"]),
                )
                for zone in arena.get("zones", ())
            ),
            tasks=tuple(tasks[1:]),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as exc:  # AttributeError: a drive not an object
        raise MazeError(f"bad scenario document: {exc!r}") from exc


def _tasks(tasks: list, measured: list) -> list[TaskMark]:
    """The tasks of a document's ``arena.tasks`` with their paths and solvability (its ``tasks``)."""
    marks = []
    for k, task in enumerate(tasks):
        found = measured[k] if k < len(measured) else {}
        path = found.get("path") or ()
        metrics = found.get("metrics")
        marks.append(
            TaskMark(
                _point(task["start"]),
                _point(task["goal"]),
                tuple(_point(p) for p in path) if len(path) >= 2 else (),
                isinstance(metrics, dict) and metrics.get("solvable") is False,
            )
        )
    return marks


def _walls(recorded: dict | None, base: BaseMap | None) -> tuple[tuple[Point, Point], ...]:
    """The walls of ``base``, checked to be the map the document's ``arena.map`` names (``recorded``).

    Raises:
        MazeError: When the document names a map and no ``base`` is given (the picture would not show
            its walls), or ``base`` is another map than the document's, or the document names none.
    """
    if base is None:
        if recorded is None:
            return ()
        raise MazeError(
            f"the floor is built on map {quoted(str(recorded['source']))}: its picture needs its spec "
            "(give --spec SPEC.maze, or draw it from its run folder)"
        )
    if recorded is None or recorded["cells"] != base_digest(base):
        named = (
            "no map" if recorded is None else f"map {quoted(str(recorded['source']))} ({recorded['cells']})"
        )
        raise MazeError(
            f"the floor is built on {named}; the spec's map is {quoted(base.source)} ({base_digest(base)})"
        )
    return tuple(((x0, y0), (x1, y1)) for x0, y0, x1, y1 in wall_boxes(base))


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


def outline(parts: tuple[tuple[Point, ...], ...]) -> tuple[tuple[Point, ...], ...]:
    """The rings of the union of an element's convex parts: each piece's boundary, then its holes.

    Filled even-odd they cover every part once. One part is its own outline; parts whose union
    covers nothing (every vertex on a line) stay as they are, drawn as their outlines.
    """
    if len(parts) == 1:
        return parts
    union = shapely.union_all([shapely.make_valid(shapely.Polygon(part)) for part in parts])
    union = shapely.simplify(union, 0)  # without the vertices where parts met along an edge
    pieces = shapely.get_parts(shapely.get_parts(union))  # a collection of a polygon and a line, too
    rings = [
        tuple(ring.coords[:-1])  # shapely repeats the first vertex at the end
        for piece in pieces
        if piece.geom_type == "Polygon" and not piece.is_empty
        for ring in (piece.exterior, *piece.interiors)
    ]
    return tuple(rings) or parts


def end_mark(
    outcome: str, centre: Point, size: float, colour: RGB, width: float, group: str = ""
) -> list[Shape]:
    """The mark of how a drive ended, ``size`` pixels from ``centre`` to each side, in its colour: a
    square where it ran out of time (``timeout``), an × where it collided."""
    x, y = centre
    if outcome == "timeout":
        corners = ((x - size, y - size), (x + size, y + size))
        return [Shape("rect", corners, stroke=colour, width=width, group=group)]
    return [
        Shape("line", ((x - a, y - size), (x + a, y + size)), stroke=colour, width=width, group=group)
        for a in (size, -size)
    ]


def darker(colour: RGB) -> RGB:
    """The outline of a fill: the same hue, darker."""
    r, g, b = (int(c * 0.6) for c in colour)
    return r, g, b
