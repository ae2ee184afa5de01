"""Peak memory of whole runs against population size, and its slope.

Usage:
    python benchmarks/memory.py [--populations 1000 10000 25000 50000 100000] [--genome 128]

Each point is one run of Table 1's experiment 8 (flat grammar, 30 generations, size
penalty) with the genome length and element slots set to ``--genome``, in a fresh
process so its peak RSS is its own. The slope is a least-squares line through the
points; the target is a run of 50,000 individuals at genome 128 under 1 GB.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np
from common import BENCHMARKS, ROOT, markdown_table, peak_rss_mb, run_json, write_csv

EXPERIMENT = ROOT / "examples" / "table1" / "exp8.maze"
TARGET_MB = 1024
COLUMNS = [
    ("population", "population", ","),
    ("genome", "genome", "d"),
    ("generations", "generations", "d"),
    ("seconds", "s", ".2f"),
    ("peak_rss_mb", "peak RSS MB", ".0f"),
    ("kb_per_individual", "KB per individual above start-up", ".2f"),
]


def run_one(population: int, genome: int, generations: int | None) -> dict:
    """One run in this process; its time and this process's peak RSS."""
    import mazegen

    spec = mazegen.load(EXPERIMENT)
    scenario = dataclasses.replace(spec.scenario, max_elements=genome)
    spec = dataclasses.replace(spec, scenario=scenario).with_evolution(
        population=population, genome=genome, runs=1, **({"generations": generations} if generations else {})
    )
    started = time.perf_counter()
    mazegen.run(spec)
    return {
        "population": population,
        "genome": genome,
        "generations": spec.evolution.generations,
        "seconds": time.perf_counter() - started,
        "peak_rss_mb": peak_rss_mb(),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--populations", type=int, nargs="+", default=[1000, 10000, 25000, 50000, 100000])
    parser.add_argument("--genome", type=int, default=128)
    parser.add_argument("--generations", type=int, help="override the experiment's 30 generations")
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "memory.csv")
    parser.add_argument("--single", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.single:
        print(json.dumps(run_one(args.single, args.genome, args.generations)))
        return
    extra = ["--generations", str(args.generations)] if args.generations else []
    rows = [
        run_json(__file__, "--single", str(p), "--genome", str(args.genome), *extra) for p in args.populations
    ]
    baseline = run_json(__file__, "--single", "1", "--genome", str(args.genome), "--generations", "1")
    sizes = np.array([r["population"] for r in rows], dtype=float)
    rss = np.array([r["peak_rss_mb"] for r in rows])
    slope, intercept = np.polyfit(sizes, rss, 1)
    fitted = slope * sizes + intercept
    r2 = 1 - ((rss - fitted) ** 2).sum() / ((rss - rss.mean()) ** 2).sum()
    for row in rows:
        row["kb_per_individual"] = (row["peak_rss_mb"] - baseline["peak_rss_mb"]) * 1024 / row["population"]
    print(markdown_table(rows, COLUMNS))
    print(
        f"\nstart-up (1 individual): {baseline['peak_rss_mb']:.0f} MB; slope {slope * 1024:.2f} KB per "
        f"individual, intercept {intercept:.0f} MB, R² {r2:.4f}"
    )
    at_target = [r for r in rows if r["population"] == 50000]
    if at_target:
        mb = at_target[0]["peak_rss_mb"]
        print(f"50,000 × genome {args.genome}: {mb:.0f} MB — {'PASS' if mb < TARGET_MB else 'FAIL'} (< 1 GB)")
    write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
