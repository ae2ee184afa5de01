"""Helpers that tie semantic errors to the user's own lines."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable, Mapping
from typing import Any, NoReturn

from textx import get_location

from mazegen.errors import MazeError
from mazegen.text import suggestion as suggestion  # the language's modules import it from here


def display_path(path: str | os.PathLike[str]) -> str:
    """A path as errors show it: relative to the working directory when below it."""
    with contextlib.suppress(ValueError):
        relative = os.path.relpath(path)
        if not relative.startswith(".."):
            return relative
    return os.path.abspath(path)


def _location(obj: Any) -> tuple[str | None, int, int]:
    loc = get_location(obj)
    filename = loc["filename"]
    return (display_path(filename) if filename else None), loc["line"], loc["col"]


def fail(obj: Any, message: str) -> NoReturn:
    """Raise a :class:`MazeError` located at the textX object ``obj``."""
    filename, line, col = _location(obj)
    raise MazeError(message, filename=filename, line=line, col=col)


def where(obj: Any) -> str:
    """``file:line:col`` of a textX object, for messages that point elsewhere."""
    filename, line, col = _location(obj)
    return f"{filename}:{line}:{col}"


def single_properties(
    properties: Iterable[Any], what: str, *, labels: Mapping[str, str] | None = None
) -> dict[str, Any]:
    """Index properties by their textX class (or ``key``), rejecting duplicates.

    Args:
        properties: textX property objects of one block.
        what: Block description used in the message (``element 'cobot'``).
        labels: How the messages name properties of several words, by class (``min speed``).
    """
    found: dict[str, Any] = {}
    for prop in properties:
        key = getattr(prop, "key", None) or type(prop).__name__
        if key in found:
            label = f"'{labels[key]}'" if labels and key in labels else _label(key)
            fail(prop, f"duplicate {label} in {what} (first given at {where(found[key])})")
        found[key] = prop
    return found


def _label(key: str) -> str:
    return "'" + key.removesuffix("Property").removesuffix("Setting").lower() + "'"


def check_range(obj: Any, low: float, high: float, what: str, *, positive: bool = True) -> None:
    """Reject inverted ranges and, optionally, non-positive bounds."""
    if high < low:
        fail(obj, f"empty {what} range {low:g}..{high:g} (low is above high)")
    if positive and low <= 0:
        fail(obj, f"{what} must be positive, got {low:g}")
