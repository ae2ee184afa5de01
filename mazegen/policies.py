"""A user's policy named by its path ``package.module:name``: how the path is written, and where its
module is looked for.

The language, the ``--controller`` option and the simulator read the same form, and look for the
module in the same places: the current folder, ``PYTHONPATH`` and the installed packages. Python
itself searches the current folder only when it runs ``-m`` or ``-c``; the ``mazegen`` command's
search path holds its script's folder instead, so the current folder is added, last, where a file
shadows none of the packages a run imports.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import importlib.util
import os
import re
import sys
from types import ModuleType

_IDENTIFIERS = r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*"
POLICY_PATH = re.compile(f"{_IDENTIFIERS}:{_IDENTIFIERS}")
"""A policy's path, as the language's ``ControllerName`` reads it (``mazegen/dsl/maze.tx``)."""

SEARCHED = "the current folder, PYTHONPATH or the installed packages"
"""Where a policy's module is looked for, as messages say it."""


def is_policy_path(name: str) -> bool:
    """Whether ``name`` is written as a policy's path ``package.module:name``."""
    return POLICY_PATH.fullmatch(name) is not None


def malformed_path(name: str) -> str:
    """What is wrong with ``name``, which is no policy's path."""
    return f"a policy's path reads package.module:name, got '{name}'"


def import_policy_module(module: str) -> ModuleType:
    """Import ``module`` (a policy's), looking in :data:`SEARCHED`.

    Raises:
        Exception: whatever the import raises (ModuleNotFoundError, or the module's own error).
    """
    _search_current_folder()
    return importlib.import_module(module)


def policy_module_found(module: str) -> bool:
    """Whether ``module`` is found in :data:`SEARCHED`, found without running any of its package's
    code: a spec names its policy long before a robot is driven."""
    _search_current_folder()
    top, *below = module.split(".")
    found = importlib.util.find_spec(top)
    for part in below:
        if found is None or found.submodule_search_locations is None:
            return False
        locations = list(found.submodule_search_locations)
        found = importlib.machinery.PathFinder.find_spec(f"{found.name}.{part}", locations)
    return found is not None


def _search_current_folder() -> None:
    here = os.getcwd()
    if here not in sys.path:
        sys.path.append(here)
