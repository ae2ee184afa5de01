"""``metric NAME(ARG=VALUE, ...) [from "FILE.py"] ...`` fitness terms: a user's measure of a floor,
found and its arguments checked where the spec names it, so that ``check`` says what a run would."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from textx import get_location

from mazegen import plugins
from mazegen.dsl.bounds import MAX_TARGET, MAX_WEIGHT, at_most
from mazegen.dsl.located import fail, suggestion, where
from mazegen.errors import MazeError
from mazegen.metric_plugins import arguments_problem, defined_names, metric_function
from mazegen.spec import FitnessTerm, PluginMetric
from mazegen.text import quoted


def _source(term: Any) -> Path | None:
    """The Python file ``from "FILE"`` names, relative to the spec file that names it."""
    if not term.source:
        return None
    spec_file = get_location(term)["filename"]
    folder = Path(spec_file).parent if spec_file else Path.cwd()
    path = (folder / term.source).resolve()
    if not path.is_file():
        fail(term, f"metric {term.name!r}: no file {quoted(term.source)} (looked for {path})")
    return path


def _found(term: Any, path: Path | None) -> tuple[Any, str | None]:
    """The plug-in's function and the package that registers it (None for a file)."""
    name = term.name
    if path is not None:
        try:
            known = defined_names(path)
        except MazeError as error:
            fail(term, f"metric {name!r}: {error}")
        if name not in known:
            fail(term, f"metric {name!r}: {path.name} defines no {name!r}{suggestion(name, known)}")
        package = None
    else:
        plugin = plugins.find("metrics", name)
        if plugin is None:
            installed = plugins.names("metrics")
            listed = f"installed: {', '.join(installed)}" if installed else "none is installed"
            fail(
                term,
                f"unknown metric plug-in {name!r}{suggestion(name, installed)} ({listed}; "
                f'or name the file that defines it: metric {name} from "FILE.py")',
            )
        package = plugin.distribution
    try:
        return metric_function(name, None if path is None else str(path), package), package
    except MazeError as error:
        fail(term, str(error))


def _arguments(term: Any, function: Any) -> tuple[tuple[str, float], ...]:
    arguments: dict[str, float] = {}
    for argument in term.arguments:
        if argument.name in arguments:
            fail(argument, f"metric {term.name!r}: argument {argument.name!r} given twice")
        at_most(argument, abs(argument.value), MAX_TARGET, f"argument {argument.name}")
        arguments[argument.name] = float(argument.value)
    problem = arguments_problem(function, arguments)
    if problem is not None:
        fail(term, f"metric {term.name!r}: {problem}")
    return tuple(arguments.items())


def plugin_term(term: Any, target: tuple[float, float] | None, types: tuple[str, ...]) -> FitnessTerm:
    """The fitness term of a ``metric`` plug-in; ``target`` is its range, checked by the caller."""
    path = _source(term)
    function, package = _found(term, path)
    plugin = PluginMetric(
        None if path is None else str(path), package, _arguments(term, function), types, where(term)
    )
    for value, label in ((term.weight, "weight"), (term.penalty, "penalty")):
        if value is not None and value < 0:
            fail(term, f"{label} must not be negative, got {value:g}")
        if value is not None:
            at_most(term, value, MAX_WEIGHT, label)
    if term.reject:
        return FitnessTerm("plugin", 1.0, float(term.limit), True, None, term.name, plugin=plugin)
    weight = -term.penalty if term.penalty is not None else term.weight if term.weight is not None else 1.0
    return FitnessTerm("plugin", float(weight), None, False, target, term.name, plugin=plugin)
