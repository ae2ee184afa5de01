"""The ``mazegen`` generator target of textX: ``textx generate SPEC.maze --target mazegen``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from textx import generator

from mazegen.dsl.loader import spec_from_model
from mazegen.generator.build import build


@generator("maze", "mazegen")
def maze_generator(
    metamodel: Any, model: Any, output_path: str | None, overwrite: bool, debug: bool, **custom_args: Any
) -> None:
    """Write the experiment files of the model's scenario (default ``build/<name>``)."""
    spec = spec_from_model(model)
    out = Path(output_path) if output_path else Path("build") / spec.name
    build(spec, out)
