"""IR-SIM's rows of the simulation benchmark: IR-SIM and MazeGen's simulator stepping the same
floors with the same commands, in robot-steps per second.

Usage:
    python benchmarks/irsim_rows.py            # 400 floors, IR-SIM on 12 of them, median of 3
    python benchmarks/irsim_rows.py --quick    # 100 floors, IR-SIM on 4, median of 3

Run alone, the floors are random floors of the factory's elements (the IR-SIM oracle's,
``tests/runtime/simulation/irsim_replay``); ``irsim_rows(population)`` takes any floors (a few
hundred of ``benchmarks/simulation.py``'s, say: every command is kept in Python lists).
MazeGen's simulator drives them once with a recording batch policy; then both simulators replay
those commands: MazeGen's through a batch policy that returns them (one Python call per step for
every robot, so the compiled loop of a bundled controller is faster still), IR-SIM from each floor's
``--format irsim`` world with ``env.step``, each with its own collision checks, and in the lidar row
each casting its own 360-beam lidar at every step. IR-SIM steps one world at a time (loading a world
is not timed); MazeGen every floor at once, with all numba threads and with one. Every figure is the
median of ``--repeats`` runs after one untimed run. The ratio is MazeGen on one thread over IR-SIM
(one thread too); targets: at least 100x without lidar, 20x with 360 beams.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from common import ROOT, markdown_table, median_seconds

sys.path.insert(0, str(ROOT))  # the oracle's floors and replay live with its test

from mazegen.runtime.documents._floor import EXPORT_METRES_PER_UNIT
from mazegen.runtime.engine._population import Population
from mazegen.runtime.simulation import NO_PATH, Observations, drive
from mazegen.runtime.threads import thread_count, threads
from mazegen.spec import Robot, robot_for
from tests.runtime.simulation.irsim_replay import (
    drive_recording,
    export_world,
    make,
    oracle_floors,
)

TARGETS = {False: 100.0, True: 20.0}
"""MazeGen's least speed-up per robot step over IR-SIM, without and with the lidar."""


class ReplayPolicy:
    """A batch policy that gives each robot, at each step, the command recorded for it."""

    def __init__(self, floors: np.ndarray, commands: dict[int, list[tuple[float, float]]]) -> None:
        longest = max((len(c) for c in commands.values()), default=0)
        self.table = np.zeros((len(floors), longest + 1, 2))  # zeros past each episode's end
        self.row = np.full(int(floors.max(initial=0)) + 1, -1)
        self.row[floors] = np.arange(len(floors))
        for k, floor in enumerate(floors.tolist()):
            given = commands.get(floor, [])
            if given:  # a start touching a part ends its episode before any command
                self.table[k, : len(given)] = given

    def __call__(self, observations: Observations) -> np.ndarray:
        return self.table[self.row[observations.floor], observations.step]


def mazegen_rate(
    floors: Population, driven: np.ndarray, policy: ReplayPolicy, robot: Robot, repeats: int
) -> float:
    """Robot-steps per second of MazeGen's simulator replaying ``policy``'s commands on ``driven``."""
    steps = int(drive(floors, robot=robot, controller=policy, indices=driven).steps.sum())
    seconds = median_seconds(
        lambda: drive(floors, robot=robot, controller=policy, indices=driven), repeats=repeats
    )
    return steps / seconds


def irsim_rate(worlds: list[Path], commands: list[np.ndarray], repeats: int) -> tuple[float, int]:
    """Robot-steps per second of IR-SIM stepping each world with its commands until it collides or
    arrives, and the steps of one run (median over ``repeats`` runs after one untimed run)."""
    rates, steps = [], 0
    for _ in range(repeats + 1):
        seconds, steps = 0.0, 0
        for world, given in zip(worlds, commands):
            env = make(world)
            robot = env.robot
            start = time.perf_counter()
            for v, w in given.tolist():
                env.step([v, w])
                steps += 1
                if robot.collision or robot.arrive:
                    break
            seconds += time.perf_counter() - start
        rates.append(steps / seconds)
    return statistics.median(rates[1:]), steps


def irsim_rows(
    population: Population, *, floors: int = 400, sample: int = 12, repeats: int = 3
) -> list[dict]:
    """One row per lidar setting: both simulators' robot-steps per second on the first ``floors``
    valid floors of ``population`` (IR-SIM on ``sample`` of those with a path), and their ratio."""
    arena, metres = population.arena, EXPORT_METRES_PER_UNIT[population.arena.unit]
    chosen = np.flatnonzero(population.valid)[:floors]
    episodes, recording = drive_recording(population, indices=chosen)
    driven = chosen[episodes.outcome != NO_PATH]
    steps_of = dict(zip(chosen.tolist(), episodes.steps.tolist()))
    policy = ReplayPolicy(driven, recording.commands)
    picked = driven[:: max(1, len(driven) // sample)][:sample]
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for lidar in (False, True):
            robot = robot_for(arena) if lidar else robot_for(arena, beams=0)
            ours = mazegen_rate(population, driven, policy, robot, repeats)
            with threads(1):
                ours_one = mazegen_rate(population, driven, policy, robot, repeats)
            worlds = [export_world(population, m, Path(folder), lidar=lidar) for m in picked.tolist()]
            given = [np.array(recording.commands[m][: steps_of[m]]) * [metres, 1.0] for m in picked.tolist()]
            theirs, steps = irsim_rate(worlds, given, repeats)
            rows.append(
                {
                    "work": "360-beam lidar" if lidar else "no lidar",
                    "floors": len(driven),
                    "mazegen": ours,
                    "mazegen_one": ours_one,
                    "irsim_floors": len(picked),
                    "irsim_steps": steps,
                    "irsim": theirs,
                    "ratio": ours_one / theirs,
                    "target": TARGETS[lidar],
                }
            )
    return rows


COLUMNS = [
    ("work", "work per robot step", "s"),
    ("floors", "MazeGen floors", "d"),
    ("mazegen", f"MazeGen steps/s ({thread_count()} threads)", ",.0f"),
    ("mazegen_one", "MazeGen steps/s (1 thread)", ",.0f"),
    ("irsim_floors", "IR-SIM floors", "d"),
    ("irsim_steps", "IR-SIM steps", ",d"),
    ("irsim", "IR-SIM steps/s", ",.0f"),
    ("ratio", "MazeGen (1 thread) / IR-SIM", ",.0f"),
    ("target", "target", ".0f"),
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="100 floors, IR-SIM on 4")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    floors, sample = (100, 4) if args.quick else (400, 12)
    rows = irsim_rows(oracle_floors(floors), floors=floors, sample=sample, repeats=args.repeats)
    print(markdown_table(rows, COLUMNS))


if __name__ == "__main__":
    main()
