"""``exactly N TYPE`` and ``at least N TYPE`` in a scenario block: elements every floor has, checked
against the scenario's elements, its grammar and its slots."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from mazegen.dsl.located import fail, where

REQUIRED_PROPERTY = "RequiredProperty"


def required_counts(
    props: list[Any], names: list[str], style: str, max_elements: int, rows: Mapping[str, Any]
) -> tuple[tuple[str, int, bool], ...]:
    """The ``(name, count, exactly)`` of a scenario's ``exactly`` and ``at least`` properties (``names``:
    its ``elements`` list, element types and ``rows``; a row may be required as an element is)."""
    found: dict[str, Any] = {}
    for prop in props:
        name = prop.element.name
        if name not in names:
            fail(prop.element, f"'{name}' is not an element of this scenario (elements {', '.join(names)})")
        adding = [row for row in names if row in rows and rows[row].member == name]
        if prop.exactly and adding:
            fail(
                prop, f"'{name}' is required exactly, and row '{adding[0]}' adds more of it: write 'at least'"
            )
        if name in found:
            fail(prop, f"'{name}' is required twice (first at {where(found[name])})")
        if prop.count < 1:
            fail(prop, f"a required count must be at least 1, got {prop.count}")
        if style == "custom":
            fail(
                prop,
                "a custom grammar says itself what a floor holds: required elements need a generated one",
            )
        found[name] = prop
    required = tuple((name, int(prop.count), bool(prop.exactly)) for name, prop in found.items())
    total = sum(count for _, count, _ in required)
    if total > max_elements:
        fail(
            props[-1],
            f"{total} elements are required and a floor holds at most {max_elements} (max elements)",
        )
    return required
