"""Throughput of MazeGen's robot simulator: whole episodes per second, per bundled controller.

Usage:
    python benchmarks/simulation.py            # 10,000 evolved floors, median of 3 drives (~3 min)
    python benchmarks/simulation.py --quick    # 2,000 evolved floors
    python benchmarks/simulation.py --controllers straight purepursuit dwa --repeats 5

The floors: ``examples/factory.maze`` (14 × 10.5 m, up to 32 elements, ``solvable required``)
built in a temporary folder and evolved for 15 generations at a population of ``--floors`` with its
own operators (``evolved_sample`` of ``kernels.py``); the last generation's valid individuals are
driven, one robot per floor, with the arena's default robot (BARN's Jackal limits, 0.1 s steps,
timeout 8 × the optimal time). Floors MazeGen finds no path on are not driven and not counted.

Each drive is timed whole, as a user or a fitness term pays for it: the paths (optimal times, and
the corners purepursuit follows), the floors' parts, the episodes. Every figure is the median of
``--repeats`` drives after one untimed drive (which compiles the kernels), with all the kernels' threads
and with one. Prints one Markdown table per controller, and the targets: ``straight`` and
``purepursuit`` at least 20,000 episodes/s on 2 cores, ``dwa`` 500 (its fields built inside the
timed drive), ``vfh`` (a 360-beam lidar) 200 (the issue's; a loaded machine measures less).
Then IR-SIM's table (``irsim_rows.py``): IR-SIM and MazeGen's simulator replaying the same commands
on the first 400 valid floors, robot-steps per second without and with a 360-beam lidar; and the
heterogeneous case (``heterogeneous.py``): ``dwa`` and ``movebase`` over 300 floors of BARN's worlds,
each its own spec and task, in one batch (the issue's goals: 500 and 300 episodes/s on 2 cores).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numpy as np
from common import markdown_table, median_seconds
from heterogeneous import COLUMNS as HETEROGENEOUS_COLUMNS
from heterogeneous import heterogeneous_rows
from irsim_rows import COLUMNS as IRSIM_COLUMNS
from irsim_rows import irsim_rows
from kernels import evolved_sample, load_problem

from mazegen.controllers import BY_CODE
from mazegen.runtime.engine._population import Population
from mazegen.runtime.simulation import NO_PATH, OUTCOMES, drive
from mazegen.runtime.threads import thread_count, threads
from mazegen.spec import robot_for

FLOORS = 10_000
QUICK_FLOORS = 2_000
REPEATS = 3
TARGETS = {"straight": 20_000.0, "purepursuit": 20_000.0, "dwa": 500.0, "vfh": 200.0}
"""Episodes per second each controller should reach with all threads (the issue's targets)."""
CONTROLLERS = tuple(row.name for row in BY_CODE)
"""Measured unless ``--controllers`` says otherwise: every bundled controller, in the order of their codes."""

COLUMNS = [
    ("threads", "threads", "d"),
    ("driven", "floors driven", ",d"),
    ("episodes_per_s", "episodes/s", ",.0f"),
    ("steps_per_s", "robot steps/s", ",.0f"),
    ("mean_steps", "mean steps", ".1f"),
    ("arrived_pct", "arrived %", ".1f"),
    ("collision_pct", "collision %", ".1f"),
    ("timeout_pct", "timeout %", ".1f"),
    ("target", "target episodes/s", ",.0f"),
]


def evolved_floors(count: int, seed: int) -> Population:
    """The last generation of the factory evolved at population ``count``."""
    sample = evolved_sample(load_problem("factory"), count, np.random.default_rng(seed))
    return sample.population


def controller_rows(name: str, floors: Population, repeats: int) -> list[dict]:
    """One row per thread count: the median drive of ``name`` over every valid floor."""
    robot = robot_for(floors.arena)
    rows = []
    every = thread_count()
    for count in sorted({every, 1}, reverse=True):
        with threads(count):
            episodes = drive(floors, robot=robot, controller=name)
            seconds = median_seconds(lambda: drive(floors, robot=robot, controller=name), repeats=repeats)
        driven = episodes.outcome != NO_PATH
        share = np.bincount(episodes.outcome[driven], minlength=len(OUTCOMES)) / max(1, driven.sum())
        rows.append(
            {
                "threads": count,
                "driven": int(driven.sum()),
                "episodes_per_s": driven.sum() / seconds,
                "steps_per_s": episodes.steps.sum() / seconds,
                "mean_steps": float(episodes.steps[driven].mean()),
                "arrived_pct": 100 * share[0],
                "collision_pct": 100 * share[1],
                "timeout_pct": 100 * share[2],
                "target": TARGETS.get(name) if count == every else None,
            }
        )
    return rows


def table(title: str, rows: list[dict], columns: list[tuple[str, str, str]] = COLUMNS) -> str:
    """A titled Markdown table: each controller's, and any other section's rows (IR-SIM's, say)."""
    return f"### {title}\n\n{markdown_table(rows, columns)}\n"


SECTIONS: list[tuple[str, Callable[[Population, int], list[dict]], list[tuple[str, str, str]]]] = [
    (
        "IR-SIM and MazeGen's simulator: the same floors, the same commands",
        lambda floors, repeats: irsim_rows(floors, repeats=repeats),
        IRSIM_COLUMNS,
    ),
    (
        "Floors that share nothing: BARN's worlds, each its own spec and task, one batch (heterogeneous.py)",
        lambda floors, repeats: heterogeneous_rows(["dwa", "movebase"], repeats),
        HETEROGENEOUS_COLUMNS,
    ),
]
"""Further tables after the controllers': (title, rows of the floors and repeats, columns)."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=f"{QUICK_FLOORS:,} floors instead of {FLOORS:,}")
    parser.add_argument("--floors", type=int, help="population size evolved")
    parser.add_argument("--repeats", type=int, default=REPEATS)
    parser.add_argument("--controllers", nargs="+", default=list(CONTROLLERS))
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    count = args.floors or (QUICK_FLOORS if args.quick else FLOORS)
    floors = evolved_floors(count, args.seed)
    print(f"{count:,} evolved floors of examples/factory.maze, {int(floors.valid.sum()):,} valid\n")
    for name in args.controllers:
        print(table(f"`{name}`", controller_rows(name, floors, args.repeats)))
    for title, rows, columns in SECTIONS:
        print(table(title, rows(floors, args.repeats), columns))


if __name__ == "__main__":
    main()
