"""MazeGen's simulated controllers against BARN's measured Gazebo runs, on the training half only.

Usage:
    python benchmarks/barn_validation.py [--controllers straight purepursuit dwa vfh] [--per-world]

The floors: the 150 training worlds of ``../shared/anchors/barn/barn-train.json`` imported with
``mazegen import`` (a 0.30 m robot, BARN's C-space radius), each with the start and goal of BARN's 2020
timing runs (``start_goal_timer_2020``). The other 150 worlds are held out: this script never reads
them, and nothing here is fitted to any world.

Each controller drives every world as the 2020 runs were timed (``jackal_timer``): the Jackal's limits
(0.5 m/s, 1.57 rad/s) and body (a 0.508 x 0.430 m box; ``--disc`` for the arena's disc), the clock
starting when the robot is √0.1 m from its start, arrival within √0.1 m of the goal, a run stopped at
50 s. Per world, BARN's measure: time over BARN's path length, a failure (a collision, no arrival, or
50 s) counting as 30 s. Each controller drives twice: a touch ending the
run (MazeGen's default) and a touch carrying on (``contact continue``: Gazebo's physics, where the
timer records no collisions). Against the worlds' measured DWA runs (5 each):

- Spearman ρ of MazeGen's measure with BARN's DWA mean (``target_dwa``); the ceiling is one Gazebo run
  against the mean of the other four (printed first);
- success rates, MazeGen's and BARN's (runs under 50 s);
- failure agreement: MazeGen's failure against the majority of BARN's five runs, per world;
- the same ρ for MazeGen's difficulty score (the documents' ``metrics.difficulty``).

The issue's goals for a move_base-faithful DWA: ρ ≥ 0.75, success within 5 points of BARN's, failure
agreement ≥ 90 %. ``--per-world`` prints every world's row besides.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import tempfile
from pathlib import Path

import numpy as np
from common import markdown_table
from heterogeneous import BARN, import_barn

import mazegen
from mazegen.controllers import BY_CODE
from mazegen.runtime.documents import Floors, load_floor
from mazegen.runtime.navigation import navigation_of, spearman
from mazegen.runtime.simulation import ARRIVED, DriveRequest, drive_many
from mazegen.spec import CONTACT_MODES, ControllerSpec, metres_per_unit

TIMER_RADIUS = math.sqrt(0.1)
"""jackal_timer's start and arrival radius, metres: the clock starts once the robot is this far
from its start, and stops when it is nearer the goal than this."""
STOP_S = 50.0
"""A 2020 run is stopped after this many seconds of the clock."""
FAILURE_S = 30.0
"""What BARN counts a failed run as, seconds."""
GOALS = {"rho": 0.75, "success_points": 5.0, "failure_agreement": 0.90}
JACKAL = (0.508, 0.430)
"""The Jackal's body, length by width, metres: the box Gazebo collides (and the simulator, by default)."""
SUMMARY = [
    ("measure", "measure", "s"),
    ("rho", "Spearman ρ vs BARN DWA", ".2f"),
    ("success", "success %", ".1f"),
    ("barn_success", "BARN DWA success %", ".1f"),
    ("agreement", "failure agreement %", ".1f"),
    ("mean_s", "mean time of arrivals s", ".1f"),
]


@dataclasses.dataclass(frozen=True)
class World:
    """One training world: its number, BARN's measurements and its imported floor."""

    number: int
    path_m: float
    times: np.ndarray
    target: float
    floors: Floors
    difficulty: float

    @property
    def barn_failures(self) -> int:
        return int((self.times >= STOP_S).sum())


def load_worlds(folder: Path, radius: float) -> list[World]:
    entries = {entry["world"]: entry for entry in json.loads(BARN.read_text())["worlds"]}
    worlds = []
    for file in import_barn(folder, 1, radius):
        floor = load_floor(file)
        number = int(floor.document["scenario"].rsplit("_", 1)[1])
        entry = entries[number]
        worlds.append(
            World(
                number,
                float(entry["path_length_m"]),
                np.array(entry["times_dwa"], np.float64),
                float(entry["target_dwa"]),
                Floors.of(floor.needs_spec("driving"), [(floor.where, floor.document)]),
                float(floor.document["metrics"]["difficulty"]),
            )
        )
    return worlds


def timed_robot(
    floors: Floors,
    contact: str,
    controllers: tuple[ControllerSpec, ...] = (),
    *,
    reverse: bool = False,
    box: bool = True,
):
    """The floor's robot as the 2020 runs timed it: arrival within √0.1 m, and time enough for 50 s of
    clock after leaving the start (the timeout is a multiple of the optimal time), never cut short for
    lack of progress; ``contact`` what a touch does; ``controllers`` settings of controllers (a fitted
    robot block's), if any; ``reverse``: the Jackal backs up at up to its speed (move_base's escape);
    ``box``: it collides as the Jackal's body, :data:`JACKAL`, not as the disc of the arena's radius."""
    robot = floors.robot
    optimal = float(navigation_of(floors.population).path_length[0]) / robot.max_speed
    timeout = (STOP_S + 10.0) / optimal
    changes: dict = {"controllers": controllers} if controllers else {}
    if reverse:
        changes["min_speed"] = -robot.max_speed
    if box:
        units = metres_per_unit(floors.spec.arena)
        changes["footprint"] = (JACKAL[0] / units, JACKAL[1] / units)
    return dataclasses.replace(
        robot, goal_tolerance=TIMER_RADIUS, timeout=timeout, stuck=STOP_S + 10.0, contact=contact, **changes
    )


def fitted_controllers(robot_file: Path, world: World) -> tuple[ControllerSpec, ...]:
    """The controller settings of a robot block (``mazegen fit``'s), read as a world's spec imports it."""
    spec_text = next(Path(world.floors.files[0]).parent.glob("*.maze")).read_text(encoding="utf-8")
    with tempfile.TemporaryDirectory() as folder:
        spec = Path(folder) / "spec.maze"
        spec.write_text(f"import {json.dumps(str(robot_file.resolve()))}\n{spec_text}", encoding="utf-8")
        robot = mazegen.load(spec).robot
    return robot.controllers if robot is not None else ()


def timed_seconds(episodes, start: tuple[float, float]) -> float:
    """The clock of a driven episode as jackal_timer read it, or ``inf`` for a failure."""
    if episodes.outcome[0] != ARRIVED:
        return math.inf
    track = episodes.trajectory[0]
    track = track[~np.isnan(track[:, 0])]
    away = np.flatnonzero(np.hypot(track[:, 0] - start[0], track[:, 1] - start[1]) >= TIMER_RADIUS)
    seconds = float(episodes.time[0]) - (away[0] if away.size else 0) * float(episodes.time[0]) / (
        len(track) - 1
    )
    return seconds if seconds < STOP_S else math.inf


def measured(
    worlds: list[World],
    controller: str,
    contact: str,
    controllers: tuple[ControllerSpec, ...] = (),
    *,
    box: bool = True,
) -> np.ndarray:
    """Each world's clock for ``controller`` (with ``controllers``' settings), ``inf`` where it failed;
    ``box``: the robot collides as the Jackal's body (else the arena's disc)."""
    requests = []
    for world in worlds:
        robot = timed_robot(world.floors, contact, controllers, reverse=controller == "movebase", box=box)
        requests.append(DriveRequest(world.floors.population, robot, robot.controller(controller)))
    driven = drive_many(requests, record=True)
    return np.array(
        [timed_seconds(episodes, w.floors.population.arena.start) for w, episodes in zip(worlds, driven)]
    )


def write_measured(worlds: list[World], path: Path) -> None:
    """BARN's five DWA runs of each world as ``mazegen fit`` reads them: scenario, outcome, time, and
    the length of BARN's path, which BARN divides the times by."""
    lines = ["scenario,outcome,time,length"]
    for world in worlds:
        scenario = Path(world.floors.files[0]).relative_to(path.parent)
        for seconds in world.times.tolist():
            outcome = "arrived" if seconds < STOP_S else "timeout"
            lines.append(f"{scenario},{outcome},{min(seconds, STOP_S):g},{world.path_m:g}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def barn_measure(seconds: np.ndarray, path_m: np.ndarray) -> np.ndarray:
    """BARN's per-world measure: time over path length, a failure counting as :data:`FAILURE_S`."""
    return np.where(np.isfinite(seconds), seconds, FAILURE_S) / path_m


def gazebo_ceiling(worlds: list[World]) -> float:
    """Mean over the five DWA runs of ρ(one run's measure, the mean measure of the other four)."""
    path = np.array([w.path_m for w in worlds])
    runs = np.array([np.where(w.times >= STOP_S, FAILURE_S, w.times) for w in worlds]) / path[:, None]
    rhos = [spearman(runs[:, k], np.delete(runs, k, axis=1).mean(axis=1)) for k in range(runs.shape[1])]
    return float(np.mean(rhos))


def summary_row(name: str, seconds: np.ndarray, worlds: list[World]) -> dict:
    path = np.array([w.path_m for w in worlds])
    target = np.array([w.target for w in worlds])
    failed = ~np.isfinite(seconds)
    barn_failed = np.array([w.barn_failures >= 3 for w in worlds])
    return {
        "measure": name,
        "rho": spearman(barn_measure(seconds, path), target),
        "success": 100 * float((~failed).mean()),
        "barn_success": 100 * float(np.mean([1 - w.barn_failures / len(w.times) for w in worlds])),
        "agreement": 100 * float((failed == barn_failed).mean()),
        "mean_s": float(seconds[~failed].mean()) if (~failed).any() else math.nan,
    }


def add_body_arguments(parser: argparse.ArgumentParser, radius: float) -> None:
    """``--robot-radius`` (default ``radius``) and ``--disc``: the radius the worlds are imported for,
    and whether the robot collides as that disc instead of the Jackal's body."""
    parser.add_argument(
        "--robot-radius", type=float, default=radius,
        help=f"the arena's robot radius the worlds are imported for (MazeGen's path and fields), metres "
        f"(default {radius:g})",
    )  # fmt: skip
    parser.add_argument(
        "--disc", action="store_true",
        help="collide the disc of the robot radius, not the Jackal's 0.508 x 0.430 m body",
    )  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--controllers", nargs="+", default=[row.name for row in BY_CODE])
    parser.add_argument("--per-world", action="store_true", help="print every world's row too")
    parser.add_argument(
        "--keep",
        type=Path,
        help="import the worlds into this folder and write measured.csv there (mazegen fit's input)",
    )
    parser.add_argument(
        "--contact", nargs="+", choices=CONTACT_MODES, default=list(CONTACT_MODES),
        help="what a touch does: end the run (MazeGen's default) or continue it (Gazebo's)",
    )  # fmt: skip
    parser.add_argument(
        "--robot", type=Path, help="a robot block (mazegen fit's) whose controller settings to drive"
    )
    add_body_arguments(parser, 0.3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="mazegen-barn-") as folder:
        worlds = load_worlds(args.keep or Path(folder), args.robot_radius)
        settings = fitted_controllers(args.robot, worlds[0]) if args.robot is not None else ()
    if args.keep is not None:
        write_measured(worlds, args.keep / "measured.csv")
        print(f"kept the imported worlds and their measured runs in {args.keep / 'measured.csv'}\n")
    fitted = f", {args.robot.name}" if args.robot is not None else ""
    clocks = {
        f"{name}{fitted}, contact {contact}": measured(worlds, name, contact, settings, box=not args.disc)
        for name in args.controllers
        for contact in args.contact
    }
    print(
        f"{len(worlds)} training worlds; one Gazebo DWA run against the mean of the other four: ρ "
        f"{gazebo_ceiling(worlds):.2f}\n"
    )
    rows = [summary_row(f"`{name}`", seconds, worlds) for name, seconds in clocks.items()]
    difficulty = np.array([w.difficulty for w in worlds])
    target = np.array([w.target for w in worlds])
    rows.append({"measure": "difficulty score", "rho": spearman(difficulty, target)})
    print(markdown_table(rows, SUMMARY))
    print(
        f"\nGoals (a move_base-faithful dwa): ρ ≥ {GOALS['rho']}, success within {GOALS['success_points']:g} "
        f"points of BARN's, failure agreement ≥ {100 * GOALS['failure_agreement']:.0f} %"
    )
    if args.per_world:
        columns = [("world", "world", "d"), ("path_m", "path m", ".2f"), ("barn", "BARN DWA s/m", ".2f"),
                   ("barn_failures", "BARN failed runs", "d")]  # fmt: skip
        columns += [(name, f"{name} s/m", ".2f") for name in clocks]
        per_world = []
        for k, world in enumerate(worlds):
            entry = {"world": world.number, "path_m": world.path_m, "barn": world.target,
                     "barn_failures": world.barn_failures}  # fmt: skip
            entry.update(
                {
                    name: barn_measure(seconds[k : k + 1], np.array([world.path_m]))
                    for name, seconds in clocks.items()
                }
            )
            per_world.append(entry)
        print("\n" + markdown_table(per_world, columns))


if __name__ == "__main__":
    main()
