"""A user's measure of a floor, named by a ``metric`` fitness term: found, loaded and called alike
by ``check`` (which finds it and checks its arguments) and by every process that scores a
population (which calls it through :func:`mazegen.runtime.metrics.plugin_metric`).

A plug-in is a function of a :class:`mazegen.runtime.plugin_view.Floors` view and the keyword
arguments the term gives it, defined in a Python file the term names (``from "dock.py"``) or
registered by an installed package under the ``mazegen.metrics`` entry point group.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import inspect
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from mazegen import plugins
from mazegen.errors import MazeError

MetricFunction = Callable[..., Any]

_LOADED: dict[tuple[str, str | None, int, int], MetricFunction] = {}
"""Functions loaded in this process, by name and file version: a file edited between two runs of
one process (a sweep, a resume) is loaded again."""


def defined_names(path: Path) -> list[str]:
    """The names a Python file defines at its top level, read without running it (for "did you mean").

    Raises:
        MazeError: when the file cannot be read or is not Python, at the line of its syntax error.
    """
    try:
        tree = ast.parse(path.read_bytes(), filename=str(path))
    except SyntaxError as error:
        raise MazeError(f"invalid Python: {error.msg}", filename=str(path), line=error.lineno) from error
    except OSError as error:
        raise MazeError(f"cannot read the metric file: {error.strerror}", filename=str(path)) from error
    names = []
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.append(node.name)
        elif isinstance(node, ast.Assign):
            names += [target.id for target in node.targets if isinstance(target, ast.Name)]
        elif isinstance(node, ast.ImportFrom | ast.Import):
            names += [(alias.asname or alias.name).split(".")[0] for alias in node.names]
    return names


def _from_file(name: str, path: Path) -> MetricFunction:
    digest = hashlib.sha256(str(path).encode()).hexdigest()[:16]
    spec = importlib.util.spec_from_file_location(f"mazegen_metric_{digest}", path)
    if spec is None or spec.loader is None:
        raise MazeError(f"metric {name!r}: {path} is not a Python file")
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as error:  # the user's module: its failure said in one line
        raise MazeError(f"metric {name!r}: {path} fails to run ({type(error).__name__}: {error})") from error
    if not hasattr(module, name):
        raise MazeError(f"metric {name!r}: {path} defines no {name!r}")
    return getattr(module, name)  # type: ignore[no-any-return]


def _from_package(name: str, package: str | None) -> MetricFunction:
    plugin = plugins.find("metrics", name)
    if plugin is None:
        needed = f"install {package} here" if package else "is its package installed?"
        raise MazeError(
            f"metric plug-in {name!r} is not installed in this environment: no package registers it "
            f"under {plugins.GROUPS['metrics']} ({needed})"
        )
    return plugin.load()  # type: ignore[no-any-return]


def metric_function(name: str, source: str | None, package: str | None = None) -> MetricFunction:
    """The function of metric plug-in ``name``: from the Python file ``source`` or, without one,
    from the installed package that registers it (``package``, named when it is missing).

    Raises:
        MazeError: in one line, when it cannot be found or loaded, or is not callable.
    """
    version = (0, 0)
    if source is not None:
        try:
            stat = os.stat(source)
        except OSError as error:
            raise MazeError(f"metric {name!r}: cannot read {source} ({error.strerror})") from error
        version = (stat.st_mtime_ns, stat.st_size)
    key = (name, source, *version)
    if key not in _LOADED:
        found = _from_package(name, package) if source is None else _from_file(name, Path(source))
        if not callable(found):
            raise MazeError(f"metric {name!r} is {type(found).__name__}, not a function of the floors")
        _LOADED[key] = found
    return _LOADED[key]


def arguments_problem(function: MetricFunction, arguments: dict[str, float]) -> str | None:
    """Why ``function`` cannot be called with the floors and ``arguments`` as keywords, or None."""
    try:
        signature = inspect.signature(function)
    except (TypeError, ValueError):  # a builtin or compiled function without a signature: say nothing
        return None
    try:
        signature.bind(None, **arguments)
    except TypeError as error:
        parameters = list(signature.parameters)[1:]
        takes = f"it takes {', '.join(parameters)}" if parameters else "it takes no arguments"
        return f"{error} ({takes} after the floors)"
    return None
