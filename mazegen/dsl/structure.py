"""Structure on the floor: elements on a step and against a wall (``at step 50 cm``, ``against wall``),
and rows, elements of one type in a line (``row rackRow of shelfRack { count 2..6  spacing 120..150 }``),
checked and put into arena units."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from mazegen.dsl.bounds import MAX_LENGTH, MAX_SLOTS, at_most
from mazegen.dsl.elements import (
    PROPERTY_LABELS,
    across,
    length_range,
    range_step,
    rotation_of,
    smallest_outline,
    zone_names,
)
from mazegen.dsl.located import check_range, fail, single_properties, suggestion
from mazegen.spec import (
    METRES_PER_UNIT,
    WALL_ROTATIONS,
    Arena,
    Box,
    ElementType,
    Point,
    Row,
    Scenario,
    placing_area,
    step_span,
    walls_reached,
)

GENE_VALUES = 65536
"""The values of a placement gene: the most step positions a side may have, so that each can be drawn."""


@dataclass(frozen=True)
class Lengths:
    """How one file's lengths become arena units: those written without a unit are in the file's
    ``units`` (times ``factor``), those that name theirs are converted into ``arena``'s unit (no arena: a
    library checked on its own, whose lengths are only checked)."""

    factor: float = 1.0
    arena: Arena | None = None

    def convert(self, obj: Any, value: float, unit: str | None, what: str) -> float:
        """``value``, of the textX object ``obj``, written in ``unit`` (or the file's), in arena units."""
        arena = self.arena
        if unit is None:
            factor = self.factor
        elif arena is None or unit == arena.unit:
            factor = 1.0
        elif unit not in METRES_PER_UNIT or arena.unit not in METRES_PER_UNIT:
            fail(
                obj,
                f"{what} {value:g} {unit} cannot be converted into {arena.unit}, the unit of arena "
                f"'{arena.name}': px has no size in metres (write it in {arena.unit}, or without a unit)",
            )
        else:
            factor = METRES_PER_UNIT[unit] / METRES_PER_UNIT[arena.unit]
        at_most(obj, value * factor, MAX_LENGTH, what)
        return value * factor


def place_element(decl: Any, element: ElementType, lengths: Lengths) -> ElementType:
    """``element`` (its lengths in arena units) on its step and against its wall, as ``decl`` says."""
    props = {type(prop).__name__: prop for prop in decl.properties}  # each once: convert_element checks
    changes: dict[str, Any] = {}
    step = props.get("StepProperty")
    if step is not None:
        if step.step <= 0:
            fail(step, f"step must be positive, got {step.step:g}")
        changes["position_step"] = lengths.convert(step, step.step, step.unit, "step")
    if "WallProperty" in props:
        changes["against_wall"] = True
        changes["rotations"] = wall_rotations(props.get("RotationProperty"), WALL_ROTATIONS)
    return dataclasses.replace(element, **changes)


def wall_rotations(prop: Any | None, default: tuple[float, ...]) -> tuple[float, ...]:
    """The rotations a ``rotation`` property gives an element (or a row) against a wall, each naming the
    wall its back turns to (:data:`~mazegen.spec.WALL_ROTATIONS`); ``default`` without one."""
    if prop is None:
        return default
    if prop.free or prop.range is not None:
        given = "any" if prop.free else f"{prop.range.low:g}..{prop.range.high:g}"
    else:
        given = next((f"{angle:g}" for angle in prop.angles if angle % 90), "")
    if given:
        fail(
            prop,
            "against a wall, a rotation says which wall the back turns to: give multiples of 90 "
            f"(0 bottom, 90 right, 180 top, 270 left), not {given}",
        )
    return tuple(float(angle) for angle in prop.angles)


def check_row_members(row_decls: dict[str, Any], element_decls: dict[str, Any]) -> None:
    """Fail at a row whose members are of no declared element type."""
    for decl in row_decls.values():
        if decl.member in row_decls:
            fail(decl, f"row '{decl.name}' is of row '{decl.member}': a row's members are elements")
        if decl.member not in element_decls:
            hint = suggestion(decl.member, element_decls)
            fail(decl, f"row '{decl.name}' of unknown element '{decl.member}'{hint}")


def convert_row(decl: Any, member: ElementType, lengths: Lengths) -> Row:
    """Check one ``row`` block and convert it; ``member`` is its members' type (in arena units)."""
    what = f"row '{decl.name}'"
    props = single_properties(decl.properties, what)
    for key, example in (("CountProperty", "count 2..6"), ("SpacingProperty", "spacing 50..100")):
        if key not in props:
            fail(decl, f"{what} has no {example.split()[0]} (add e.g. '{example}')")
    count = props["CountProperty"]
    fewest, most = count.low, count.low if count.high is None else count.high
    check_range(count, fewest, most, "count", positive=False)
    if fewest < 2:
        fail(count, f"a row has at least 2 members, got {fewest}")
    if most > MAX_SLOTS:
        fail(count, f"a row has at most {MAX_SLOTS} members (the most elements a floor holds), got {most}")
    spacing = props["SpacingProperty"]
    low, high = length_range(spacing.spacing, "spacing")
    step = range_step(spacing.spacing, "spacing")

    def converted(value: float) -> float:
        return lengths.convert(spacing, value, spacing.unit, "spacing")

    rotation = props.get("RotationProperty")
    turn = rotation_of(rotation) or {"rotations": member.rotations, "rotation_range": member.rotation_range}
    if member.against_wall:
        turn = {"rotations": wall_rotations(rotation, member.rotations)}
    return Row(
        name=decl.name,
        member=member.name,
        count=(fewest, most),
        spacing=(converted(low), converted(high)),
        spacing_step=None if step is None else converted(step),
        **turn,
    )


def check_structure(decl: Any, scenario: Scenario, element_decls: dict[str, Any]) -> None:
    """Fail at the scenario ``decl`` (converted: ``scenario``) when a row of it could never fit in its
    ``max elements``, or it places by its grammar an element or a row that placement genes place."""
    props = {type(prop).__name__: prop for prop in decl.properties}
    for row in scenario.rows:
        if row.count[0] > scenario.max_elements:
            fail(
                props.get("MaxElementsProperty", decl),
                f"scenario '{scenario.name}' holds at most {scenario.max_elements} elements "
                f"('max elements'), and row '{row.name}' has at least {row.count[0]} members",
            )
    if scenario.placement is None:
        return
    placed = [f"row '{row.name}'" for row in scenario.rows] + [
        f"element '{name}' ({PROPERTY_LABELS[kind]})"
        for name in scenario.elements
        for kind in (type(prop).__name__ for prop in element_decls[name].properties)
        if kind in PROPERTY_LABELS
    ]
    if placed:
        fail(
            props["PlacementProperty"],
            f"{placed[0]} is placed by placement genes, and scenario '{scenario.name}' places its elements "
            "by its grammar's numbers (drop 'placement grammar', or the structure)",
        )


def check_placed(decl: Any, element: ElementType, arena: Arena, walls: Box) -> None:
    """Fail at an element's ``at step`` or ``against wall`` when no floor could place it so: no multiple
    of its step where it is placed, more of them than a gene chooses from, or zones that hold it reaching
    none of its walls (the box ``walls``)."""
    props = {type(prop).__name__: prop for prop in decl.properties}
    area, holding, unit = placing_area(arena, element, walls), arena.holding(element.name), arena.unit
    where = f"the zones that hold it ({zone_names(holding)})" if holding else f"arena '{arena.name}'"
    if element.position_step is not None:
        _check_steps(props["StepProperty"], element.name, element.position_step, area, where, unit)
    if element.against_wall and holding and not walls_reached(area, walls, element.rotations):
        angles = ", ".join(f"{angle:g}" for angle in element.rotations)
        fail(
            props["WallProperty"],
            f"element '{element.name}' stands against a wall (rotation {angles}), and {where} reach none "
            "of those walls",
        )


def _check_steps(prop: Any, name: str, step: float, area: Box, where: str, unit: str) -> None:
    """Fail at an ``at step`` that puts no position, or more than a gene chooses from, across ``area``."""
    for low, high in ((area[0], area[2]), (area[1], area[3])):
        count = step_span(low, high, step)[1]
        if count == 0:
            fail(
                prop,
                f"element '{name}' can never stand on its step {step:g} {unit}: no multiple of it lies "
                f"between {low:g} and {high:g} {unit}, across {where}",
            )
        if count > GENE_VALUES:
            fail(
                prop,
                f"step {step:g} {unit} gives {count} positions from {low:g} to {high:g} {unit} across "
                f"{where}; at most {GENE_VALUES}, the values of a placement gene (give a larger step)",
            )


def check_row_fits(decl: Any, row: Row, member: ElementType, arena: Arena) -> None:
    """Fail at a row that can never lie wholly inside ``arena``, or inside the box of the zones that hold
    its members: its fewest members at their smallest size and spacing, turned any way its rotations
    allow (a free rotation: when it is longer than the box's diagonal)."""
    outline = smallest_outline(member)
    xs = [x for x, _ in outline]
    last = (row.count[0] - 1) * (max(xs) - min(xs) + row.spacing[0])  # from the first member to the last
    points = outline + [(x + last, y) for x, y in outline]
    area, holding, unit = arena.area_of(member.name), arena.holding(member.name), arena.unit
    room = (area[2] - area[0], area[3] - area[1])
    where = (
        f"the zones that hold {member.name} ({zone_names(holding)})"
        if holding
        else f"arena '{arena.name}' ({arena.width:g} x {arena.height:g} {unit})"
    )
    smallest = f"at its fewest members ({row.count[0]}), smallest size and spacing it is"
    if row.rotation_range is not None:
        length, diagonal = across(points), math.hypot(*room)
        if length > diagonal:
            box = "the zones' box" if holding else "the arena"
            fail(
                decl,
                f"row '{row.name}' can never fit inside {where}: {smallest} {length:.4g} {unit} across, "
                f"the diagonal of {box} {diagonal:.4g} {unit}",
            )
        return
    boxes = [(angle, *_turned_extent(points, angle)) for angle in row.rotations]
    slack = 1e-9 * max(room)
    if all(width > room[0] + slack or height > room[1] + slack for _, width, height in boxes):
        sizes = ", ".join(
            f"{width:.4g} x {height:.4g} {unit} at rotation {angle:g}" for angle, width, height in boxes
        )
        fail(decl, f"row '{row.name}' can never fit inside {where}: {smallest} {sizes}")


def _turned_extent(points: list[Point], angle: float) -> tuple[float, float]:
    """Width and height of the box around ``points`` turned by ``angle`` degrees."""
    cos, sin = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    xs = [x * cos - y * sin for x, y in points]
    ys = [x * sin + y * cos for x, y in points]
    return max(xs) - min(xs), max(ys) - min(ys)
