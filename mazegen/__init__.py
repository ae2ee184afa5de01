"""MazeGen: robot-navigation scenarios from a small language, by grammatical evolution.

The API (``load``, ``build``, ``run``, ``resume``, ``sweep``) lives in :mod:`mazegen.api`; it is imported
on first use so that ``import mazegen`` stays light for the command line.
"""

from __future__ import annotations

from typing import Any

from mazegen.version import __version__ as __version__  # the package states its version

__all__ = ["build", "load", "resume", "run", "sweep"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from mazegen import api

        return getattr(api, name)
    raise AttributeError(f"module 'mazegen' has no attribute {name!r}")
