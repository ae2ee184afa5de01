"""The ``.maze`` grammar as a textX metamodel, for the loader to parse with.

Apart from :mod:`mazegen.dsl.language` (the textX registration, whose checks call the loader),
so that the loader never imports what imports it.
"""

from __future__ import annotations

from pathlib import Path

from textx import metamodel_for_language, metamodel_from_file
from textx.exceptions import TextXRegistrationError

GRAMMAR_FILE = Path(__file__).with_name("maze.tx")


def grammar_metamodel():
    """The textX metamodel of the ``.maze`` grammar, without MazeGen's semantic checks."""
    metamodel = metamodel_from_file(str(GRAMMAR_FILE), autokwd=True)
    metamodel.register_obj_processors({"Number": float, "Integer": int})
    return metamodel


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
