"""``zone NAME rect|polygon ... keep clear | accepts T, ... | holds T, ...`` in an arena block: named
areas and their rule for the elements, checked against the arena and the declared elements."""

from __future__ import annotations

from typing import Any

from mazegen.dsl.located import fail, suggestion, where
from mazegen.dsl.shapes import polygon_parts
from mazegen.spec import Point, Zone

RULES = {"keep": "clear", "accepts": "accepts", "holds": "holds"}
"""The language's word for each rule of :data:`mazegen.spec.ZONE_RULES`."""


def convert_zones(props: list[Any], width: float, height: float) -> tuple[Zone, ...]:
    """The zones of one arena block (``props``, its ``zone`` properties) of a ``width x height`` arena."""
    zones: dict[str, Zone] = {}
    first: dict[str, Any] = {}
    for prop in props:
        if prop.name in zones:
            fail(prop, f"duplicate zone '{prop.name}' (first given at {where(first[prop.name])})")
        outline = _outline(prop.area)
        try:
            parts = polygon_parts(outline)
        except ValueError as error:
            fail(prop.area, f"zone '{prop.name}': {error}")
        beyond = [p for p in outline if not (0 <= p[0] <= width and 0 <= p[1] <= height)]
        if beyond:
            x, y = beyond[0]
            fail(
                prop.area,
                f"zone '{prop.name}' reaches beyond the arena {width:g} x {height:g} at ({x:g}, {y:g})",
            )
        types = tuple(getattr(prop.rule, "types", ()))
        zones[prop.name] = Zone(
            prop.name, RULES[prop.rule.kind], _ccw(outline), _world(outline, parts), types
        )
        first[prop.name] = prop
    return tuple(zones.values())


def check_zone_types(props: list[Any], declared: set[str], rows: dict[str, str]) -> None:
    """Fail at a zone naming an element type that is not declared, or a row (``rows``: each row's
    members' type, by the row's name)."""
    for prop in props:
        for name in getattr(prop.rule, "types", ()):
            if name in rows:
                fail(
                    prop.rule, f"zone '{prop.name}': '{name}' is a row: name its members' type '{rows[name]}'"
                )
            if name not in declared:
                fail(prop.rule, f"zone '{prop.name}': unknown element '{name}'{suggestion(name, declared)}")


def _outline(area: Any) -> list[Point]:
    if area.kind == "rect":
        (x0, y0), (x1, y1) = (area.low.x, area.low.y), (area.high.x, area.high.y)
        if not (x0 < x1 and y0 < y1):
            corners = f"({x0:g}, {y0:g}) ({x1:g}, {y1:g})"
            fail(area, f"a zone's rect goes from its lower-left corner to its upper-right, got {corners}")
        return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return [(p.x, p.y) for p in area.points]


def _ccw(outline: list[Point]) -> tuple[Point, ...]:
    area = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(outline, outline[1:] + outline[:1]))
    return tuple(outline if area > 0 else outline[::-1])


def _world(outline: list[Point], parts: tuple[Any, ...]) -> tuple[tuple[Point, ...], ...]:
    """The convex parts :func:`polygon_parts` gives (normalised: bounding box centred, longest side 1)
    moved back onto the arena."""
    xs, ys = [p[0] for p in outline], [p[1] for p in outline]
    span = max(max(xs) - min(xs), max(ys) - min(ys))
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2
    return tuple(tuple((ux * span + cx, uy * span + cy) for ux, uy in part.unit) for part in parts)
