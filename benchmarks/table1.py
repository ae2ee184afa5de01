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
import statistics
import time
from pathlib import Path

from common import BENCHMARKS, ROOT, markdown_table, peak_rss_mb, run_json, write_csv

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
    means = [float(r.fitness[r.fitness > float("-inf")].mean()) for r in result.runs]
    return {
        "experiment": number,
        "population": spec.evolution.population,
        "generations": spec.evolution.generations,
        "runs": runs,
        "seconds": seconds,
        "seconds_per_run": seconds / runs,
        "individuals_per_s": individuals / seconds,
        "evaluations": evaluations,
        "evaluations_per_s": evaluations / seconds,
        "peak_rss_mb": peak_rss_mb(),
        "best_max": max(bests),
        "best_mean": statistics.mean(bests),
        "final_mean": statistics.mean(means),
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


COLUMNS = [
    ("experiment", "exp", "d"),
    ("population", "population", ","),
    ("generations", "generations", "d"),
    ("runs", "runs", "d"),
    ("seconds", "total s", ".1f"),
    ("seconds_per_run", "s/run", ".2f"),
    ("individuals_per_s", "individuals/s", ",.0f"),
    ("evaluations_per_s", "evaluations/s", ",.0f"),
    ("peak_rss_mb", "peak RSS MB", ".0f"),
    ("best_max", "best (max of runs)", "g"),
    ("best_mean", "best (mean of runs)", ".2f"),
    ("final_mean", "mean fitness (last gen.)", ".2f"),
    ("paper_best_mean", "paper: mean best", ".2f"),
    ("paper_minutes", "paper: minutes", "g"),
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiments", type=int, nargs="+", default=list(range(1, 9)))
    parser.add_argument("--runs", type=int, default=15)
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "table1.csv")
    parser.add_argument("--single", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.single:
        print(json.dumps(run_one(args.single, args.runs)))
        return
    paper = paper_figures()
    rows = [
        {**run_json(__file__, "--single", str(number), "--runs", str(args.runs)), **paper.get(number, {})}
        for number in args.experiments
    ]
    print(markdown_table(rows, COLUMNS))
    total = sum(r["seconds"] for r in rows)
    evaluations = sum(r["evaluations"] for r in rows)
    print(f"\ntotal: {total:.1f} s, {evaluations:,} evaluations ({evaluations / total:,.0f}/s)")
    write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
