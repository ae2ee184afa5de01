"""What several tasks per floor cost (issue 28, point 5): static evaluation of one population on floors
of 1, 4 and 16 tasks.

Usage:
    python benchmarks/tasks.py                 # population 2,000, median of 7 (~1 min)
    python benchmarks/tasks.py --population 5000 --repeats 5

The spec is the factory's elements on a 14 x 10.5 m arena with ``solvable required`` and a difficulty
target (so that every task's path is searched and surveyed); its tasks are drawn (``tasks N seed 1 min
distance 5 m``). The same random genomes are evaluated under each (mapping, decoding, every term),
after two untimed calls; medians of wall time. A floor of N tasks is measured once per task, so the
searches cost about N times as much while mapping, placement and the configuration space are shared.
Prints a Markdown table and writes ``benchmarks/tasks.csv``.
"""

from __future__ import annotations

import argparse
import tempfile
from functools import partial
from pathlib import Path

import numpy as np
from common import BENCHMARKS, markdown_table, median_seconds, write_csv

import mazegen
from mazegen.runtime.engine._operators import random_codons, random_genes
from mazegen.runtime.engine._problem import Problem

SPEC = """
import manufacturing
arena hall {{ size 1400 x 1050 cm  robot radius 25  {tasks} }}
scenario floor on hall {{ elements cobot, router, vwall, hwall  max elements 16 }}
fitness {{ count  overlap penalty 0.5  solvable required  difficulty target medium }}
evolution {{ population 2000  generations 1  genome 32  seed 1 }}
"""
TASKS = {
    1: "start (60, 60)  goal (1340, 990)",
    4: "tasks 4 seed 1 min distance 5 m",
    16: "tasks 16 seed 1 min distance 5 m",
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", type=int, default=2_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory(prefix="mazegen-tasks-") as temp:
        rng = np.random.default_rng(3)
        codons = random_codons(rng, args.population, 32, 255)
        genes = random_genes(rng, args.population, 16)
        for count, words in TASKS.items():
            path = Path(temp) / f"tasks{count}.maze"
            path.write_text(SPEC.format(tasks=words))
            mazegen.build(mazegen.load(path), Path(temp) / f"build{count}")
            problem = Problem.from_build_dir(Path(temp) / f"build{count}")
            seconds = median_seconds(partial(problem.evaluate, codons, genes), repeats=args.repeats, warmup=2)
            rows.append({"tasks": count, "seconds": seconds, "per_second": args.population / seconds})
    for row in rows:
        row["times_one"] = row["seconds"] / rows[0]["seconds"]
    columns = [
        ("tasks", "tasks per floor", "d"),
        ("seconds", "s per evaluation", ".4f"),
        ("per_second", "individuals/s", ",.0f"),
        ("times_one", "× one task", ".2f"),
    ]
    print(f"Static evaluation of {args.population:,} individuals, median of {args.repeats}\n")
    print(markdown_table(rows, columns))
    write_csv(BENCHMARKS / "tasks.csv", rows)


if __name__ == "__main__":
    main()
