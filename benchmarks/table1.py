"""Table 1 of the MazeGen paper, rerun: time, throughput, memory and fitness per experiment.

Usage:
    python benchmarks/table1.py [--experiments 1 2 ... 8] [--runs 15] [--csv benchmarks/table1.csv]

Each experiment runs in its own process (so peak RSS is its own) from
``examples/table1/expN.maze``. The paper's published figures are read from
``../shared/anchors/mazegen-results/`` when that folder is present.
"""

from __future__ import annotations

import argparse
import csv
import json
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAPER = ROOT.parent / "shared" / "anchors" / "mazegen-results"
# experiment -> (BNF_Version, Population, Fitnes_Function) in the paper's CSV
PAPER_KEYS = {
    1: ("1", "1000", "ffv1"),
    2: ("1", "5000", "ffv1"),
    3: ("1.5", "1000", "ffv15np"),
    4: ("1.5", "5000", "ffv15np"),
    5: ("1.5", "1000", "ffv15p"),
    6: ("1.5", "5000", "ffv15p"),
    7: ("1.5", "10000", "ffv15p"),
    8: ("1.5", "50000", "ffv15p"),
}


def run_one(number: int, runs: int) -> dict:
    """Run experiment ``number`` in this process and return its figures."""
    import mazegen

    spec = mazegen.load(ROOT / "examples" / "table1" / f"exp{number}.maze")
    mazegen.run(spec, runs=1, population=50, generations=1)  # load the compiled kernels first
    started = time.perf_counter()
    result = mazegen.run(spec, runs=runs)
    seconds = time.perf_counter() - started
    bests = [float(r.fitness[r.fitness > float("-inf")].max()) for r in result.runs]
    evaluations = sum(sum(row.evaluations for row in r.stats) for r in result.runs)
    individuals = runs * spec.evolution.population * (spec.evolution.generations + 1)
    return {
        "experiment": number,
        "population": spec.evolution.population,
        "generations": spec.evolution.generations,
        "runs": runs,
        "seconds": seconds,
        "seconds_per_run": seconds / runs,
        "individuals_per_s": individuals / seconds,
        "evaluations": evaluations,
        "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
        "best_max": max(bests),
        "best_mean": statistics.mean(bests),
    }


def paper_figures() -> dict[int, dict]:
    """The paper's fitness (mean of per-run maxima) and time per experiment, where published."""
    if not PAPER.is_dir():
        return {}
    per_run: dict[tuple, dict[str, float]] = {}
    with open(PAPER / "MazegenDataset.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            key = (row["BNF_Version"], row["Population"], row["Fitnes_Function"])
            runs = per_run.setdefault(key, {})
            runs[row["Run_Number"]] = max(runs.get(row["Run_Number"], 0.0), float(row["Fitness_Score"]))
    minutes = {}
    with open(PAPER / "MazegenExecutingTimeDataset.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            if row.get("BNF_Version"):
                minutes[(row["BNF_Version"], row["Population"])] = float(row["Execution_Time"])
    figures = {}
    for number, key in PAPER_KEYS.items():
        runs = per_run.get(key, {})
        figures[number] = {
            "paper_best_mean": statistics.mean(runs.values()) if runs else None,
            "paper_minutes": minutes.get(key[:2]),
        }
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiments", type=int, nargs="+", default=list(range(1, 9)))
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument("--csv", type=Path, default=ROOT / "benchmarks" / "table1.csv")
    parser.add_argument("--single", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.single:
        print(json.dumps(run_one(args.single, args.runs)))
        return
    paper = paper_figures()
    rows = []
    for number in args.experiments:
        done = subprocess.run(
            [sys.executable, __file__, "--single", str(number), "--runs", str(args.runs)],
            capture_output=True,
            text=True,
            check=True,
        )
        rows.append({**json.loads(done.stdout.splitlines()[-1]), **paper.get(number, {})})
    print(
        "| exp | population × generations | runs | total s | s/run | individuals/s | peak RSS MB "
        "| best (max / mean of runs) | paper: mean best | paper: minutes |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        paper_best = "—" if r.get("paper_best_mean") is None else f"{r['paper_best_mean']:.2f}"
        paper_minutes = "—" if r.get("paper_minutes") is None else f"{r['paper_minutes']:g}"
        print(
            f"| {r['experiment']} | {r['population']:,} × {r['generations']} | {r['runs']} "
            f"| {r['seconds']:.1f} | {r['seconds_per_run']:.2f} | {r['individuals_per_s']:,.0f} "
            f"| {r['peak_rss_mb']:.0f} "
            f"| {r['best_max']:g} / {r['best_mean']:.2f} | {paper_best} | {paper_minutes} |"
        )
    print(f"\ntotal: {sum(r['seconds'] for r in rows):.1f} s")
    with open(args.csv, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
