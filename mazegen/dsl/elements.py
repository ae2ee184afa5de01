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
from mazegen.spec import Arena, ElementType, Part, Zone

_COLOUR = re.compile(r"#[0-9a-fA-F]{3}|#[0-9a-fA-F]{6}|[a-zA-Z]{3,20}")

PROPERTY_LABELS = {"StepProperty": "at step", "WallProperty": "against wall"}
"""How messages name the element properties of two words."""


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


def length_range(obj: Any, what: str) -> tuple[float, float]:
    """A positive range ``LOW..HIGH`` (or one length) of lengths, within the largest length."""
    low = obj.low
    high = low if obj.high is None else obj.high
    check_range(obj, low, high, what)
    at_most(obj, high, MAX_LENGTH, what)
    return (low, high)


def range_step(obj: Any, what: str) -> float | None:
    """The ``step S`` of a range ``LOW..HIGH step S``, positive and within the largest length."""
    if obj.step is None:
        return None
    if obj.step <= 0:
        fail(obj, f"{what} step must be positive, got {obj.step:g}")
    at_most(obj, obj.step, MAX_LENGTH, f"{what} step")
    return obj.step


def _angles(obj: Any, angles: tuple[float, ...]) -> None:
    for angle in angles:
        if abs(angle) > MAX_ANGLE:
            fail(obj, f"rotation angles must be within -{MAX_ANGLE}..{MAX_ANGLE}, got {angle:g}")


def rotation_of(prop: Any | None) -> dict[str, Any]:
    """The ``rotations`` or ``rotation_range`` a ``rotation`` property gives (none: nothing)."""
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
    props = single_properties(decl.properties, what, labels=PROPERTY_LABELS)
    if "ShapeProperty" not in props:
        fail(decl, f"{what} has no shape (add e.g. 'shape rect')")
    if "SizeProperty" not in props:
        fail(decl, f"{what} has no size (add e.g. 'size 20..60')")
    shape = props["ShapeProperty"].shape
    size_prop = props["SizeProperty"]
    size = length_range(size_prop.size, "size")
    size2 = None
    extras: dict[str, Any] = rotation_of(props.get("RotationProperty"))
    extras["size_step"] = range_step(size_prop.size, "size")
    if shape.kind == "rect":
        if size_prop.depth is None:
            fail(size_prop, f"{what} is a rect: give 'size WIDTH x DEPTH', e.g. 'size 10..20 x 100..300'")
        size2 = length_range(size_prop.depth, "depth")
        extras["depth_step"] = range_step(size_prop.depth, "depth")
    elif size_prop.depth is not None:
        fail(size_prop.depth, f"only a rect takes a depth; {what} is a {shape.kind}")
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


def smallest_outline(element: ElementType) -> list[tuple[float, float]]:
    """The vertices of ``element`` at its smallest size, in its own frame (before rotation)."""
    sx = element.size[0]
    sy = sx if element.size2 is None else element.size2[0]
    return [
        (ux * sx + ox, uy * sy + oy)
        for part in element.parts
        for (ux, uy), (ox, oy) in zip(part.unit, part.offset)
    ]


def across(points: list[tuple[float, float]]) -> float:
    """The longest distance between two of ``points``: their extent in any rotation."""
    return max(math.dist(p, q) for p, q in itertools.combinations(points, 2))


def check_fits(decl: Any, element: ElementType, arena: Arena) -> None:
    """Fail at an element's declaration when even its smallest size cannot lie wholly inside ``arena``
    (two of its points farther apart than the arena's corners): sizes meant in another unit, such as
    a library in cm under an arena in m; likewise for the zones that hold it."""
    width, diagonal = across(smallest_outline(element)), math.hypot(arena.width, arena.height)
    unit = arena.unit
    if width > diagonal:
        fail(
            decl,
            f"element '{element.name}' can never fit inside arena '{arena.name}' "
            f"({arena.width:g} x {arena.height:g} {unit}): at its smallest size it is {width:.4g} {unit} "
            f"across, the arena's diagonal {diagonal:.4g} {unit} (are its sizes in another unit?)",
        )
    holding = arena.holding(element.name)
    widest = max((math.dist(*_box_corners(z.outline)) for z in holding), default=math.inf)
    if width > widest:
        fail(
            decl,
            f"element '{element.name}' can never fit inside the zones that hold it ({zone_names(holding)}): "
            f"at its smallest size it is {width:.4g} {unit} across, the widest zone's diagonal "
            f"{widest:.4g} {unit}",
        )


def zone_names(zones: tuple[Zone, ...]) -> str:
    """``'racks', 'yard'``: the zones' names as messages give them."""
    return ", ".join(f"'{zone.name}'" for zone in zones)


def _box_corners(outline: tuple[tuple[float, float], ...]) -> tuple[tuple[float, float], tuple[float, float]]:
    xs, ys = [x for x, _ in outline], [y for _, y in outline]
    return (min(xs), min(ys)), (max(xs), max(ys))


def in_arena_units(element: ElementType, factor: float) -> ElementType:
    """``element`` with its lengths (sizes and their steps, bar thicknesses, height) multiplied by
    ``factor``: declared in a file whose ``units`` differ from the arena's."""
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
        size_step=None if element.size_step is None else element.size_step * factor,
        depth_step=None if element.depth_step is None else element.depth_step * factor,
    )
