"""Public names of a package that load from their modules on first use (PEP 562)."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any


def lazy_names(package: str, homes: dict[str, list[str]]) -> Callable[[str], Any]:
    """The ``__getattr__`` of ``package``, whose public names are listed by module (``homes``,
    module names relative to the package): each is imported from its module when first read, so
    that importing one module of a package does not import all the others (and what they need)."""
    home = {name: f"{package}.{module}" for module, names in homes.items() for name in names}

    def __getattr__(name: str) -> Any:
        if name in home:
            return getattr(importlib.import_module(home[name]), name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    return __getattr__
