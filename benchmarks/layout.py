"""Designed layouts against random ones (issue 28, point 6): examples/layout.maze's evolved floors
against random floors of the same required elements, by the length of the robot's tasks.

Usage:
    python benchmarks/layout.py                  # 5 runs, 2,000 random layouts (~2 min)
    python benchmarks/layout.py --runs 2 --random 500

Random layouts hold the same required elements (six racks, two lines), each at a uniform random
size, allowed rotation and position, redrawn until it is inside the arena and overlaps no other
(random genomes of the spec are almost never valid: eight large elements rarely all fit), and are
kept when every task has a path, as the evolved ones have. For each floor:
the tasks' path lengths summed (metres; the straight-line sum is the least there is). Evolved: the
best floor of each of ``--runs`` runs (seeds 1..runs). Prints a Markdown table and writes
``benchmarks/layout.csv``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, write_csv
from shapely import box
from shapely.affinity import rotate

import mazegen
from mazegen.runtime import metrics
from mazegen.runtime.engine import PLACEMENT_GENES, Population
from mazegen.runtime.geometry import ElementTable
from mazegen.spec import Spec

SPEC = ROOT / "examples" / "layout.maze"
VALID = ("overlap", "outside", "solvable")
"""The penalty terms a valid layout scores 0 on."""


def random_layouts(spec: Spec, count: int, seed: int) -> tuple[int, np.ndarray]:
    """``count`` random layouts of the spec's required elements, each element at a uniform random size,
    allowed rotation and position, redrawn until it lies inside the arena and overlaps none placed
    before (shapely decides, not MazeGen); how many of them give every task a path, and those
    layouts' summed task path lengths."""
    rng = np.random.default_rng(seed)
    arena, names = spec.arena, list(spec.scenario.elements)
    needed = [name for name, number, _ in spec.scenario.required for _ in range(number)]
    ids = np.full((count, len(needed)), -1, np.int32)
    params = np.zeros((count, len(needed), PLACEMENT_GENES))
    bounds = box(0, 0, arena.width, arena.height)
    for i in range(count):
        placed: list = []
        for k, name in enumerate(needed):
            kind = spec.element(name)
            while True:
                width = rng.uniform(*kind.size)
                depth = rng.uniform(*kind.size2) if kind.size2 else width
                angle = float(rng.choice(kind.rotations))
                x, y = rng.uniform(0, arena.width), rng.uniform(0, arena.height)
                shape = rotate(box(x - width / 2, y - depth / 2, x + width / 2, y + depth / 2), angle, (x, y))
                if bounds.contains(shape) and not any(shape.intersects(other) for other in placed):
                    break
            placed.append(shape)
            ids[i, k] = names.index(name)
            params[i, k] = (x, y, width, depth, np.radians(angle))
    table = ElementTable.from_types(spec.scenario_elements)
    counts = np.full(count, len(needed), np.int32)
    floors = Population(ids, counts, lambda: params, np.ones(count, bool), table, arena)
    solvable = metrics.unsolvable(floors) == 0
    return int(solvable.sum()), metrics.travel_length(floors, "total")[solvable]


def evolved_layouts(runs: int, folder: Path) -> list[float]:
    """The summed task path lengths of the best floor of each run (seeds 1..runs)."""
    found = []
    for seed in range(1, runs + 1):
        result = mazegen.run(SPEC, seed=seed, runs=1, out_dir=folder / f"seed-{seed}", catalog=False)
        best = result.best[0][0]
        assert all(best["terms"][key] == 0 for key in VALID), best["terms"]
        found.append(sum(task["metrics"]["path_length"] for task in best["tasks"]))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--random", type=int, default=2_000, help="random layouts drawn")
    args = parser.parse_args()
    spec = mazegen.load(SPEC)
    straight = sum(np.hypot(t.goal[0] - t.start[0], t.goal[1] - t.start[1]) for t in spec.arena.tasks)
    with tempfile.TemporaryDirectory(prefix="mazegen-layout-") as temp:
        folder = Path(temp)
        valid, random_totals = random_layouts(spec, args.random, seed=7)
        evolved = evolved_layouts(args.runs, folder)
    rows = [
        {
            "floors": f"random ({valid:,} valid of {args.random:,})",
            "count": valid,
            "median": statistics.median(random_totals),
            "best": float(random_totals.min()),
            "worst": float(random_totals.max()),
        },
        {
            "floors": f"evolved (best of each of {args.runs} runs)",
            "count": len(evolved),
            "median": statistics.median(evolved),
            "best": min(evolved),
            "worst": max(evolved),
        },
    ]
    print(f"Tasks' path lengths summed, metres (straight lines: {straight:.2f} m)\n")
    columns = [
        ("floors", "floors", ""),
        ("median", "median", ".2f"),
        ("best", "best", ".2f"),
        ("worst", "worst", ".2f"),
    ]
    print(markdown_table(rows, columns))
    shorter = 1 - rows[1]["median"] / rows[0]["median"]
    as_short = np.mean(random_totals <= rows[1]["worst"])
    print(f"\nevolved median {shorter:.1%} shorter than the random median;")
    print(f"{as_short:.1%} of the random layouts are as short as the worst evolved one")
    write_csv(BENCHMARKS / "layout.csv", rows)


if __name__ == "__main__":
    main()
