"""Throughput of the path search and of the difficulty metrics on an evolved population of 50,000.

Usage:
    python benchmarks/navigation.py            # population 50,000, median of 5 calls (~3 min)
    python benchmarks/navigation.py --quick    # population 5,000, median of 3 calls
    python benchmarks/navigation.py --repeats 9

Each spec is built in a temporary folder and evolved for 15 generations at the measured population
size with its own operators (``evolved_sample`` of ``kernels.py``); its last generation is decoded
once (placements included), so the timings cover the path search alone. Every figure is the median
of ``--repeats`` calls after one untimed call, with all numba threads and with one:

* ``examples/factory.maze`` on its own grid (12.5 cm cells) and on a 25 cm grid (the population's
  arena replaced, the placements decoded again before timing): ``navigate`` (solvability, path
  length, coverage); on its own grid also ``reach`` (solvability and coverage without paths);
* ``examples/factory.maze``: the full evaluation ``problem.evaluate`` (mapping, decoding and every
  fitness term, into a workspace kept from call to call as a run's generations do), all threads
  only: as the spec asks (its terms read solvability, so
  no path is searched) and with every path's length read too, which is what is checked against
  the target of 300,000 evaluations per second;
* ``examples/workshop.maze``: ``navigate``, and ``survey`` (the path search plus BARN's difficulty
  metrics along each path).

Prints a Markdown table, the target and the budget it leaves for path lengths on top of
solvability (against what ``navigate`` costs on top of ``reach`` in the same run), writes
``benchmarks/navigation.csv``.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import tempfile
import types
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, median_seconds, peak_rss_mb, write_csv
from kernels import EVOLVED_GENERATIONS, Sample, evolved_sample

import mazegen
from mazegen.runtime import metrics
from mazegen.runtime.engine._population import Population
from mazegen.runtime.engine._problem import Problem, Workspace
from mazegen.runtime.geometry._cspace import grid_of
from mazegen.runtime.navigation._connectivity import reach
from mazegen.runtime.navigation._difficulty import survey
from mazegen.runtime.navigation._paths import navigate
from mazegen.runtime.threads import thread_count, threads

SPECS = {
    "factory": ROOT / "examples" / "factory.maze",
    "workshop": ROOT / "examples" / "workshop.maze",
}
POPULATION = 50_000
QUICK_POPULATION = 5_000
REPEATS = 5
QUICK_REPEATS = 3
WARMUP = 1
TARGET = 300_000.0
"""Full evaluations per second the factory's evolved population should reach with all threads."""


def reading_path_length(problem: Problem) -> Problem:
    """``problem`` with a fitness that reads every path's length before its own terms (which then
    take solvability from the same search), the fitness itself unchanged."""
    own = problem.fitness_module
    module = types.ModuleType("fitness_reading_path_length")

    def terms(pop: Population) -> dict[str, np.ndarray]:
        metrics.path_length(pop)
        return own.terms(pop)

    module.terms, module.rejected = terms, own.rejected  # type: ignore[attr-defined]
    return dataclasses.replace(problem, fitness_module=module)


# What is timed: a zero-argument call made of the problem, its evolved sample and the (re-gridded)
# population.
OPERATIONS: dict[str, Callable[[Problem, Sample, Population], Callable[[], object]]] = {
    "navigate": lambda problem, sample, pop: partial(navigate, pop, grid_of(pop.arena)),
    "reach": lambda problem, sample, pop: partial(reach, pop, grid_of(pop.arena)),
    "survey": lambda problem, sample, pop: partial(survey, pop),
    "full evaluation": lambda problem, sample, pop: partial(
        problem.evaluate, sample.codons, sample.genes, Workspace()
    ),
    "full evaluation + path": lambda problem, sample, pop: partial(
        reading_path_length(problem).evaluate, sample.codons, sample.genes, Workspace()
    ),
}


@dataclass(frozen=True)
class Case:
    """One row of the table.

    Attributes:
        spec: A key of :data:`SPECS`.
        operation: A key of :data:`OPERATIONS`.
        grid: Cell size in arena units replacing the spec's, or ``None`` for the spec's own.
        one_thread: Also time the operation on a single numba thread.
    """

    spec: str
    operation: str
    grid: float | None = None
    one_thread: bool = True


CASES = (
    Case("factory", "navigate"),
    Case("factory", "reach"),
    Case("factory", "navigate", grid=25.0),
    Case("factory", "full evaluation", one_thread=False),
    Case("factory", "full evaluation + path", one_thread=False),
    Case("workshop", "navigate"),
    Case("workshop", "survey"),
)


def load_problem(path: Path) -> Problem:
    """Build the spec at ``path`` in a temporary folder and load it."""
    with tempfile.TemporaryDirectory() as folder:
        mazegen.build(path, folder)
        return Problem.from_build_dir(Path(folder))


def on_grid(pop: Population, grid: float | None) -> Population:
    """``pop`` on an arena with cell size ``grid`` (``pop`` itself for ``None``), its placements decoded."""
    if grid is not None:
        pop = dataclasses.replace(pop, arena=dataclasses.replace(pop.arena, grid=grid))
    _ = pop.params  # decode the placements now, not inside the first timed call
    return pop


def seconds_on(count: int, action: Callable[[], object], repeats: int) -> float:
    """Median seconds of ``action`` on ``count`` of the kernels' threads."""
    with threads(count):
        return median_seconds(action, repeats=repeats, warmup=WARMUP)


def describe(pop: Population) -> dict:
    """Grid size, valid and solvable shares and mean elements of ``pop`` on its arena's grid."""
    grid = grid_of(pop.arena)
    found = navigate(pop, grid)
    return {
        "grid": grid.cell,
        "cells": f"{grid.cols} × {grid.rows}",
        "valid_pct": 100 * float(pop.valid.mean()),
        "solvable_pct": 100 * float(found.solvable.mean()),
        "mean_elements": float(pop.n_elements.mean()),
    }


def measure(population: int, repeats: int) -> list[dict]:
    """Evolve each spec's population once and time every case of :data:`CASES` on it."""
    rows = []
    for spec_name, path in SPECS.items():
        problem = load_problem(path)
        sample = evolved_sample(problem, population, np.random.default_rng(1))
        for case in (case for case in CASES if case.spec == spec_name):
            pop = on_grid(sample.population, case.grid)
            action = OPERATIONS[case.operation](problem, sample, pop)
            parallel = seconds_on(thread_count(), action, repeats)
            single = seconds_on(1, action, repeats) if case.one_thread else None
            row = {
                "spec": spec_name,
                "operation": case.operation,
                **describe(pop),
                "rows": sample.rows,
                "ms": 1e3 * parallel,
                "per_s": sample.rows / parallel,
                "ms_1t": None if single is None else 1e3 * single,
                "per_s_1t": None if single is None else sample.rows / single,
                "speedup": None if single is None else single / parallel,
            }
            rows.append(row)
            print(
                f"  {spec_name:9} {case.operation:22} grid {row['grid']:5} {1e3 * parallel:9.2f} ms",
                flush=True,
            )
    return rows


COLUMNS = [
    ("spec", "spec", "s"),
    ("operation", "operation", "s"),
    ("grid", "grid cm", "g"),
    ("cells", "cells", "s"),
    ("rows", "individuals", ","),
    ("valid_pct", "valid %", ".1f"),
    ("solvable_pct", "solvable %", ".1f"),
    ("mean_elements", "mean elements", ".2f"),
    ("ms", "ms", ".1f"),
    ("per_s", "evaluations/s", ",.0f"),
    ("ms_1t", "1 thread ms", ".1f"),
    ("per_s_1t", "1 thread evaluations/s", ",.0f"),
    ("speedup", "speed-up", ".2f"),
]


def target_line(rows: list[dict]) -> str:
    """PASS or FAIL of the factory's full evaluation with path lengths against :data:`TARGET`."""
    row = next(
        row for row in rows if row["spec"] == "factory" and row["operation"] == "full evaluation + path"
    )
    verdict = "PASS" if row["per_s"] >= TARGET else "FAIL"
    return (
        f"{verdict}  full evaluation with solvability and path length >= {TARGET:,.0f} evaluations/s "
        f"on factory's evolved population (all threads): {row['per_s']:,.0f}/s"
    )


def budget_line(rows: list[dict]) -> str:
    """What the target leaves per floor for path lengths on top of the spec's own evaluation (which
    decides solvability without paths), beside what searching them costs on top of that in this run."""
    rows = [row for row in rows if row["spec"] == "factory"]
    own = next(row for row in rows if row["operation"] == "full evaluation")
    # Rows on the spec's own grid, where the full evaluation runs (not the 25 cm navigate row).
    factory = {row["operation"]: row for row in rows if row["grid"] == own["grid"]}
    allowed = 1e6 / TARGET - 1e6 / own["per_s"]
    extra = 1e6 / factory["navigate"]["per_s"] - 1e6 / factory["reach"]["per_s"]
    cost = f"navigate costs {extra:.2f} µs per floor more than reach (all threads)"
    if allowed < 0:
        return f"the spec's own evaluation alone is {-allowed:.2f} µs per floor over the target; {cost}"
    return f"path lengths may add {allowed:.2f} µs per floor to the spec's own evaluation; {cost}"


def main() -> None:
    """Measure, print the table and the target, write the CSV."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--quick", action="store_true", help=f"population {QUICK_POPULATION:,}, {QUICK_REPEATS} repeats"
    )
    parser.add_argument("--repeats", type=int, help=f"timed calls per figure (median; default {REPEATS})")
    args = parser.parse_args()
    population = QUICK_POPULATION if args.quick else POPULATION
    repeats = args.repeats or (QUICK_REPEATS if args.quick else REPEATS)

    print(
        f"navigation at population {population:,}, median of {repeats}, {thread_count()} threads, "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    rows = measure(population, repeats)

    print(f"\n### Navigation ({population:,} individuals evolved for {EVOLVED_GENERATIONS} generations)\n")
    print(markdown_table(rows, COLUMNS))
    print("\n### Target\n")
    print(target_line(rows))
    print(budget_line(rows))

    path = BENCHMARKS / "navigation.csv"
    write_csv(path, rows)
    print(f"\nwrote {path.relative_to(ROOT)}")
    print(f"peak RSS {peak_rss_mb():.0f} MB, load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
