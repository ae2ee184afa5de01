"""Search quality: MazeGen's crossover and mutation operators against each other, and alogos on the
Figure 1 task: best fitness at equal numbers of evaluations, and time to a stated target.

Usage:
    python benchmarks/quality.py [--seeds 10] [--tasks figure1 exp3 exp5 workshop] [--no-alogos]
                                 [--csv benchmarks/quality.csv]

Tasks (each at its own fixed budget, the same for every contender: population × (generations + 1)
individuals):

* ``figure1``: the paper's Figure 1 count task with ``benchmarks/peers.py``'s settings (tournament 3,
  crossover 0.9, mutation 0.05, genome 32, population 1,000, 15 generations); alogos runs it too
  (when installed: ``pip install -e .[bench]``).
* ``exp3``, ``exp5``: Table 1's experiments 3 (count) and 5 (count with a size-limit penalty) as
  written in ``examples/table1`` (truncation 0.1, population 1,000, 15 generations).
* ``workshop``: the rich floor of ``examples/workshop.maze`` (count, no overlap, on the floor,
  solvable, diversity, coverage) at population 1,000 and 30 generations (its own 4,000 x 60 is
  too long to repeat ten times here); also the median number of elements and element types of
  each run's best floor.

MazeGen's operators (see ``docs/language.md``): ``genome`` is MazeGen's first pair (one cut anywhere
in the genome, placement rows cut apart, int-flip over every codon), ``onepoint`` and ``variable``
PonyGE2's fixed and variable one-point crossover within the used codons with int-flip within the
used codons, ``variable+genome`` variable crossover with int-flip over every codon. Run ``s`` of a
contender uses seed ``s`` (MazeGen: ``numpy.random.default_rng(s)`` into the engine's ``evolve``;
alogos: ``random.seed(s)``). Fitness at equal evaluations decides, not wall time: the machine may be
shared; time to target is wall seconds from the start of a run (generation 0 included) until its
best reaches the task's target, reported as the median over the runs that reach it.
"""

from __future__ import annotations

import argparse
import dataclasses
import random
import statistics
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, write_csv

import mazegen
from mazegen.runtime.engine._evolution import RunResult, evolve
from mazegen.runtime.engine._problem import Problem
from mazegen.spec import Spec


@dataclasses.dataclass(frozen=True)
class Task:
    """A spec, the evolution settings that fix its budget, and the fitness that counts as reached."""

    spec: Path
    settings: dict[str, object]
    target: float
    fitness: str = ""  # a term added to the spec's fitness block


FIGURE1 = {"selection": "tournament", "tournament": 3, "crossover": 0.9, "mutation": 0.05}
TASKS = {
    "figure1": Task(ROOT / "examples" / "mazegen1.maze", {**FIGURE1, "population": 1000}, 16),
    "figure1-5000": Task(ROOT / "examples" / "mazegen1.maze", {**FIGURE1, "population": 5000}, 16),
    "exp3": Task(ROOT / "examples" / "table1" / "exp3.maze", {}, 32),
    "exp5": Task(ROOT / "examples" / "table1" / "exp5.maze", {}, 32),
    "workshop": Task(ROOT / "examples" / "workshop.maze", {}, 60),
    "difficulty": Task(
        ROOT / "examples" / "workshop.maze",
        {"population": 1000, "generations": 30},
        60,
        "difficulty target hard weight 8",
    ),
}
OPERATORS = {
    "genome": ("onepoint within genome", "within genome"),
    "onepoint": ("onepoint within used", "within used"),
    "variable": ("variable within used", "within used"),
    "variable+genome": ("variable within used", "within genome"),
}

COLUMNS = [
    ("task", "task", ""),
    ("contender", "operators", ""),
    ("evaluations", "individuals", ",d"),
    ("median", "median best", "g"),
    ("spread", "min..max (IQR)", ""),
    ("reached", "reached target", ""),
    ("seconds", "median s to target", ".3f"),
    ("elements", "median elements", "g"),
    ("types", "median types", "g"),
]


def spread(values: Sequence[float]) -> str:
    """``min..max (q1..q3)`` of ``values``."""
    q1, _, q3 = statistics.quantiles(values, n=4, method="inclusive")
    return f"{min(values):g}..{max(values):g} ({q1:g}..{q3:g})"


def seconds_to(result: RunResult, target: float) -> float | None:
    """Wall seconds from the start of the run until its best first reaches ``target``, if it does."""
    elapsed = 0.0
    for row in result.stats:
        elapsed += row.seconds
        if row.best >= target:
            return elapsed
    return None


def best_floor(problem: Problem, result: RunResult) -> tuple[int, int]:
    """Elements and distinct element types of the run's best floor."""
    best = int(np.argmax(result.fitness))
    mapped = problem.evaluate(result.codons[best : best + 1], result.genes[best : best + 1]).mapped
    ids = mapped.element_ids[0, : mapped.n_elements[0]]
    return int(ids.size), int(np.unique(ids).size)


def summary(task: str, contender: str, evaluations: int, target: float, runs: list[dict]) -> dict:
    """One table row from the runs of one contender on one task."""
    bests = [run["best"] for run in runs]
    reached = [run["seconds"] for run in runs if run["seconds"] is not None]
    floors = [run["floor"] for run in runs if run.get("floor")]
    return {
        "task": task,
        "contender": contender,
        "evaluations": evaluations,
        "median": statistics.median(bests),
        "spread": spread(bests),
        "reached": f"{len(reached)}/{len(runs)} ≥ {target:g}",
        "seconds": statistics.median(reached) if reached else None,
        "elements": statistics.median(f[0] for f in floors) if floors else None,
        "types": statistics.median(f[1] for f in floors) if floors else None,
    }


def race_mazegen(name: str, task: Task, spec: Spec, seeds: int, build_dir: Path) -> list[dict]:
    """Every operator pair on one task, ``seeds`` runs each."""
    mazegen.build(spec, build_dir)
    problem = Problem.from_build_dir(build_dir)
    base = problem.spec.evolution
    warmup = dataclasses.replace(base, population=50, generations=1)
    evolve(problem, warmup, np.random.default_rng(0))  # compiles the kernels before any run is timed
    floors = problem.spec.scenario.name == "workshop"
    rows = []
    for contender, (crossover, mutation) in OPERATORS.items():
        settings = dataclasses.replace(base, crossover_operator=crossover, mutation_operator=mutation)
        runs = []
        for seed in range(seeds):
            result = evolve(problem, settings, np.random.default_rng(seed))
            runs.append(
                {
                    "best": float(result.fitness.max()),
                    "seconds": seconds_to(result, task.target),
                    "floor": best_floor(problem, result) if floors else None,
                }
            )
        evaluations = settings.population * (settings.generations + 1)
        rows.append(summary(name, f"MazeGen {contender}", evaluations, task.target, runs))
        print(markdown_table(rows[-1:], COLUMNS).splitlines()[-1], flush=True)
    return rows


def race_alogos(name: str, task: Task, seeds: int) -> dict:
    """alogos on the Figure 1 task, a generation at a time to time its best against the target."""
    import alogos
    from alogos.systems import ge
    from peers import BNF, FigureCount, alogos_ea

    ge.default_parameters.max_wraps = 0  # as benchmarks/peers.py: the EA's own setting does not reach it
    grammar = alogos.Grammar(bnf_text=BNF)
    population, generations = int(task.settings["population"]), 15
    runs = []
    for seed in range(seeds):
        random.seed(seed)
        ea = alogos_ea(grammar, FigureCount(), population, generations)
        started, reached = time.perf_counter(), None
        for _ in range(generations + 1):
            best = ea.step()
            if reached is None and best.fitness >= task.target:
                reached = time.perf_counter() - started
        runs.append({"best": float(best.fitness), "seconds": reached})
    return summary(name, "alogos", population * (generations + 1), task.target, runs)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--tasks", nargs="+", choices=sorted(TASKS), default=list(TASKS))
    parser.add_argument("--no-alogos", action="store_true", help="race MazeGen's operators only")
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "quality.csv")
    args = parser.parse_args()
    if args.seeds < 2:
        parser.error("--seeds must be at least 2 (the spread needs quartiles)")
    rows = []
    with tempfile.TemporaryDirectory(prefix="mazegen-quality-") as temp:
        for name in args.tasks:
            task = TASKS[name]
            source = task.spec
            if task.fitness:  # a copy with one more term (the spec imports bundled libraries only)
                source = Path(temp) / f"{name}.maze"
                text = task.spec.read_text(encoding="utf-8")
                added = text.replace("fitness {", f"fitness {{\n{task.fitness}", 1)
                source.write_text(added, encoding="utf-8")
            spec = mazegen.load(source).with_evolution(**task.settings)
            rows += race_mazegen(name, task, spec, args.seeds, Path(temp) / name)
            if name.startswith("figure1") and not args.no_alogos:
                rows.append(race_alogos(name, task, args.seeds))
                print(markdown_table(rows[-1:], COLUMNS).splitlines()[-1], flush=True)
    print()
    print(markdown_table(rows, COLUMNS))
    write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
