"""Floors that share nothing, driven in one batch: BARN's worlds, each with its own arena and task.

Usage:
    python benchmarks/heterogeneous.py [--controllers dwa movebase straight] [--repeats 3] [--tasks 2]

The floors: the 150 training worlds of ``../shared/anchors/barn/barn-train.json`` imported with
``mazegen import`` (each a spec of its own: a 4.5 × 4.5 m arena, its walls, its start and goal),
``--tasks`` documents each: the start and goal of BARN's 2020 timing runs, then random tasks drawn
by ``--tasks N --seed K``; 300 floors by default. Each floor's task is its own, so no two floors
share an arena. Timed, medians of ``--repeats`` after one untimed drive:

- ``one batch``: :func:`mazegen.runtime.simulation.drive_many` over all floors (paths, parts,
  fields and episodes), the way ``mazegen drive`` and ``mazegen.drive`` now drive them;
- ``one floor at a time``: :func:`mazegen.runtime.simulation.drive` per floor, the way they drove
  before (every floor of its own spec was a batch of one);
- ``documents``: ``mazegen.drive`` of the scenario files, reading and checking them included;
- ``run population``: a population of as many evolved floors of ``examples/factory.maze``
  (14 × 10.5 m) in one homogeneous batch, the figure the issue compares with. Its episodes are
  longer, so robot steps per second compare the simulator's work; episodes per second what a user
  waits for.
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np
from common import ROOT, markdown_table, median_seconds
from kernels import evolved_sample, load_problem

import mazegen
from mazegen.runtime.documents import Floors, load_floor
from mazegen.runtime.navigation import navigation_of
from mazegen.runtime.simulation import NO_PATH, DriveRequest, drive, drive_many
from mazegen.spec import robot_for

BARN = ROOT.parent / "shared" / "anchors" / "barn" / "barn-train.json"
GOAL_EPISODES_PER_S = {"dwa": 500.0, "movebase": 300.0}
"""The issue's goals over 300 heterogeneous BARN-sized floors, on 2 cores."""
COLUMNS = [
    ("controller", "controller", "s"),
    ("how", "driven as", "s"),
    ("floors", "floors", ",d"),
    ("episodes_per_s", "episodes/s", ",.0f"),
    ("steps_per_s", "robot steps/s", ",.0f"),
    ("arrived_pct", "arrived %", ".1f"),
    ("goal", "goal episodes/s", ",.0f"),
]


def import_barn(folder: Path, tasks: int, radius: float = 0.3) -> list[Path]:
    """Every training world of :data:`BARN` imported into ``folder``: ``tasks`` scenario files each, for a
    robot of ``radius`` metres."""
    from click.testing import CliRunner

    from mazegen.cli.import_ import import_command

    worlds = [entry["world"] for entry in json.loads(BARN.read_text())["worlds"]]
    runner = CliRunner()
    files = []
    for world in worlds:
        for task in range(tasks):
            out = folder / f"world-{world:03d}-task-{task}"
            extra = [] if task == 0 else ["--tasks", "1", "--seed", str(task)]
            extra += [] if radius == 0.3 else ["--robot-radius", str(radius)]
            done = runner.invoke(import_command, [str(BARN), "--world", str(world), "-o", str(out), *extra])
            if done.exit_code != 0:
                raise SystemExit(f"importing world {world}: {done.output}")
            files.append(out / "scenario-01.json")
    return files


def requests_of(files: list[Path], controller: str) -> list[DriveRequest]:
    """One request per file: its floor under its own spec and robot, if it has a path."""
    requests = []
    for file in files:
        floor = load_floor(file)
        batch = Floors.of(floor.needs_spec("driving"), [(floor.where, floor.document)])
        rows = np.flatnonzero(navigation_of(batch.population).solvable)
        requests.append(DriveRequest(batch.population, batch.robot, batch.robot.controller(controller), rows))
    return requests


def row(
    controller: str, how: str, seconds: float, outcome: np.ndarray, steps: np.ndarray, goal: float | None
) -> dict:
    driven = outcome != NO_PATH
    return {
        "controller": controller,
        "how": how,
        "floors": int(driven.sum()),
        "episodes_per_s": driven.sum() / seconds,
        "steps_per_s": steps.sum() / seconds,
        "arrived_pct": 100 * float((outcome[driven] == 0).mean()),
        "goal": goal,
    }


def controller_rows(controller: str, files: list[Path], repeats: int) -> list[dict]:
    requests = requests_of(files, controller)
    goal = GOAL_EPISODES_PER_S.get(controller)
    batch = drive_many(requests)
    outcome = np.concatenate([e.outcome for e in batch])
    steps = np.concatenate([e.steps for e in batch])
    alone = [drive(r.population, robot=r.robot, controller=r.controller, indices=r.indices) for r in requests]
    if any(
        not np.array_equal(a.outcome, b.outcome) or not np.array_equal(a.steps, b.steps)
        for a, b in zip(alone, batch)
    ):
        raise SystemExit(f"{controller}: one batch and one floor at a time drove differently")
    rows = [
        row(
            controller,
            "one batch",
            median_seconds(lambda: drive_many(requests), repeats=repeats),
            outcome,
            steps,
            goal,
        ),
        row(
            controller,
            "one floor at a time",
            median_seconds(
                lambda: [
                    drive(r.population, robot=r.robot, controller=r.controller, indices=r.indices)
                    for r in requests
                ],
                repeats=repeats,
            ),
            outcome,
            steps,
            None,
        ),
        row(
            controller,
            "documents (mazegen.drive)",
            median_seconds(lambda: mazegen.drive(files, [controller]), repeats=repeats),
            outcome,
            steps,
            None,
        ),
    ]
    population = evolved_sample(load_problem("factory"), len(files), np.random.default_rng(1)).population
    robot = robot_for(population.arena)
    episodes = drive(population, robot=robot, controller=controller)
    seconds = median_seconds(lambda: drive(population, robot=robot, controller=controller), repeats=repeats)
    rows.append(row(controller, "run population (factory)", seconds, episodes.outcome, episodes.steps, None))
    return rows


def heterogeneous_rows(controllers: list[str], repeats: int, tasks: int = 2) -> list[dict]:
    """The table's rows: each controller over BARN's imported worlds, driven each way."""
    with tempfile.TemporaryDirectory(prefix="mazegen-barn-") as folder:
        files = import_barn(Path(folder), tasks)
        return [found for name in controllers for found in controller_rows(name, files, repeats)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--controllers", nargs="+", default=["dwa", "movebase", "straight"])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--tasks", type=int, default=2, help="scenario files per world (300 floors at 2)")
    args = parser.parse_args()
    print(f"BARN's {len(json.loads(BARN.read_text())['worlds'])} training worlds, {args.tasks} tasks each\n")
    print(markdown_table(heterogeneous_rows(args.controllers, args.repeats, args.tasks), COLUMNS))


if __name__ == "__main__":
    main()
