"""The model processor that gives ``textx check`` the same semantic checks as ``mazegen check``."""

from __future__ import annotations

from typing import Any

from textx.exceptions import TextXSemanticError

from mazegen.dsl import loader
from mazegen.errors import MazeError


def check_model(model: Any, _metamodel: Any) -> None:
    """Run MazeGen's semantic checks on a model parsed by textX itself."""
    if loader.loading.get():
        return
    try:
        loader.check_model(model)
    except MazeError as error:
        raise TextXSemanticError(
            error.message, line=error.line, col=error.col, filename=error.filename
        ) from None
