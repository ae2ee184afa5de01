"""Sweeps: a grid of settings over specs, each cell an experiment of several runs.

A sweep names values for some settings (``population=1000,5000``, ``seed=1..3``,
``fitness.overlap=0.25,0.5``); every combination, for every spec, is a cell with its
own run directory named from its settings, and all cells share one catalog.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mazegen.errors import MazeError, brief, option
from mazegen.generator.build import fitness_lines
from mazegen.spec import EVOLUTION_BOUNDS, Evolution, Spec

Value = int | float


@dataclass(frozen=True)
class _Setting:
    kind: Callable[[str], Value]
    check: Callable[[Value], bool]
    bounds: str


_SETTINGS = {
    name: _Setting(type(getattr(Evolution(), name)), *bounds)
    for name, bounds in EVOLUTION_BOUNDS.items()
    if name != "codon_max"  # the codons' range is the grammar's, not a setting to sweep
}
"""Evolution settings a sweep may vary, with their bounds (those of the evolution block)."""

FITNESS = "fitness."
"""Prefix of a fitness term's weight: ``fitness.overlap`` is the overlap penalty's weight."""

MAX_CELLS = 10_000
"""The most cells a sweep may have (all specs together), checked before any cell is made."""

_LONGEST_NAME = 100
"""Longest default folder name of a sweep (file systems allow 255 bytes)."""

_WEIGHT = _Setting(float, lambda v: v >= 0, "at least 0")
_RANGE = re.compile(r"(-?\d+)\.\.(-?\d+)")
_NAME = re.compile(r"[^A-Za-z0-9_.]+")


@dataclass(frozen=True)
class Axis:
    """One swept setting and its values, in the order given."""

    name: str
    values: tuple[Value, ...]

    @classmethod
    def parse(cls, text: str) -> Axis:
        """Read ``NAME=VALUES``: values separated by commas, integers also as ``LOW..HIGH``.

        Raises:
            MazeError: for an unknown setting, a bad value or one out of bounds.
        """
        name, equals, raw = text.partition("=")
        name = name.strip()
        if not equals or not raw.strip():
            raise MazeError(
                f"cannot read --set '{brief(text)}' (write NAME=VALUES, e.g. population=500,1000)"
            )
        setting = _WEIGHT if name.startswith(FITNESS) and len(name) > len(FITNESS) else _SETTINGS.get(name)
        if setting is None:
            known = ", ".join([*_SETTINGS, f"{FITNESS}TERM"])
            raise MazeError(f"cannot sweep '{brief(name)}' (known: {known})")
        values: list[Value] = []
        for part in raw.split(","):
            part = part.strip()
            span = _RANGE.fullmatch(part)
            try:
                if span is not None and setting.kind is int:
                    low, high = int(span[1]), int(span[2])
                    if high - low + 1 > MAX_CELLS:  # before it is made: seed=1..99999999999999999999
                        raise MazeError(
                            f"--set {name}: {brief(part)} holds {brief(high - low + 1)} values; "
                            f"a sweep has at most {MAX_CELLS} cells"
                        )
                    values += range(low, high + 1)
                else:
                    values.append(setting.kind(part))
            except ValueError:
                raise MazeError(f"--set {name}: '{brief(part)}' is not a valid value") from None
            if len(values) > MAX_CELLS:
                raise MazeError(
                    f"--set {name}: more than {MAX_CELLS} values; a sweep has at most {MAX_CELLS} cells"
                )
        for value in values:
            if isinstance(value, float) and not math.isfinite(value):
                raise MazeError(f"--set {name}: {value} must be a finite number, {setting.bounds}")
            if not setting.check(value):
                raise MazeError(f"--set {name}: {brief(value)} must be {setting.bounds}")
        if not values:
            raise MazeError(f"--set {name}: empty range '{brief(raw)}'")
        if len(set(values)) != len(values):
            raise MazeError(f"--set {name}: a value is given twice")
        return cls(name, tuple(values))


def parse_axes(texts: Sequence[str]) -> list[Axis]:
    """The axes of ``--set`` options, each setting in one of them.

    Raises:
        MazeError: for an axis :meth:`Axis.parse` refuses, or a setting given twice.
    """
    axes = [Axis.parse(text) for text in texts]
    _check_distinct(axes)
    return axes


def _check_distinct(axes: list[Axis]) -> None:
    names = [axis.name for axis in axes]
    for name in names:
        if names.count(name) > 1:
            raise MazeError(f"--set {name} is given twice (give all its values in one --set)")


def grid(axes: list[Axis]) -> list[dict[str, Value]]:
    """Every combination of the axes' values, the first axis varying slowest.

    Raises:
        MazeError: when a setting is swept twice.
    """
    _check_distinct(axes)
    names = [axis.name for axis in axes]
    return [dict(zip(names, values)) for values in itertools.product(*(axis.values for axis in axes))]


def _check_size(specs: int, axes: list[Axis]) -> None:
    """Refuse more than :data:`MAX_CELLS` cells before making them."""
    cells = math.prod(len(axis.values) for axis in axes)
    if specs * cells > MAX_CELLS:
        count = f"{specs} specs x {cells} cells" if specs > 1 else f"{cells} cells"
        raise MazeError(f"--set: {count}; a sweep has at most {MAX_CELLS} cells")


def apply_cell(spec: Spec, cell: dict[str, Value]) -> Spec:
    """``spec`` with a cell's settings applied.

    Raises:
        MazeError: for a fitness term the spec lacks, or settings that contradict each other.
    """
    evolution: dict[str, Any] = {}
    fitness = list(spec.fitness)
    for name, value in cell.items():
        if name.startswith(FITNESS):
            key = name[len(FITNESS) :]
            matches = [i for i, term in enumerate(fitness) if term.key == key]
            if not matches:
                known = ", ".join(term.key for term in spec.fitness)
                raise MazeError(f"spec '{spec.name}' has no fitness term '{key}' (its terms: {known})")
            for index in matches:
                fitness[index] = dataclasses.replace(fitness[index], weight=float(value))
        elif name in ("tournament", "truncation"):
            evolution.update(selection=name, **{name: value})
        else:
            evolution[name] = value
    try:
        swept = dataclasses.replace(spec, fitness=tuple(fitness)).with_evolution(**evolution)
    except ValueError as error:  # settings within bounds alone but not together (population x genome)
        raise MazeError(f"{cell_name(spec.name, cell)}: {error}") from None
    settings = swept.evolution
    if settings.elitism >= settings.population:
        if "elitism" in cell:
            raise MazeError(f"{cell_name(spec.name, cell)}: elitism must be below the population")
        swept = swept.with_evolution(elitism=settings.population - 1)  # as mazegen run --population does
    if settings.selection == "tournament" and settings.tournament > settings.population:
        raise MazeError(f"{cell_name(spec.name, cell)}: tournament is larger than the population")
    return swept


def _text(value: Value) -> str:
    """A value as names and messages write it: ``0.5``, ``0`` for ``0.0``."""
    return f"{value:g}" if isinstance(value, float) else str(value)


def sweep_name(specs: Sequence[Spec]) -> str:
    """A sweep's default folder name: each of its scenarios' names once, joined by ``+``
    (``factory+table1_exp3``), or the first and how many more when that is too long."""
    names = list(dict.fromkeys(spec.name for spec in specs))
    joined = "+".join(names)
    return joined if len(joined) <= _LONGEST_NAME else f"{names[0]}+{len(names) - 1}-more"


def cell_name(scenario: str, cell: dict[str, Value]) -> str:
    """A cell's run directory name: the scenario, then each swept setting and its value."""
    parts = [scenario]
    for name, value in cell.items():
        parts.append(_NAME.sub("_", name.removeprefix(FITNESS) + _text(value)))
    return "-".join(parts)


@dataclass(frozen=True)
class Cell:
    """One cell of a sweep: its spec (settings applied), where it is written, and how far it got.

    Attributes:
        spec: The spec with the cell's settings.
        settings: The swept settings' values.
        run_dir: The cell's run directory.
        state: ``new`` (to run), ``resume`` (interrupted earlier) or ``finished`` (skipped).
    """

    spec: Spec
    settings: dict[str, Value]
    run_dir: Path
    state: str


def plan_cells(specs: list[Spec], axes: list[Axis], out_dir: Path, *, force: bool) -> list[Cell]:
    """The cells of a sweep, each with its state in ``out_dir``.

    Raises:
        MazeError: for two cells with one name, or a cell directory that holds another
            experiment (without ``force``).
    """
    _check_size(len(specs), axes)
    cells = []
    for spec in specs:
        made: dict[tuple[Any, ...], dict[str, Value]] = {}
        for settings in grid(axes):
            swept = apply_cell(spec, settings)
            _check_changes(spec, made, swept, settings)
            run_dir = out_dir / cell_name(spec.name, settings)
            cells.append(Cell(swept, settings, run_dir, "new" if force else _state(run_dir, swept)))
    names = [cell.run_dir.name for cell in cells]
    if len(set(names)) != len(names):
        raise MazeError("two cells share a name: give specs whose scenarios have different names")
    return cells


def _check_changes(
    spec: Spec, made: dict[tuple[Any, ...], dict[str, Value]], swept: Spec, settings: dict[str, Value]
) -> None:
    """Refuse a cell where a setting changes nothing, or that would run the experiment of an
    earlier cell (``made``, by what runs).

    What runs is the fitness module and the evolution settings (a sweep changes nothing
    else): the weight of a term that rejects (``solvable required``), for one, is in neither.
    """
    runs = _what_runs(swept)
    for name, value in settings.items():
        try:
            without = apply_cell(spec, {other: v for other, v in settings.items() if other != name})
        except MazeError:
            continue  # the other settings need this one (an elitism below a swept population)
        if without != swept and _what_runs(without) == runs:
            raise MazeError(
                f"--set {name}={brief(_text(value))} changes nothing in spec '{spec.name}' "
                "(it runs the same experiment as without it)"
            )
    earlier = made.setdefault(runs, settings)
    if earlier is not settings:
        names = ", ".join(name for name in settings if settings[name] != earlier[name])
        raise MazeError(
            f"--set {names}: cells {cell_name(spec.name, earlier)} and {cell_name(spec.name, settings)} "
            "would run the same experiment"
        )


def _what_runs(spec: Spec) -> tuple[Any, ...]:
    """What a run of ``spec`` depends on that a sweep can change: fitness lines and evolution settings."""
    penalised, rejecting = fitness_lines(spec)
    return (tuple(penalised), tuple(rejecting), spec.evolution)


def _state(run_dir: Path, spec: Spec) -> str:
    if not run_dir.is_dir() or not any(run_dir.iterdir()):
        return "new"
    from mazegen.runtime.documents import RunDirectory

    written = RunDirectory(run_dir).spec
    if not written.is_file() or written.read_text(encoding="utf-8") != spec.to_json():
        raise MazeError(
            f"this cell's directory holds another experiment (use {option('force')} to replace it)",
            filename=str(run_dir),
        )
    return "finished" if RunDirectory(run_dir).finished else "resume"
