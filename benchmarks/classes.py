"""What finding homotopy classes costs (issue 30), beside the path search every run already does.

Usage:
    python benchmarks/classes.py                  # 200 evolved factory floors, median of 3 (~1 min)
    python benchmarks/classes.py --floors 500 --max-classes 4

Evolves the factory example (population 1,000, 10 generations) and takes the valid, solvable floors
of its final population. Times, after a warm-up call that compiles every kernel: the path search
(``navigate``: solvability and path length of every floor, one call), the survey (the path and
BARN's difficulty metrics), the number of classes of every floor in one compiled call
(``class_counts``: what a suite's measure and the ``classes`` fitness term read) and the classes of
every floor named with their paths and gaps (``floor_topology``, floor by floor), with the default
settings and with ``--max-classes``; medians of wall time, on the threads in use (``--threads``).
Prints the seconds per floor and each one's ratio to the path search, the mean number of classes,
and how many floors hit the limit; writes ``benchmarks/classes.csv``.
"""

from __future__ import annotations

import argparse
import tempfile
from functools import partial
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, median_seconds, write_csv

import mazegen
from mazegen.runtime.engine import Population, Problem
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.navigation import class_counts, floor_topology, navigate, survey
from mazegen.runtime.threads import threads

COLUMNS = [
    ("operation", "operation", "s"),
    ("ms_per_floor", "ms per floor", ".4f"),
    ("ratio", "× path search", ".0f"),
    ("classes", "mean classes", ".2f"),
    ("at_limit", "floors at the limit", "d"),
]


def floors_of_a_run(count: int) -> Population:
    """Valid, solvable floors of an evolved factory population, at most ``count``."""
    with tempfile.TemporaryDirectory(prefix="mazegen-classes-") as temp:
        spec = ROOT / "examples" / "factory.maze"
        result = mazegen.run(spec, population=1000, generations=10, out_dir=temp, force=True, catalog=False)
        problem = Problem.from_build_dir(Path(temp) / "experiment")
    final = result.runs[0]
    _, pop = problem.decode(final.codons, final.genes)
    rows = np.flatnonzero(pop.valid & navigate(pop, grid_of(pop.arena)).solvable)[:count]
    return problem.decode(final.codons[rows], final.genes[rows])[1]


def classes_of_all(pop: Population, max_classes: int) -> list[int]:
    grid = grid_of(pop.arena)
    return [len(floor_topology(pop, grid, i, max_classes=max_classes).classes) for i in range(pop.size)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--floors", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--max-classes", type=int, default=4)
    parser.add_argument("--threads", type=int, default=2, help="threads the compiled calls use")
    args = parser.parse_args()
    with threads(args.threads):
        measure(args)


def measure(args: argparse.Namespace) -> None:
    pop = floors_of_a_run(args.floors)
    grid = grid_of(pop.arena)
    search = median_seconds(partial(navigate, pop, grid), repeats=args.repeats)
    rows = [{"operation": "path search (navigate)", "seconds": search, "classes": None, "at_limit": None}]
    rows.append({"operation": "survey (path and difficulty metrics)", "seconds": median_seconds(
        partial(survey, pop), repeats=args.repeats), "classes": None, "at_limit": None})  # fmt: skip
    for limit in (mazegen.spec.MAX_CLASSES, args.max_classes):
        counted = partial(class_counts, pop, grid, max_classes=limit)
        numbers = counted()
        seconds = median_seconds(counted, repeats=args.repeats)
        rows.append({
            "operation": f"class counts, one call (at most {limit})", "classes": float(np.mean(numbers)),
            "seconds": seconds, "at_limit": int(np.sum(numbers == limit)),
        })  # fmt: skip
    for limit in (mazegen.spec.MAX_CLASSES, args.max_classes):
        counts = classes_of_all(pop, limit)
        seconds = median_seconds(partial(classes_of_all, pop, limit), repeats=args.repeats, warmup=0)
        at_limit = sum(count == limit for count in counts)
        name = f"classes named, floor by floor (at most {limit})"
        rows.append(
            {"operation": name, "seconds": seconds, "classes": float(np.mean(counts)), "at_limit": at_limit}
        )
    for row in rows:
        row["ms_per_floor"] = 1000 * row["seconds"] / pop.size
        row["ratio"] = row["seconds"] / search
    print(f"{pop.size} floors of the factory example, grid {grid.cols} x {grid.rows} cells\n")
    print(markdown_table(rows, COLUMNS))
    write_csv(BENCHMARKS / "classes.csv", rows)


if __name__ == "__main__":
    main()
