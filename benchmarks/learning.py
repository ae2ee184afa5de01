"""Throughput of ``mazegen.gym.FloorVectorEnv``: environment steps per second, with and without lidar.

Usage:
    python benchmarks/learning.py              # a pool of 1,024 floors, IR-SIM on 12 of 400, median of 3
    python benchmarks/learning.py --quick      # a pool of 256 floors, IR-SIM on 4 of 100, shorter timings
    python benchmarks/learning.py --threads 1 --repeats 5

The levels: a pool of fresh floors of the bundled training spec (``mazegen.gym.TRAINING_SPEC``,
10 × 7.5 m, up to 12 elements, each floor valid with a path from start to goal), drawn once with
``SpecLevels`` and passed as ``levels=``, so every automatic reset draws a level from the pool. The
environment runs 256 and 1,024 sub-environments, with a 360-beam lidar and without (``beams=0``),
in the default autoreset mode (``NEXT_STEP``). The actions are fixed: a seeded random (v, w) per
sub-environment, v uniform in [0, top speed], w uniform in [-1, 1] rad/s, drawn once and given at
every step; so the timing covers ``env.step`` alone: the compiled step of every robot, the
observations, the info and the resets of the episodes that ended the step before (a level drawn
from the pool and loaded into its slot). Each configuration runs some untimed steps first (the
first compiles the kernels), then the number of vector steps that takes about 2 s (0.5 s with
``--quick``; a short probe decides it); a figure is sub-environments × vector steps / the median seconds of
``--repeats`` runs. The episodes ended per vector step count every episode that arrived, collided
or timed out in the timed steps.

Then IR-SIM's table (``irsim_rows.py``) on the pool's first 400 floors (100 with ``--quick``):
IR-SIM and MazeGen's simulator replaying the same commands, robot-steps per second.

Targets, on 2 cores, per configuration: at least 1,000,000 environment steps per second without
lidar and 100,000 with the 360-beam lidar. Writes ``benchmarks/learning.csv``.
"""

from __future__ import annotations

import argparse
import math
import time
from contextlib import nullcontext

import numpy as np
from common import BENCHMARKS, markdown_table, median_seconds, write_csv
from irsim_rows import COLUMNS as IRSIM_COLUMNS
from irsim_rows import irsim_rows

from mazegen.gym import TRAINING_SPEC, FloorVectorEnv, Levels, SpecLevels
from mazegen.runtime.threads import thread_count, threads

SUB_ENVIRONMENTS = (256, 1024)
BEAMS = (0, 360)
TARGETS = {0: 1_000_000.0, 360: 100_000.0}
"""Least environment steps per second on 2 cores, per lidar beam count."""
POOL, QUICK_POOL = 1024, 256
"""Training-spec floors drawn once; the environments' resets draw from them."""
IRSIM_FLOORS, QUICK_IRSIM_FLOORS = (400, 12), (100, 4)
"""(pool floors replayed by MazeGen, IR-SIM's share of them) in IR-SIM's table."""
SECONDS, QUICK_SECONDS = 2.0, 0.5
"""Wall time a timed run of vector steps aims at."""
WARMUP, PROBE = 50, 20
"""Untimed vector steps before timing (the first compiles the kernels), then the probe's."""

COLUMNS = [
    ("num_envs", "sub-environments", ",d"),
    ("beams", "lidar beams", "d"),
    ("steps_per_s", "steps per second", ",.0f"),
    ("ended_per_step", "episodes ended per vector step", ".2f"),
    ("target", "target", ",.0f"),
    ("pass", "pass", "s"),
]


def run_steps(env: FloorVectorEnv, actions: np.ndarray, steps: int) -> int:
    """Step ``env`` ``steps`` times by ``actions``; returns the episodes that ended."""
    ended = 0
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(actions)
        ended += int(np.count_nonzero(terminated | truncated))
    return ended


def measure(
    pool: Levels, actions: np.ndarray, beams: int, *, seconds: float, repeats: int, seed: int
) -> dict:
    """One configuration's row: ``len(actions)`` sub-environments on ``pool``'s levels, ``beams``
    lidar beams, ``actions`` at every step."""
    num_envs = len(actions)
    env = FloorVectorEnv(num_envs, levels=pool, beams=beams, seed=seed)
    env.reset(seed=seed)
    run_steps(env, actions, WARMUP)
    started = time.perf_counter()
    run_steps(env, actions, PROBE)
    steps = max(PROBE, math.ceil(seconds * PROBE / (time.perf_counter() - started)))
    ended: list[int] = []
    median = median_seconds(lambda: ended.append(run_steps(env, actions, steps)), repeats=repeats, warmup=0)
    rate, target = num_envs * steps / median, TARGETS[beams]
    return {
        "num_envs": num_envs,
        "beams": beams,
        "threads": thread_count(),
        "vector_steps": steps,
        "seconds": median,
        "steps_per_s": rate,
        "ended_per_step": sum(ended) / (steps * repeats),
        "target": target,
        "pass": "PASS" if rate >= target else "FAIL",
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=f"a pool of {QUICK_POOL} floors, shorter runs")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, help="numba threads (default every core)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    pool_size = QUICK_POOL if args.quick else POOL
    seconds = QUICK_SECONDS if args.quick else SECONDS
    floors, sample = QUICK_IRSIM_FLOORS if args.quick else IRSIM_FLOORS
    with threads(args.threads) if args.threads else nullcontext():
        started = time.perf_counter()
        source = SpecLevels(TRAINING_SPEC)
        pool = source.sample(np.random.default_rng(args.seed), pool_size)
        print(
            f"{len(pool):,} training-spec floors drawn in {time.perf_counter() - started:.1f} s "
            f"(a first draw compiles the kernels); numba threads: {thread_count()}\n"
        )
        rng = np.random.default_rng(args.seed)
        most = max(SUB_ENVIRONMENTS)
        actions = np.column_stack(
            [rng.uniform(0.0, source.robot.max_speed, most), rng.uniform(-1.0, 1.0, most)]
        )
        rows = [
            measure(pool, actions[:n], beams, seconds=seconds, repeats=args.repeats, seed=args.seed)
            for n in SUB_ENVIRONMENTS
            for beams in BEAMS
        ]
        print(markdown_table(rows, COLUMNS))
        write_csv(BENCHMARKS / "learning.csv", rows)
        if pool.codons is None or pool.genes is None:
            raise SystemExit("the pool's levels carry no genomes: IR-SIM's floors cannot be rebuilt")
        _, population = source.problem.decode(pool.codons[:floors], pool.genes[:floors])
        print("\n### IR-SIM and MazeGen's simulator: the pool's floors, the same commands\n")
        irsim = irsim_rows(population, floors=floors, sample=sample, repeats=args.repeats)
        print(markdown_table(irsim, IRSIM_COLUMNS))


if __name__ == "__main__":
    main()
