"""Element declarations of a ``.maze`` model → :class:`ElementType`."""

from __future__ import annotations

import dataclasses
import itertools
import math
import re
from typing import Any

from mazegen.dsl import shapes
from mazegen.dsl.bounds import MAX_ANGLE, MAX_CORNERS, MAX_LENGTH, at_most
from mazegen.dsl.located import check_range, fail, single_properties
from mazegen.spec import Arena, ElementType, Part

_COLOUR = re.compile(r"#[0-9a-fA-F]{3}|#[0-9a-fA-F]{6}|[a-zA-Z]{3,20}")


def _parts(shape: Any) -> tuple[Part, ...]:
    kind = shape.kind
    try:
        if kind in ("rect", "square"):
            return shapes.rect_parts() if kind == "rect" else shapes.square_parts()
        if kind == "triangle":
            return shapes.triangle_parts()
        if kind == "polygon":
            if not 3 <= shape.sides <= MAX_CORNERS:
                fail(shape, f"a regular polygon has 3 to {MAX_CORNERS} sides, got {shape.sides}")
            return shapes.regular_polygon_parts(shape.sides)
        if kind == "points":
            if len(shape.points) > MAX_CORNERS:
                fail(shape, f"an outline has at most {MAX_CORNERS} points, got {len(shape.points)}")
            _check_points(shape.points)
            return shapes.polygon_parts([(p.x, p.y) for p in shape.points])
        if shape.thickness <= 0:
            fail(shape, f"bar thickness must be positive, got {shape.thickness:g}")
        at_most(shape, shape.thickness, MAX_LENGTH, "bar thickness")
        if len(shape.segments) > MAX_CORNERS:
            fail(shape, f"a bar figure has at most {MAX_CORNERS} bars, got {len(shape.segments)}")
        _check_points([end for s in shape.segments for end in (s.start, s.end)])
        segments = [((s.start.x, s.start.y), (s.end.x, s.end.y)) for s in shape.segments]
        return shapes.bar_parts(segments, shape.thickness)
    except ValueError as error:
        fail(shape, f"bad {kind} shape: {error}")


def _check_points(points: list[Any]) -> None:
    """Keep every point's coordinates within the largest length."""
    for point in points:
        if max(abs(point.x), abs(point.y)) > MAX_LENGTH:
            fail(
                point,
                f"a point's coordinates must be within -{MAX_LENGTH}..{MAX_LENGTH}, "
                f"got ({point.x:.15g}, {point.y:.15g})",
            )


def _range(obj: Any, what: str) -> tuple[float, float]:
    low = obj.low
    high = low if obj.high is None else obj.high
    check_range(obj, low, high, what)
    at_most(obj, high, MAX_LENGTH, what)
    return (low, high)


def _angles(obj: Any, angles: tuple[float, ...]) -> None:
    for angle in angles:
        if abs(angle) > MAX_ANGLE:
            fail(obj, f"rotation angles must be within -{MAX_ANGLE}..{MAX_ANGLE}, got {angle:g}")


def _rotation(prop: Any | None) -> dict[str, Any]:
    if prop is None:
        return {}
    if prop.free:
        return {"rotation_range": (0.0, 360.0)}
    if prop.range is not None:
        check_range(prop.range, prop.range.low, prop.range.high, "rotation", positive=False)
        _angles(prop.range, (prop.range.low, prop.range.high))
        return {"rotation_range": (prop.range.low, prop.range.high)}
    angles = tuple(float(a) for a in prop.angles)
    _angles(prop, angles)
    return {"rotations": angles}


def convert_element(decl: Any) -> ElementType:
    """Check one ``element`` block and convert it."""
    what = f"element '{decl.name}'"
    props = single_properties(decl.properties, what)
    if "ShapeProperty" not in props:
        fail(decl, f"{what} has no shape (add e.g. 'shape rect')")
    if "SizeProperty" not in props:
        fail(decl, f"{what} has no size (add e.g. 'size 20..60')")
    shape = props["ShapeProperty"].shape
    size_prop = props["SizeProperty"]
    size = _range(size_prop.size, "size")
    size2 = None
    if shape.kind == "rect":
        if size_prop.depth is None:
            fail(size_prop, f"{what} is a rect: give 'size WIDTH x DEPTH', e.g. 'size 10..20 x 100..300'")
        size2 = _range(size_prop.depth, "depth")
    elif size_prop.depth is not None:
        fail(size_prop.depth, f"only a rect takes a depth; {what} is a {shape.kind}")
    extras: dict[str, Any] = _rotation(props.get("RotationProperty"))
    if "ColourProperty" in props:
        colour = props["ColourProperty"].colour
        if not _COLOUR.fullmatch(colour):
            fail(props["ColourProperty"], f"bad colour {colour!r} (use #rgb, #rrggbb or a colour name)")
        extras["colour"] = colour
    if "ClassProperty" in props:
        extras["semantic_class"] = props["ClassProperty"].semantic
    if "HeightProperty" in props:
        height = props["HeightProperty"].height
        if height <= 0:
            fail(props["HeightProperty"], f"height must be positive, got {height:g}")
        at_most(props["HeightProperty"], height, MAX_LENGTH, "height")
        extras["height"] = height
    return ElementType(
        name=decl.name, shape=shape.kind, parts=_parts(shape), size=size, size2=size2, **extras
    )


def _smallest_across(element: ElementType) -> float:
    """The longest distance between two points of ``element`` at its smallest size, in any rotation."""
    sx = element.size[0]
    sy = sx if element.size2 is None else element.size2[0]
    points = [
        (ux * sx + ox, uy * sy + oy)
        for part in element.parts
        for (ux, uy), (ox, oy) in zip(part.unit, part.offset)
    ]
    return max(math.dist(p, q) for p, q in itertools.combinations(points, 2))


def check_fits(decl: Any, element: ElementType, arena: Arena) -> None:
    """Fail at an element's declaration when even its smallest size cannot lie wholly inside ``arena``
    (two of its points farther apart than the arena's corners): sizes meant in another unit, such as
    a library in cm under an arena in m; likewise for the zones that hold it."""
    across, diagonal = _smallest_across(element), math.hypot(arena.width, arena.height)
    unit = arena.unit
    if across > diagonal:
        fail(
            decl,
            f"element '{element.name}' can never fit inside arena '{arena.name}' "
            f"({arena.width:g} x {arena.height:g} {unit}): at its smallest size it is {across:.4g} {unit} "
            f"across, the arena's diagonal {diagonal:.4g} {unit} (are its sizes in another unit?)",
        )
    holding = [z for z in arena.zones if z.rule == "holds" and element.name in z.types]
    widest = max((math.dist(*_box_corners(z.outline)) for z in holding), default=math.inf)
    if across > widest:
        names = ", ".join(f"'{z.name}'" for z in holding)
        fail(
            decl,
            f"element '{element.name}' can never fit inside the zones that hold it ({names}): at its "
            f"smallest size it is {across:.4g} {unit} across, the widest zone's diagonal {widest:.4g} {unit}",
        )


def _box_corners(outline: tuple[tuple[float, float], ...]) -> tuple[tuple[float, float], tuple[float, float]]:
    xs, ys = [x for x, _ in outline], [y for _, y in outline]
    return (min(xs), min(ys)), (max(xs), max(ys))


def in_arena_units(element: ElementType, factor: float) -> ElementType:
    """``element`` with its lengths (sizes, bar thicknesses, height) multiplied by ``factor``: declared in
    a file whose ``units`` differ from the arena's."""
    if factor == 1.0:
        return element
    parts = tuple(
        Part(part.unit, tuple((ox * factor, oy * factor) for ox, oy in part.offset)) for part in element.parts
    )
    return dataclasses.replace(
        element,
        parts=parts,
        size=(element.size[0] * factor, element.size[1] * factor),
        size2=None if element.size2 is None else (element.size2[0] * factor, element.size2[1] * factor),
        height=element.height * factor,
    )
