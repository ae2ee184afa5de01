"""The ``.maze`` grammar as a textX metamodel, for the loader to parse with.

Apart from :mod:`mazegen.dsl.language` (the textX registration, whose checks call the loader),
so that the loader never imports what imports it.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from textx import metamodel_for_language, metamodel_from_file
from textx.exceptions import TextXRegistrationError, TextXSemanticError

from mazegen.dsl.bounds import MAX_DIGITS, digits_before_point

GRAMMAR_FILE = Path(__file__).with_name("maze.tx")


def grammar_metamodel():
    """The textX metamodel of the ``.maze`` grammar, without MazeGen's semantic checks."""
    metamodel = metamodel_from_file(str(GRAMMAR_FILE), autokwd=True)
    metamodel.register_obj_processors({"Number": _bounded_literal(float), "Integer": _bounded_literal(int)})
    return metamodel


def _bounded_literal(convert: Callable[[str], float]) -> Callable[[str], float]:
    """A converter that refuses a literal too long to be a meaningful number; textX locates the
    error at the literal."""

    def read(text: str) -> float:
        digits = digits_before_point(text)
        if digits > MAX_DIGITS:
            raise TextXSemanticError(
                f"number too long: at most {MAX_DIGITS} digits before the point, got {digits}"
            )
        return convert(text)

    return read


def metamodel():
    """Return the registered ``maze`` metamodel (the grammar's alone if not installed: the loader
    runs the semantic checks itself)."""
    try:
        return metamodel_for_language("maze")
    except TextXRegistrationError:
        return _fallback_metamodel()


_FALLBACK: list = []


def _fallback_metamodel():
    if not _FALLBACK:
        _FALLBACK.append(grammar_metamodel())
    return _FALLBACK[0]
