"""The bounds of every number in the language, checked at ``mazegen check`` (docs/language.md §10).

A literal longer than :data:`MAX_DIGITS` digits is refused as it is read (it would become
``inf`` as a float, or fail Python's int conversion beyond 4,300 digits); each use then bounds
its value, so nothing unbounded or non-finite reaches the generator, the arrays or the kernels.
"""

from __future__ import annotations

from typing import Any

from mazegen.dsl.located import fail

MAX_DIGITS = 20
"""Digits before the decimal point of any number (the largest seed has 19)."""

MAX_LENGTH = 1_000_000
"""Lengths in arena units: arena sides, element sizes, heights, thicknesses, radii, size limits."""

MAX_WEIGHT = 1_000_000
"""Weights of fitness terms."""

MAX_TARGET = 1_000_000_000
"""The upper end of a target range (difficulty scores and path metrics)."""

MAX_ANGLE = 360
"""Rotation angles lie within -MAX_ANGLE..MAX_ANGLE degrees."""

MAX_CORNERS = 64
"""Sides of a regular polygon, points of an outline, bars of a figure: each becomes vertices
every element of that type carries through the geometry kernels."""

MAX_TERMINALS = 10_000
"""Values of a ``sizes`` or ``positions`` range: each becomes an alternative of the grammar."""

MAX_SLOTS = 1000
"""Element slots per floor: every individual carries this many placement rows, and the overlap
test keeps a list of every pair, so the count is bounded to keep memory in reason."""


def digits_before_point(text: str) -> int:
    """How many digits a number literal has before its decimal point."""
    return len(text.lstrip("+-").partition(".")[0])


def at_most(obj: Any, value: float, bound: float, what: str) -> None:
    """Fail at ``obj`` when ``value`` is above ``bound`` (lower bounds are checked by each use)."""
    if value > bound:
        fail(obj, f"{what} must be at most {bound:.15g}, got {value:.15g}")
