"""Spec → build directory: grammar.bnf, fitness.py, experiment.py and spec.json."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from jinja2 import Environment, PackageLoader, StrictUndefined

from mazegen.errors import MazeError
from mazegen.fileio import write_atomic
from mazegen.fitness_terms import term_kind
from mazegen.generator.grammar import scenario_rules
from mazegen.spec import Spec
from mazegen.version import __version__

ARTIFACTS = ("grammar.bnf", "fitness.py", "experiment.py", "spec.json")


@dataclass(frozen=True)
class TermLine:
    """One rendered fitness term: its key, Python expression and a comment; ``drives`` when it reads
    how a robot fares (its expression reads ``driven``, the individuals chosen to drive)."""

    key: str
    expression: str
    note: str
    drives: bool = False


def _environment() -> Environment:
    env = Environment(
        loader=PackageLoader("mazegen", "templates"),
        undefined=StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,
    )
    # Every literal reaches generated Python through repr, so no spec text can inject code.
    env.filters["pyrepr"] = repr
    return env


def fitness_lines(spec: Spec) -> tuple[list[TermLine], list[TermLine]]:
    """Split the spec's terms into scored lines and rejection tests."""
    penalised: list[TermLine] = []
    rejecting: list[TermLine] = []
    for term in spec.fitness:
        row = term_kind(term)
        call, note = row.call(term)
        if term.reject:
            rejecting.append(TermLine(term.key, call, note + " (reject)"))
        elif term.weight != 0:
            sign = "" if row.reward else "-"
            expression = f"{sign}{float(term.weight)!r} * {call}"
            penalised.append(TermLine(term.key, expression, note, drives=row.reads == "drive"))
    return penalised, rejecting


def grammar_text(spec: Spec) -> str:
    """The ``grammar.bnf`` of ``spec``."""
    return (
        _environment()
        .get_template("grammar.bnf.jinja")
        .render(rules=scenario_rules(spec), style=spec.scenario.grammar, **_context(spec))
    )


def _context(spec: Spec) -> dict[str, str]:
    return {"name": spec.name, "version": __version__}


def _non_finite(value: Any, where: str) -> Iterator[str]:
    """Where, in a spec's data, a number is infinite or NaN (``arena.width``, ``fitness[0].weight``)."""
    if isinstance(value, float) and not math.isfinite(value):
        yield f"{where} ({value})"
    elif isinstance(value, dict):
        for key, item in value.items():
            yield from _non_finite(item, f"{where}.{key}" if where else key)
    elif isinstance(value, list | tuple):
        for index, item in enumerate(value):
            yield from _non_finite(item, f"{where}[{index}]")


def _check_buildable(spec: Spec, grammar: str) -> None:
    """Refuse a spec (made in Python, or edited) whose files could not run: ``inf`` would reach
    fitness.py as a name and spec.json as ``Infinity``, a bad grammar would fail the run in a
    folder the user never sees. The language already refuses both at ``check``."""
    from mazegen.runtime.engine import parse_bnf

    for where in _non_finite(dataclasses.asdict(spec), ""):
        raise MazeError(f"the spec holds a non-finite number at {where}", filename=spec.source)
    parse_bnf(grammar, filename=f"{spec.source} (its grammar)")


def render_artifacts(spec: Spec) -> dict[str, str]:
    """Render every build artifact of ``spec`` as text, keyed by file name.

    Raises:
        MazeError: for a spec holding an infinite or NaN number, or whose grammar does not read.
    """
    env = _environment()
    context = _context(spec)
    grammar = grammar_text(spec)
    _check_buildable(spec, grammar)
    penalised, rejecting = fitness_lines(spec)
    driving = [line for line in penalised if line.drives]
    driven = 1.0 if not driving else spec.robot_or_default.driven
    return {
        "grammar.bnf": grammar,
        "fitness.py": env.get_template("fitness.py.jinja").render(
            penalised=[line for line in penalised if not line.drives],
            driving=driving,
            driven=float(driven),
            rejecting=rejecting,
            **context,
        ),
        "experiment.py": env.get_template("experiment.py.jinja").render(**context),
        "spec.json": spec.to_json(),
    }


def build(spec: Spec, out_dir: Path) -> list[Path]:
    """Write the build artifacts of ``spec`` into ``out_dir`` (atomically, file by file)."""
    written = []
    for name, text in render_artifacts(spec).items():
        path = out_dir / name
        write_atomic(path, text)
        written.append(path)
    return written
