"""Registration of the ``maze`` language with textX."""

from __future__ import annotations

from textx import LanguageDesc

from mazegen.dsl.metamodel import grammar_metamodel
from mazegen.dsl.textx_check import check_model


def build_metamodel():
    """Build the textX metamodel of the ``.maze`` language, with MazeGen's semantic checks."""
    metamodel = grammar_metamodel()
    metamodel.register_model_processor(check_model)
    return metamodel


maze_language = LanguageDesc(
    "maze",
    pattern="*.maze",
    description="MazeGen scenario specifications",
    metamodel=build_metamodel,
)
