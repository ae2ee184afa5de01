"""MazeGen: robot-navigation scenarios from a small language, by grammatical evolution.

The API (``load``, ``build``, ``run``, ``resume``, ``sweep``, ``drive``, ``classes``) lives in
:mod:`mazegen.api`; it and the types it returns are imported on first use, so that
``import mazegen`` stays light for the command line.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from mazegen.api import build, classes, drive, load, resume, run, sweep
    from mazegen.errors import MazeError
    from mazegen.runtime.plugin_view import Floors
    from mazegen.runtime.runs import ExperimentResult
    from mazegen.spec import Spec

from mazegen.version import __version__ as __version__  # the package states its version

_HOMES = {
    "build": "mazegen.api",
    "classes": "mazegen.api",
    "drive": "mazegen.api",
    "load": "mazegen.api",
    "run": "mazegen.api",
    "resume": "mazegen.api",
    "sweep": "mazegen.api",
    "ExperimentResult": "mazegen.runtime.runs._launcher",
    "Floors": "mazegen.runtime.plugin_view",
    "MazeError": "mazegen.errors",
    "Spec": "mazegen.spec",
}
"""Each public name and the module that defines it."""

__all__ = [
    "ExperimentResult",
    "Floors",
    "MazeError",
    "Spec",
    "build",
    "classes",
    "drive",
    "load",
    "resume",
    "run",
    "sweep",
]


def __getattr__(name: str) -> Any:
    if name in _HOMES:
        import importlib

        return getattr(importlib.import_module(_HOMES[name]), name)
    raise AttributeError(f"module 'mazegen' has no attribute {name!r}")


def __dir__() -> list[str]:
    """The public names and the module's own attributes, not the helpers it imports."""
    return sorted([*__all__, *(name for name in globals() if name.startswith("__"))])
