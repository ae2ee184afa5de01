"""What a picture shows around the arena: coordinates along its edges, the legend and a scale bar.

:func:`mazegen.runtime.reports._picture.layout` places them; lengths are in image pixels (``u`` of
them per 800th of the picture, text ``font`` pixels high), positions through ``at``, which takes an
arena point to the image.
"""

from __future__ import annotations

import itertools
import math
from collections import Counter
from typing import Any

from mazegen.runtime.reports._scene import (
    ENDINGS,
    FILL_OPACITY,
    GOAL_COLOUR,
    INK,
    MARKER_OPACITY,
    NO_PATH_COLOUR,
    PATH_COLOUR,
    RGB,
    START_COLOUR,
    WALL_COLOUR,
    ZONE_COLOURS,
    ZONE_OPACITY,
    Point,
    Scene,
    Shape,
    darker,
    end_mark,
    label,
)


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


def longest_label(length: float) -> int:
    """Characters of the longest tick label along an axis of ``length`` units (about: the last one)."""
    return len(_coordinate(length, _nice_length(length / 20)))


def _coordinate(value: float, step: float) -> str:
    """A tick's label: as many decimals as the step needs, or three digits and an exponent when long."""
    text = f"{value:.{_decimals(step)}f}"
    return text if len(text) <= 8 else f"{value:.3g}"


def axes(scene: Scene, at: Any, k: float, u: float, font: float, tick: float) -> list[Shape]:
    """Ticks and coordinates along the arena's bottom (x) and left (y) edges."""
    shapes = []
    longest = longest_label(scene.arena.width) * 0.6 * font
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


def legend(
    scene: Scene, types: Counter[str], corner: Point, side: float, max_rows: int, u: float, font: float
) -> list[Shape]:
    """The map the floor is built on, a row per zone rule (its zones' names), one row per element type
    (sorted), then start, goal, the path
    (or "no path") and each controller: a line in its colour, ending in the mark its drive ended with
    (:data:`ENDINGS`)."""
    colours = {e.kind: e.colour for e in reversed(scene.elements)}
    chars = int((side - 2 * font) / (0.6 * font))
    entries: list[tuple[str, str, RGB]] = []
    if scene.map_source:
        entries.append(("rect", label(f"map {scene.map_source}", chars), WALL_COLOUR))
    for rule in ("clear", "accepts", "holds"):  # one row per rule: which zones follow it
        names = [zone.name for zone in scene.zones if zone.rule == rule]
        if names:
            words = "keep clear" if rule == "clear" else rule
            entries.append(("zone", label(f"{words}: {', '.join(names)}", chars), ZONE_COLOURS[rule]))
    entries += [
        ("rect", f"{label(kind, chars - len(str(count)) - 3)} ({count})", colours[kind])
        for kind, count in sorted(types.items())
    ]
    ends = ("starts", "goals") if scene.tasks else ("start", "goal")
    entries += [("circle", ends[0], START_COLOUR), ("circle", ends[1], GOAL_COLOUR)]
    if scene.path:
        travelled = sum(math.dist(a, b) for a, b in itertools.pairwise(scene.path))
        first = "first task's path" if scene.tasks else "path"
        entries.append(("line", f"{first} ({_with_unit(travelled, scene.arena.unit)})", PATH_COLOUR))
    elif scene.unsolvable:
        entries.append(("line", "no path", NO_PATH_COLOUR))
    entries += [
        (drive.ending[0] if drive.ending else "line", f"{drive.controller}: {drive.outcome}", drive.colour)
        for drive in scene.drives
    ]
    if len(entries) > max_rows:
        hidden = len(entries) - max_rows + 1
        entries = [*entries[: max_rows - 1], ("none", f"+{hidden} more", INK)]
    lx, top = corner
    shapes = []
    for i, (swatch, text, colour) in enumerate(entries):
        y = top + i * 1.6 * font
        if swatch in ("rect", "zone"):
            opacity = ZONE_OPACITY if swatch == "zone" else FILL_OPACITY
            shapes.append(Shape("rect", ((lx, y), (lx + font, y + font)), colour, darker(colour), opacity, u))
        elif swatch == "circle":
            centre = (lx + font / 2, y + font / 2)
            shapes.append(Shape("circle", (centre,), colour, darker(colour), MARKER_OPACITY, u, font / 2))
        elif swatch == "line" or swatch in ENDINGS:
            end = (lx + font, y + font / 2)
            shapes.append(Shape("line", ((lx, y + font / 2), end), stroke=colour, width=2.5 * u))
            if swatch in ENDINGS:
                shapes += end_mark(swatch, end, 0.3 * font, colour, 1.5 * u)
        shapes.append(Shape("text", ((lx + 1.6 * font, y + 0.85 * font),), fill=INK, width=font, text=text))
    return shapes


def scale_bar(scene: Scene, origin: Point, right: float, k: float, u: float, font: float) -> list[Shape]:
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
