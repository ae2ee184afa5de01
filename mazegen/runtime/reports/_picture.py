"""The picture of a scenario document as drawing primitives in image pixels.

:mod:`mazegen.runtime.reports._render` writes these primitives as SVG or PNG, so both show
the same thing: the arena (y up, flipped to the image's y down) with axes in the
arena unit, the walls of the map the floor is built on (dark grey, under the elements), every element
as one semi-opaque shape in its colour (the outline of its parts,
:func:`mazegen.runtime.reports._scene.outline`), the robot's path when the document has one or a
"no path" mark when its metrics say there is none, each driven controller's trajectory as a line
in its own colour (an × where it collided, a square where it ran out of time), the start and goal
as circles of the robot radius, a title, a legend with a count per element type, the path and
each controller, and a scale bar (:mod:`mazegen.runtime.reports._guides`). What is drawn
inside the arena belongs to a group clipped to the arena's frame, so that large
elements never cover the title, legend, axes or scale bar.
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Any

from mazegen.errors import MazeError
from mazegen.runtime.reports._guides import axes, legend, longest_label, scale_bar
from mazegen.runtime.reports._scene import (
    FILL_OPACITY,
    GOAL_COLOUR,
    INK,
    MARKER_OPACITY,
    NO_PATH_COLOUR,
    PAPER,
    PATH_COLOUR,
    START_COLOUR,
    WALL_COLOUR,
    WHITE,
    ZONE_COLOURS,
    ZONE_OPACITY,
    Element,
    Picture,
    Point,
    Scene,
    Shape,
    darker,
    end_mark,
    label,
)

_MIN_FONT = 10.0  # pixels: small pictures (the report's thumbnails) stay readable


def layout(scene: Scene, pixels: int) -> Picture:
    """Lay the picture out, ``pixels`` along its longer side."""
    if pixels < 100:
        raise MazeError(f"a drawing needs at least 100 pixels, not {pixels}")
    u = pixels / 800
    font = max(13 * u, _MIN_FONT)
    pad, side, tick = 12 * u, 200 / 13 * font, 0.4 * font
    row, title_h = 1.6 * font, pad + 1.8 * font
    char = 0.6 * font  # the width of a digit, about
    digits = longest_label(scene.arena.height)
    ox, oy = pad + tick + 0.3 * font + digits * char, title_h + 0.5 * font
    bottom_h = tick + 1.3 * font + 2.4 * font + pad  # tick labels, then the scale bar
    gap = pad + 3 * char  # room for the last x tick label's right half
    k = min(
        (pixels - ox - gap - side - pad) / scene.arena.width, (pixels - oy - bottom_h) / scene.arena.height
    )
    types = Counter(e.kind for e in scene.elements)
    max_rows = int((pixels - title_h - pad) / row)
    width = round(ox + k * scene.arena.width + gap + side + pad)
    # the map, the zones' rules, types, start, goal, path, controllers
    legend_rows = (
        bool(scene.map_source)
        + len({zone.rule for zone in scene.zones})
        + len(types)
        + 2
        + bool(scene.path or scene.unsolvable)
        + len(scene.drives)
    )
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
        *axes(scene, at, k, u, font, tick),
        *legend(scene, types, (width - pad - side, title_h), side, max_rows, u, font),
        *scale_bar(scene, (ox, oy + k * scene.arena.height + tick + 3.2 * font), frame[1][0], k, u, font),
    ]
    return Picture(width, height, frame, tuple(shapes))


def _arena_contents(scene: Scene, at: Any, k: float, u: float, font: float) -> list[Shape]:
    """The zones, the map's walls, the elements, the path or the "no path" mark, the trajectories, start and
    goal, and the marks of how the drives ended: the clipped groups."""
    shapes = [
        Shape(
            "polygon",
            tuple(at(p) for p in zone.outline),
            ZONE_COLOURS[zone.rule],
            darker(ZONE_COLOURS[zone.rule]),
            ZONE_OPACITY,
            1.5 * u,
            group="zones",
        )
        for zone in scene.zones
    ]
    shapes += [
        Shape(
            "text",
            (at(zone.outline[0]),),
            fill=darker(ZONE_COLOURS[zone.rule]),
            width=0.8 * font,
            text=zone.name,
            group="zones",
        )
        for zone in scene.zones
    ]
    shapes += [
        Shape("rect", (at((x0, y1)), at((x1, y0))), fill=WALL_COLOUR, group="walls")
        for (x0, y0), (x1, y1) in scene.walls
    ]
    shapes += [_element(element, at, u) for element in scene.elements]
    if scene.path:
        shapes.append(
            Shape(
                "polyline",
                tuple(at(p) for p in scene.path),
                stroke=PATH_COLOUR,
                width=2.5 * u,
                group="elements",
            )
        )
    shapes += _trajectories(scene, at, u)
    radius = max(3.0, k * scene.arena.robot_radius)
    shapes += _other_tasks(scene, at, 0.6 * radius, u, font)
    for point, colour in ((scene.arena.start, START_COLOUR), (scene.arena.goal, GOAL_COLOUR)):
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
    shapes += _endings(scene, at, radius, u)
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


def _element(element: Element, at: Any, u: float) -> Shape:
    """An element as one shape: a polygon, or a path of rings when its outline has several (parts
    apart, or a hole)."""
    rings = tuple(tuple(at(p) for p in ring) for ring in element.outline)
    fill, stroke = element.colour, darker(element.colour)
    if len(rings) == 1:
        return Shape("polygon", rings[0], fill, stroke, FILL_OPACITY, u, group="elements")
    return Shape("path", (), fill, stroke, FILL_OPACITY, u, group="elements", rings=rings)


def _endings(scene: Scene, at: Any, size: float, u: float) -> list[Shape]:
    """The mark of how each drive ended, of the robot's size in the controller's colour, over start
    and goal: an × where it collided, a square where it ran out of time."""
    shapes = []
    for drive in scene.drives:
        if drive.ending is not None:
            kind, point = drive.ending
            shapes += end_mark(kind, at(point), size, drive.colour, 3 * u, group="drive")
    return shapes


def _other_tasks(scene: Scene, at: Any, radius: float, u: float, font: float) -> list[Shape]:
    """The tasks after the first of a floor of several: each path thinner than the first's, each
    start and goal a smaller marker, a "no path" mark where a task has none."""
    shapes = []
    for task in scene.tasks:
        if task.path:
            points = tuple(at(p) for p in task.path)
            shapes.append(Shape("polyline", points, stroke=PATH_COLOUR, width=1.2 * u, group="elements"))
        for point, colour in ((task.start, START_COLOUR), (task.goal, GOAL_COLOUR)):
            circle = Shape(
                "circle", (at(point),), colour, darker(colour), MARKER_OPACITY, u, radius, group="elements"
            )
            shapes.append(circle)
        if task.unsolvable:
            shapes += _no_path_mark(at(task.start), at(task.goal), u, font)
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
        shapes.append(Shape("line", ends, stroke=NO_PATH_COLOUR, width=2.5 * u, group="no-path"))
    mx, my = (start[0] + goal[0]) / 2, (start[1] + goal[1]) / 2
    half = 2.6 * font
    box = ((mx - half, my - 0.9 * font), (mx + half, my + 0.7 * font))
    return [
        *shapes,
        Shape("rect", box, WHITE, NO_PATH_COLOUR, 0.9, 1.5 * u, group="no-path"),
        Shape(
            "text",
            ((mx, my + 0.35 * font),),
            fill=NO_PATH_COLOUR,
            width=font,
            text="no path",
            anchor="middle",
            group="no-path",
        ),
    ]
