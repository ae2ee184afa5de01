"""Registration of the ``maze`` language with textX and access to its metamodel."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from textx import LanguageDesc, metamodel_for_language, metamodel_from_file
from textx.exceptions import TextXRegistrationError, TextXSemanticError

from mazegen.dsl.bounds import MAX_DIGITS, digits_before_point

GRAMMAR_FILE = Path(__file__).with_name("maze.tx")


def build_metamodel():
    """Build the textX metamodel of the ``.maze`` language."""
    metamodel = metamodel_from_file(str(GRAMMAR_FILE), autokwd=True)
    metamodel.register_obj_processors({"Number": _bounded_literal(float), "Integer": _bounded_literal(int)})
    # Deferred import: the checker converts whole specs, which needs this module.
    from mazegen.dsl.textx_check import check_model

    metamodel.register_model_processor(check_model)
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


maze_language = LanguageDesc(
    "maze",
    pattern="*.maze",
    description="MazeGen scenario specifications",
    metamodel=build_metamodel,
)


def metamodel():
    """Return the registered ``maze`` metamodel (built directly if not installed)."""
    try:
        return metamodel_for_language("maze")
    except TextXRegistrationError:
        return _fallback_metamodel()


_FALLBACK: list = []


def _fallback_metamodel():
    if not _FALLBACK:
        _FALLBACK.append(build_metamodel())
    return _FALLBACK[0]
