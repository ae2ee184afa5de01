"""Start-up: what a user waits for before any evolution, timed as whole ``mazegen`` commands.

Usage:
    python benchmarks/startup.py [--repeats 5] [--csv benchmarks/startup.csv]

Times, as subprocesses (wall clock, median of ``--repeats``): ``mazegen check`` of the
factory example, a small ``mazegen run`` (population 100, 2 generations) with numba's
cache warm, and the same run with an empty numba cache (``NUMBA_CACHE_DIR`` pointed
at a fresh folder), which is what the very first run after installing costs.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from common import BENCHMARKS, ROOT, markdown_table, median_seconds, write_csv

FACTORY = str(ROOT / "examples" / "factory.maze")
TARGETS = {"check": 1.0, "small run (warm cache)": 2.0}
COLUMNS = [("command", "command", "s"), ("seconds", "median s", ".2f"), ("target_s", "target s", "g"),
           ("verdict", "verdict", "s")]  # fmt: skip


def mazegen(*args: str, env: dict[str, str] | None = None) -> None:
    """Run ``mazegen ARGS`` quietly; fail loudly if it fails."""
    done = subprocess.run(
        [shutil.which("mazegen") or "mazegen", *args], capture_output=True, text=True, env=env, check=False
    )
    if done.returncode != 0:
        raise SystemExit(f"mazegen {' '.join(args)} failed:\n{done.stderr}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--csv", type=Path, default=BENCHMARKS / "startup.csv")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="mazegen-startup-") as temp:
        out = str(Path(temp) / "run")
        small = ("run", FACTORY, "--population", "100", "--generations", "2", "-q", "--force", "-o", out)

        def cold_run() -> None:
            cache = tempfile.mkdtemp(dir=temp)  # an empty numba cache: every kernel compiles
            mazegen(*small, env={**os.environ, "NUMBA_CACHE_DIR": cache})

        commands = [
            ("check", lambda: mazegen("check", FACTORY), args.repeats),
            ("small run (warm cache)", lambda: mazegen(*small), args.repeats),
            ("small run (empty numba cache)", cold_run, 1),
        ]
        rows = []
        for name, action, repeats in commands:
            seconds = median_seconds(action, repeats=repeats, warmup=1 if repeats > 1 else 0)
            target = TARGETS.get(name)
            verdict = None if target is None else ("PASS" if seconds < target else "FAIL")
            rows.append({"command": name, "seconds": seconds, "target_s": target, "verdict": verdict})
    print(markdown_table(rows, COLUMNS))
    write_csv(args.csv, rows)


if __name__ == "__main__":
    main()
