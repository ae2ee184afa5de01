"""A built experiment loaded for evaluation: spec, grammar, fitness module and tables."""

from __future__ import annotations

import importlib.util
import sys
import traceback
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.fileio import read_text
from mazegen.runtime.engine._bnf import Grammar, parse_bnf
from mazegen.runtime.engine._compiled_grammar import CompiledGrammar, RowToken, compile_grammar
from mazegen.runtime.engine._mapping import NUMBERS_PER_ELEMENT, PopulationMap, map_population
from mazegen.runtime.engine._placement import PLACEMENT_GENES, Ranges
from mazegen.runtime.engine._population import Population, decode
from mazegen.runtime.engine._used_operators import Usage, usage_of
from mazegen.runtime.geometry import ElementTable
from mazegen.spec import Spec

INVALID = -np.inf
"""Fitness of individuals that map to no scenario or that the spec rejects."""

REJECTED = "rejected"
"""The one verdict of :meth:`Problem.rejections` for a fitness module that does not tell its
reject terms apart."""


@dataclass(frozen=True)
class Evaluation:
    """Fitness of a population and what it was computed from."""

    fitness: np.ndarray
    terms: dict[str, np.ndarray]
    population: Population
    mapped: PopulationMap


def read_build_spec(build_dir: Path) -> Spec:
    """The ``spec.json`` of a build directory, with a one-line error when missing or damaged."""
    spec_path = build_dir / "spec.json"
    if not spec_path.is_file():
        raise MazeError(
            "not a .maze file nor a MazeGen build directory (no spec.json)", filename=str(build_dir)
        )
    try:
        return Spec.from_json(spec_path.read_text(encoding="utf-8"))
    except (
        ValueError,
        KeyError,
        TypeError,
        AttributeError,  # JSON of another shape: null, a list…
    ) as error:  # JSONDecodeError and UnicodeDecodeError are ValueErrors
        raise MazeError(
            f"damaged spec.json ({type(error).__name__}: {error})", filename=str(spec_path)
        ) from None


def _made_by_an_earlier_version(error: ModuleNotFoundError, path: Path) -> MazeError:
    """A build folder (or a run's copy of one) whose fitness module imports what this MazeGen moved."""
    lines = [
        frame.lineno for frame in traceback.extract_tb(error.__traceback__) if frame.filename == str(path)
    ]
    return MazeError(
        f"fitness.py imports {error.name}, which this MazeGen does not have: it was made by an earlier "
        "version; rebuild it with 'mazegen build SPEC' (and redo any edits)",
        filename=str(path),
        line=lines[-1] if lines else None,
    )


@lru_cache(maxsize=16)
def fitness_module(path: str, text: str) -> ModuleType:
    """The fitness module ``path`` holds as ``text``, loaded once per process for each text: its
    functions are pure, so the problems of one build share it, and an edit loads it afresh."""
    return load_fitness(Path(path))


@lru_cache(maxsize=16)
def compiled_bnf(
    text: str, filename: str, elements: tuple[str, ...], rows: tuple[RowToken, ...] = ()
) -> tuple[Grammar, CompiledGrammar]:
    """The grammar ``text`` (from ``filename``) parsed and compiled for ``elements`` and ``rows``
    (:attr:`~mazegen.spec.Spec.row_tokens`), once per process."""
    grammar = parse_bnf(text, filename=filename)
    return grammar, compile_grammar(grammar, list(elements), rows)


def load_fitness(path: Path) -> ModuleType:
    """The fitness module at ``path``, loaded afresh; a module that does not load is a one-line error."""
    module_name = f"mazegen_fitness_{abs(hash(str(path)))}"
    loader_spec = importlib.util.spec_from_file_location(module_name, path)
    if loader_spec is None or loader_spec.loader is None:
        raise MazeError("cannot load the fitness module", filename=str(path))
    module = importlib.util.module_from_spec(loader_spec)
    try:
        loader_spec.loader.exec_module(module)
    except SyntaxError as error:
        raise MazeError(
            f"fitness module does not compile: {error.msg}",
            filename=str(path),
            line=error.lineno,
            col=error.offset,
        ) from None
    except Exception as error:  # an edited module that raises as it loads
        if isinstance(error, ModuleNotFoundError) and (error.name or "").startswith("mazegen."):
            raise _made_by_an_earlier_version(error, path) from None
        raise MazeError(
            f"fitness module raised {type(error).__name__} as it loads: {error}", filename=str(path)
        ) from None
    for name in ("terms", "rejected"):
        if not callable(getattr(module, name, None)):
            raise MazeError(f"fitness module must define {name}(pop)", filename=str(path))
    sys.modules.setdefault(module_name, module)
    return module


class Workspace:
    """The large arrays of an evaluation, kept from one generation to the next.

    A population of 50,000 with 32 slots needs tens of MB per evaluation; writing
    into the same pages each generation spares the allocation and page faults.
    Evaluations that use a workspace return views of it, valid until the next one.
    """

    def __init__(self) -> None:
        self._map: PopulationMap | None = None
        self._params = np.empty((0, 0, PLACEMENT_GENES))

    def arrays(
        self, rows: int, slots: int, numbers: bool, membership: bool
    ) -> tuple[PopulationMap, np.ndarray]:
        """Mapping and placement arrays for ``rows`` individuals (views of the first rows); ``numbers``
        and ``membership``: with room for the numbers and the row membership of every slot."""
        kept = self._map
        width = slots if numbers else 0
        members = slots if membership else 0
        if (
            kept is None
            or kept.valid.shape[0] < rows
            or kept.element_ids.shape[1] != slots
            or (kept.numbers.shape[1] != width)
            or (kept.membership.shape[1] != members)
        ):
            capacity = max(rows, 0 if kept is None else kept.valid.shape[0])
            kept = self._map = PopulationMap(
                np.empty(capacity, np.bool_),
                np.empty(capacity, np.int32),
                np.empty(capacity, np.int32),
                np.empty((capacity, slots), np.int32),
                np.empty((capacity, width, NUMBERS_PER_ELEMENT), np.float64),
                np.empty((capacity, slots), np.int32),
                np.empty((capacity, members, 3), np.int32),
            )
            self._params = np.empty((capacity, slots, PLACEMENT_GENES))
        view = PopulationMap(*(array[:rows] for array in vars(kept).values()))
        return view, self._params[:rows]


@dataclass(frozen=True)
class Problem:
    """Everything needed to evaluate genomes of one experiment."""

    spec: Spec
    grammar: Grammar
    compiled: CompiledGrammar
    table: ElementTable
    ranges: Ranges
    fitness_module: ModuleType
    build_dir: Path

    @classmethod
    def from_build_dir(cls, build_dir: Path) -> Problem:
        """Load ``spec.json``, ``grammar.bnf`` and ``fitness.py`` from a build directory (the grammar
        and the fitness module are parsed once per process for each text they hold)."""
        spec = read_build_spec(build_dir)
        grammar_path, fitness_path = build_dir / "grammar.bnf", build_dir / "fitness.py"
        grammar = read_text(grammar_path, "grammar")
        module = fitness_module(str(fitness_path), read_text(fitness_path, "fitness module"))
        compiled = compiled_bnf(grammar, str(grammar_path), spec.scenario.elements, spec.row_tokens)
        return cls.assemble(spec, compiled, module, build_dir)

    @classmethod
    def assemble(
        cls,
        spec: Spec,
        grammar: tuple[Grammar, CompiledGrammar],
        fitness_module: ModuleType,
        build_dir: Path,
    ) -> Problem:
        """The problem of ``spec`` with its grammar (from :func:`compiled_bnf`) and fitness module."""
        return cls(
            spec=spec,
            grammar=grammar[0],
            compiled=grammar[1],
            table=ElementTable.from_types(spec.scenario_elements),
            ranges=Ranges.from_spec(spec),
            fitness_module=fitness_module,
            build_dir=build_dir,
        )

    @property
    def slots(self) -> int:
        """Element slots K (placement rows per genome)."""
        return self.spec.scenario.max_elements

    def decode(
        self,
        codons: np.ndarray,
        genes: np.ndarray,
        workspace: Workspace | None = None,
        *,
        searching: bool = False,
    ) -> tuple[PopulationMap, Population]:
        """Map structure codons and decode placements (into ``workspace`` when given); ``searching``:
        for a search (see :attr:`Population.searching`)."""
        numbers = self.reads_numbers
        membership = bool(self.spec.scenario.rows)
        out, params = (
            (None, None)
            if workspace is None
            else workspace.arrays(codons.shape[0], self.slots, numbers, membership)
        )
        mapped = self.map(codons, numbers=numbers, out=out)
        return mapped, decode(mapped, genes, self.ranges, self.table, self.spec, params, searching=searching)

    def usage(self, codons: np.ndarray) -> Usage:
        """How much of each genome of ``codons`` its mapping reads (for the operators within it)."""
        return usage_of(self.map(codons, numbers=False), codons.shape[1])

    @property
    def reads_numbers(self) -> bool:
        """Whether placements read the numbers a mapping collects (only grammar placement does)."""
        return self.spec.scenario.placement is not None

    def map(self, codons: np.ndarray, *, numbers: bool, out: PopulationMap | None = None) -> PopulationMap:
        """Map structure codons with the spec's mapping settings (into ``out`` when given);
        ``numbers``: collect the numbers grammar placement reads."""
        evolution = self.spec.evolution
        return map_population(
            self.compiled,
            codons,
            wraps=evolution.wraps,
            consume=evolution.consume,
            max_elements=self.slots,
            numbers=numbers,
            out=out,
        )

    def score(self, population: Population) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Fitness and per-term values of a decoded population.

        Raises:
            MazeError: when the fitness module (which users may edit) fails, naming its line.
        """
        terms = _call_fitness(self.fitness_module, "terms", population)
        total = np.zeros(population.size, dtype=np.float64)
        for values in terms.values():
            total += values
        rejected = _call_fitness(self.fitness_module, "rejected", population)
        bad = ~population.valid | np.asarray(rejected, dtype=bool)
        return np.where(bad, INVALID, total), terms

    def rejections(self, population: Population) -> dict[str, np.ndarray]:
        """Each reject term's verdict per individual (True: rejected), by term key; a fitness module
        without ``rejections`` (generated before it, or edited without it) gives one verdict,
        ``REJECTED``, its ``rejected(pop)``.

        Raises:
            MazeError: when the fitness module fails, naming its line.
        """
        if not callable(getattr(self.fitness_module, "rejections", None)):
            return {REJECTED: np.asarray(_call_fitness(self.fitness_module, "rejected", population), bool)}
        verdicts = _call_fitness(self.fitness_module, "rejections", population)
        return {key: np.asarray(verdict, dtype=bool) for key, verdict in verdicts.items()}

    def evaluate(
        self,
        codons: np.ndarray,
        genes: np.ndarray,
        workspace: Workspace | None = None,
        *,
        searching: bool = False,
    ) -> Evaluation:
        """Map, decode and score a population of genomes (into ``workspace`` when given); ``searching``:
        for a search, which drives only the spec's best fraction (:attr:`Population.searching`)."""
        mapped, population = self.decode(codons, genes, workspace, searching=searching)
        fitness, terms = self.score(population)
        return Evaluation(fitness, terms, population, mapped)


def _call_fitness(module: ModuleType, name: str, population: Population) -> Any:
    """``module.name(population)``; an exception raised through the module's own lines becomes a
    one-line error at the last of them (the module runs from a worker's copy, so it is named
    ``fitness.py`` alone). A :class:`MazeError` is already one line about what the user gave (a
    policy the simulator cannot load), which ``fitness.py`` did not cause: it passes as it is."""
    try:
        return getattr(module, name)(population)
    except MazeError:
        raise
    except Exception as error:
        lines = [
            line
            for frame, line in traceback.walk_tb(error.__traceback__)
            if frame.f_code.co_filename == module.__file__
        ]
        if not lines:
            raise
        raise MazeError(
            f"{name}(pop) raised {type(error).__name__}: {error}", filename="fitness.py", line=lines[-1]
        ) from None
