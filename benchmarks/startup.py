"""Start-up: what a user waits for before any evolution or driving, timed as whole ``mazegen`` commands.

Usage:
    python benchmarks/startup.py [--repeats 5] [--controllers straight purepursuit dwa vfh]
                                 [--csv benchmarks/startup.csv]

Times, as subprocesses (wall clock): ``mazegen check`` of the factory example and, with numba's
cache warm, ``mazegen run`` of it and ``mazegen drive`` of its best scenarios with each bundled
controller (medians of ``--repeats``); then what a new user meets: the first ``mazegen run`` of
the factory example with an empty kernel cache (``NUMBA_CACHE_DIR`` a fresh folder), and the
first drive with each controller after that run (each from a copy of the cache the run left, so
that every controller compiles as if it were the first one driven). The cold figures are single
runs: each compiles everything once; so is the first run of the Python API, which compiles in its
own process (as ``resume`` and ``sweep`` do) where ``mazegen run`` uses both cores. The goals are
the issue's: a first run within 20 s and a first drive within 15 s on a quiet 2-core machine; the
warm ones are what the README quotes.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import BENCHMARKS, ROOT, markdown_table, median_seconds, write_csv

from mazegen.controllers import BY_CODE

FACTORY = str(ROOT / "examples" / "factory.maze")
CONTROLLERS = tuple(row.name for row in BY_CODE)
GOALS = {
    "check": 1.0,
    "run (warm cache)": 2.0,
    "drive (warm cache)": 2.0,
    "first run": 20.0,
    "first drive": 15.0,
}
API_RUN = "import sys, mazegen; mazegen.run(sys.argv[1], out_dir=sys.argv[2], force=True)"
"""A run of the Python API, which compiles in its own process, as ``resume`` and ``sweep`` do."""
COLUMNS = [("command", "command", "s"), ("seconds", "s", ".2f"), ("goal_s", "goal s", "g"),
           ("verdict", "verdict", "s")]  # fmt: skip


def mazegen(*args: str, cache: str | None = None) -> float:
    """Run ``mazegen ARGS`` (with kernel cache ``cache``, if given) and return its wall time in seconds."""
    env = dict(os.environ) if cache is None else {**os.environ, "NUMBA_CACHE_DIR": cache}
    started = time.perf_counter()
    done = subprocess.run(
        [shutil.which("mazegen") or "mazegen", *args], capture_output=True, text=True, env=env, check=False
    )
    seconds = time.perf_counter() - started
    if done.returncode != 0:
        raise SystemExit(f"mazegen {' '.join(args)} failed:\n{done.stderr}")
    return seconds


def python_run(spec: str, out: str, cache: str) -> float:
    """Wall seconds of :data:`API_RUN` with kernel cache ``cache``."""
    started = time.perf_counter()
    subprocess.run(
        [sys.executable, "-c", API_RUN, spec, out], env={**os.environ, "NUMBA_CACHE_DIR": cache}, check=True,
        capture_output=True,
    )  # fmt: skip
    return time.perf_counter() - started


def row(command: str, seconds: float, goal_key: str | None) -> dict:
    goal = GOALS.get(goal_key or "")
    if goal is None:
        return {"command": command, "seconds": seconds, "goal_s": None, "verdict": None}
    return {
        "command": command,
        "seconds": seconds,
        "goal_s": goal,
        "verdict": "PASS" if seconds <= goal else "FAIL",
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--controllers", nargs="+", choices=CONTROLLERS, default=list(CONTROLLERS))
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "startup.csv")
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory(prefix="mazegen-startup-") as temp:
        run_dir = str(Path(temp) / "run")
        run = ("run", FACTORY, "-q", "--force", "-o", run_dir)

        def drive(name: str) -> tuple[str, ...]:
            return ("drive", run_dir, "--controller", name, "--json")

        cold = str(Path(temp) / "cold-cache")  # empty: the first run compiles every kernel it calls
        rows.append(row("first run (empty kernel cache)", mazegen(*run, cache=cold), "first run"))
        alone = python_run(FACTORY, str(Path(temp) / "api-run"), str(Path(temp) / "api-cache"))
        rows.append(row("first run of the Python API (one process)", alone, None))
        for name in args.controllers:
            cache = str(Path(temp) / f"cache-{name}")
            shutil.copytree(cold, cache)  # the cache as the first run left it
            rows.append(row(f"first drive, {name}", mazegen(*drive(name), cache=cache), "first drive"))
        repeats = args.repeats
        rows.append(row("check", median_seconds(lambda: mazegen("check", FACTORY), repeats=repeats), "check"))
        rows.append(
            row(
                "run (warm cache)", median_seconds(lambda: mazegen(*run), repeats=repeats), "run (warm cache)"
            )
        )
        for name in args.controllers:
            seconds = median_seconds(lambda name=name: mazegen(*drive(name)), repeats=repeats)
            rows.append(row(f"drive {name} (warm cache)", seconds, "drive (warm cache)"))
    print(markdown_table(rows, COLUMNS))
    write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
