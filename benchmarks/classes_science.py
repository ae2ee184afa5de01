"""Do floors of one homotopy class make one test (issue 30, part 4)? Measured difficulty against classes.

Usage:
    python benchmarks/classes_science.py                       # ~25 s warm (+30 s compiling, on first use)
    python benchmarks/classes_science.py --permutations 2000 --seed 2 --top 8
    python benchmarks/classes_science.py --no-run              # part 1 only: no run, no suite

Part 1: is measured controller difficulty more alike within a class than between classes? Two sets
of floors with measured drives, grouped by their canonical class (``signature``, docs/classes.md):

- the calibration floors (``tests/runtime/navigation/calibration_floors.json``: 180 of
  ``workshop.maze``, 180 of ``factory.maze``) with their measured difficulty from
  ``calibration_data.csv``: per floor the mean over the four controllers of time over optimal time
  (a failure counted at the timeout factor), scaled to 0 at the optimal time and 1 at the timeout,
  as ``benchmarks/calibration.py`` and the calibration tests read it (``measured_target``);
- the 150 training worlds of ``../shared/anchors/barn/barn-train.json``, imported with ``mazegen
  import`` as ``benchmarks/barn_validation.py`` does (a 0.30 m robot, the start and goal of BARN's 2020
  timing runs), with BARN's measured Gazebo DWA difficulty ``target_dwa`` (mean over 5 runs of time
  over path length, a 50 s timeout counted as 30 s). The held-out half is never read.

Per set (and per calibration spec) the one-way analysis of variance of the difficulty by group:
within-group sum of squares over the total (1 − η²), beside its expected value were the labels
random, (N − k) / (N − 1) for N floors in k groups (singletons alone make it fall), the F
statistic, and a permutation p-value (the group labels shuffled ``--permutations`` times, seeded; p
is the share of shuffles with a between-group sum of squares at least the observed one, counting
the observed labels once). Floors alone in their group carry no within-group information, so the
test is also run on the floors whose signature is shared (groups of two or more), and grouped by
the number of classes instead of the signature. The largest groups are listed with their mean
difficulty.

Part 2: how many distinct tests do a run's ten best floors and a suite hold? A run of
``examples/factory.maze`` with its defaults and a ``mazegen suite --size 20`` of it (in temporary
folders), classified by ``mazegen.classes``: distinct signatures over floors, the groups it forms,
and how many floors reach the kept-classes limit (``MAX_CLASSES``; their signature is the set of
their shortest classes only).

Writes ``benchmarks/classes_science.csv``: one row per floor (source, floor, number of classes,
signature, measured difficulty where there is one), from which any other grouping can be tested.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np
from calibration import DATA, FLOORS, saved_floors
from common import BENCHMARKS, ROOT, markdown_table, write_csv
from heterogeneous import BARN, import_barn

import mazegen
from mazegen.runtime.documents import floor_classes, load_floor
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.navigation import floor_topology
from mazegen.runtime.navigation._calibration import (
    TARGET_CONTROLLERS,
    CalibrationFloors,
    measured_target,
    read_calibration,
)
from mazegen.spec import MAX_CLASSES

TESTS = [
    ("set", "floors of", "s"),
    ("grouping", "grouped by", "s"),
    ("floors", "floors", "d"),
    ("groups", "groups", "d"),
    ("singletons", "groups of 1", "d"),
    ("largest", "largest group", "d"),
    ("ratio", "within / total variance", ".3f"),
    ("null", "same, labels at random", ".3f"),
    ("f", "F", ".2f"),
    ("p", "permutation p", ".4f"),
]
GROUPS = [
    ("set", "floors of", "s"),
    ("signature", "canonical class", "s"),
    ("floors", "floors", "d"),
    ("mean", "mean difficulty", ".3f"),
    ("sd", "sd", ".3f"),
]
DISTINCT = [
    ("source", "floors of", "s"),
    ("floors", "floors", "d"),
    ("distinct", "distinct signatures", "d"),
    ("share", "distinct / floors", ".2f"),
    ("groups", "groups (mazegen.classes)", "d"),
    ("at_limit", f"floors at {MAX_CLASSES} classes", "d"),
    ("mean_classes", "mean classes", ".2f"),
    ("min_classes", "fewest classes", "d"),
]


def calibration_set() -> list[dict]:
    """The calibration floors: per floor its spec, classes, signature and measured difficulty (the
    mean over :data:`TARGET_CONTROLLERS`, 0 at the optimal time, 1 at the timeout)."""
    saved = CalibrationFloors.read(FLOORS)
    data = read_calibration(DATA)
    target = measured_target(data, TARGET_CONTROLLERS)
    rows = []
    for floors in saved_floors(saved):
        grid = grid_of(floors.population.arena)
        for k, row in enumerate(floors.rows):
            top = floor_topology(floors.population, grid, int(row))
            rows.append({"source": f"calibration {floors.name}", "floor": f"{floors.name}-{k:03d}",
                         "classes": len(top.classes), "signature": top.signature})  # fmt: skip
    if [row["source"].split()[1] for row in rows] != [row["spec"] for row in data]:
        raise SystemExit(f"{FLOORS.name} and {DATA.name} list the floors in different orders")
    for row, value in zip(rows, target):
        row["difficulty"] = float(value)
    return rows


def barn_set(folder: Path) -> list[dict]:
    """BARN's training worlds, imported into ``folder``: per world its classes, signature and
    BARN's measured DWA difficulty (``target_dwa``)."""
    entries = {entry["world"]: entry for entry in json.loads(BARN.read_text())["worlds"]}
    rows = []
    for file in import_barn(folder, 1):
        floor = load_floor(file)
        number = int(floor.document["scenario"].rsplit("_", 1)[1])
        found = floor_classes(floor)
        rows.append({"source": "BARN train", "floor": f"world-{number:03d}", "classes": found.count,
                     "signature": found.signature,
                     "difficulty": float(entries[number]["target_dwa"])})  # fmt: skip
    return rows


def anova(values: np.ndarray, labels: list, permutations: int, seed: int) -> dict:
    """One-way ANOVA of ``values`` by ``labels``, with a permutation p-value (labels shuffled)."""
    codes = np.unique(np.array(labels, dtype=object).astype(str), return_inverse=True)[1]
    n, k = values.size, int(codes.max()) + 1
    sizes = np.bincount(codes, minlength=k)
    centred = values - values.mean()
    total = float((centred**2).sum())

    def between(sums: np.ndarray) -> np.ndarray:
        return (sums**2 / sizes).sum(axis=-1)  # the centred values sum to 0 overall

    observed = float(between(np.bincount(codes, weights=centred, minlength=k)))
    within = total - observed
    shuffled = np.random.default_rng(seed).permuted(np.tile(codes, (permutations, 1)), axis=1)
    offsets = (np.arange(permutations) * k)[:, None]
    sums = np.bincount((shuffled + offsets).ravel(), weights=np.tile(centred, permutations),
                       minlength=permutations * k).reshape(permutations, k)  # fmt: skip
    extreme = int((between(sums) >= observed - 1e-12 * total).sum())
    return {
        "floors": n,
        "groups": k,
        "singletons": int((sizes == 1).sum()),
        "largest": int(sizes.max()),
        "ratio": within / total,
        "null": (n - k) / (n - 1),
        "f": (observed / (k - 1)) / (within / (n - k)) if 1 < k < n and within > 0 else None,
        "p": (1 + extreme) / (1 + permutations) if k > 1 else None,
    }


def tests_of(name: str, rows: list[dict], permutations: int, seed: int) -> list[dict]:
    """The three tests of one set: by signature, by shared signature only, by number of classes."""
    values = np.array([row["difficulty"] for row in rows])
    signatures = [row["signature"] for row in rows]
    counts = Counter(signatures)
    shared = np.array([counts[s] > 1 for s in signatures])
    return [
        {"set": name, "grouping": "signature"} | anova(values, signatures, permutations, seed),
        {"set": name, "grouping": "signature, shared only"}
        | anova(values[shared], [s for s, keep in zip(signatures, shared) if keep], permutations, seed),
        {"set": name, "grouping": "number of classes"}
        | anova(values, [row["classes"] for row in rows], permutations, seed),
    ]


def largest_groups(name: str, rows: list[dict], top: int) -> list[dict]:
    """The ``top`` largest signature groups of a set, with their difficulty's mean and spread."""
    by: dict[str, list[float]] = {}
    for row in rows:
        by.setdefault(row["signature"], []).append(row["difficulty"])
    ordered = sorted(by.items(), key=lambda item: (-len(item[1]), item[0]))[:top]
    return [{"set": name, "signature": s, "floors": len(v), "mean": float(np.mean(v)),
             "sd": float(np.std(v, ddof=1)) if len(v) > 1 else None} for s, v in ordered]  # fmt: skip


def distinct_row(source: str, found) -> dict:
    """How many distinct tests ``mazegen.classes``' result ``found`` holds."""
    signatures = [floor.signature for floor in found.floors]
    counts = [floor.count for floor in found.floors]
    return {
        "source": source,
        "floors": len(signatures),
        "distinct": len(set(signatures)),
        "share": len(set(signatures)) / len(signatures),
        "groups": len(found.groups),
        "at_limit": sum(count >= MAX_CLASSES for count in counts),
        "mean_classes": float(np.mean(counts)),
        "min_classes": min(counts),
    }


def run_and_suite(folder: Path) -> tuple[list[dict], list[dict]]:
    """A default run and a 20-floor suite of the factory example, classified."""
    spec = ROOT / "examples" / "factory.maze"
    mazegen.run(spec, out_dir=folder / "run", force=True, catalog=False)
    done = subprocess.run(
        [sys.executable, "-m", "mazegen", "suite", str(spec), "--size", "20", "-o", str(folder / "suite"),
         "-q"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    if done.returncode != 0:
        raise SystemExit(f"mazegen suite failed:\n{done.stderr}")
    rows, floors = [], []
    for source, where in (("run (10 best)", folder / "run"), ("suite (--size 20)", folder / "suite")):
        found = mazegen.classes(where)
        rows.append(distinct_row(source, found))
        floors += [{"source": source, "floor": Path(f.file).name, "classes": f.count,
                    "signature": f.signature, "difficulty": None} for f in found.floors]  # fmt: skip
    return rows, floors


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--permutations", type=int, default=10_000, help="label shuffles per test")
    parser.add_argument("--seed", type=int, default=1, help="seed of the shuffles (each test's own)")
    parser.add_argument("--top", type=int, default=6, help="largest groups listed per set")
    parser.add_argument("--no-run", action="store_true", help="part 1 only: no run or suite")
    args = parser.parse_args()
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mazegen-classes-science-") as folder:
        calibration = calibration_set()
        barn = barn_set(Path(folder) / "barn")
        sets = {
            "calibration, both specs": calibration,
            "calibration workshop": [r for r in calibration if r["source"] == "calibration workshop"],
            "calibration factory": [r for r in calibration if r["source"] == "calibration factory"],
            "BARN train": barn,
        }
        distinct, made = ([], []) if args.no_run else run_and_suite(Path(folder))
    print(
        f"Part 1: measured difficulty by class. Calibration: mean of {', '.join(TARGET_CONTROLLERS)} "
        "(0 optimal .. 1 timeout); BARN: Gazebo DWA target_dwa (s/m, failures 30 s). "
        f"{args.permutations:,} permutations, seed {args.seed}.\n"
    )
    tests = [row for name, rows in sets.items() for row in tests_of(name, rows, args.permutations, args.seed)]
    print(markdown_table(tests, TESTS))
    for name, rows in sets.items():
        counts = Counter(row["signature"] for row in rows)
        alone = sum(1 for row in rows if counts[row["signature"]] == 1)
        verdict = " (most floors have a signature of their own)" if alone > len(rows) / 2 else ""
        print(f"- {name}: {len(counts)} signatures over {len(rows)} floors, {alone} floors alone in theirs"
              f" ({100 * alone / len(rows):.0f} %){verdict}")  # fmt: skip
    print("\nLargest groups (canonical class):\n")
    print(markdown_table([g for name in ("calibration workshop", "calibration factory", "BARN train")
                          for g in largest_groups(name, sets[name], args.top)], GROUPS))  # fmt: skip
    if distinct:
        print("\nPart 2: distinct tests among a run's ten best floors and a suite's (examples/factory.maze)")
        print()
        print(markdown_table(distinct, DISTINCT))
    write_csv(BENCHMARKS / "classes_science.csv", [*calibration, *barn, *made])
    print(f"\n{time.perf_counter() - started:.0f} s; wrote benchmarks/classes_science.csv")


if __name__ == "__main__":
    main()
