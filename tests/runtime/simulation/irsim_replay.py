"""IR-SIM as an oracle of MazeGen's simulator: the same floors, exported with ``--format irsim``,
driven in IR-SIM with the commands MazeGen's simulator was given.

``oracle_floors`` makes random floors of the factory's elements; ``drive_recording`` drives them in
MazeGen's simulator with a batch policy whose every command it keeps; ``replay`` steps one exported
world in IR-SIM with such commands and reports IR-SIM's own verdict (its collision check, its goal
check). The benchmark's IR-SIM rows step the same worlds (benchmarks/simulation.py).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from mazegen.runtime.documents._floor import Floor
from mazegen.runtime.engine._population import Population
from mazegen.runtime.exporters._floor import ExportOptions
from mazegen.runtime.exporters._irsim import irsim_files
from mazegen.runtime.geometry._elements import world_vertices
from mazegen.runtime.simulation import Episodes, Observations, drive
from mazegen.spec import robot_for
from tests.runtime.floors import ARENA, NAMES, population, random_floors

METRES = 0.01
"""ARENA is in centimetres; the exported worlds are in metres."""


def oracle_floors(count: int, seed: int = 18) -> Population:
    """``count`` random floors of the factory's elements in :data:`ARENA` (some without a path)."""
    return population(ARENA, random_floors(np.random.default_rng(seed), count, ARENA))


def floor_parts(floors: Population, index: int) -> list[np.ndarray]:
    """Every convex part of floor ``index``, exactly as the simulator's kernels place it."""
    count = int(floors.n_elements[index])
    ids = floors.element_ids[index, :count]
    vertices = world_vertices(floors.table, ids, floors.params[index, :count])
    table = floors.table
    return [
        vertices[k, p, : table.n_vertices[e, p]]
        for k, e in enumerate(ids.tolist())
        for p in range(int(table.n_parts[e]))
    ]


def export_world(floors: Population, index: int, folder: Path, *, lidar: bool) -> Path:
    """Floor ``index`` as an IR-SIM world (the default robot of its arena), without its lidar
    unless ``lidar``: IR-SIM casts it at every step, which the replay does not read."""
    parts = [part.tolist() for part in floor_parts(floors, index)]
    document = {
        "format": "mazegen-scenario",
        "version": 1,
        "scenario": "oracle",
        "arena": dataclasses.asdict(floors.arena),
        "elements": [{"type": NAMES[0], "x": 0, "y": 0, "parts": parts}] if parts else [],
    }
    ((name, data),) = irsim_files(
        Floor(document, None, folder / f"floor-{index:03d}.json"), ExportOptions()
    ).items()
    world = yaml.safe_load(data)
    if not lidar:
        world["robot"][0]["sensors"] = []
    path = folder / name
    path.write_text(yaml.safe_dump(world))
    return path


class RecordingPolicy:
    """A batch policy that heads for the goal and keeps every command it gives, per floor.

    Robots on even floors steer away from what the lidar sees ahead; robots on odd floors charge
    at the goal, so that the drive ends in every way: arrivals, collisions and timeouts.
    """

    def __init__(self, scans: int = 0) -> None:
        self.commands: dict[int, list[tuple[float, float]]] = {}
        self.keep = scans
        self.scans: dict[int, list[np.ndarray]] = {}

    def __call__(self, observations: Observations) -> np.ndarray:
        max_speed, _, max_turn = observations.limits[:3]
        radius = observations.limits[6]
        angles, scan = observations.angles, observations.scan
        bearing = np.arctan2(observations.goal[:, 2], observations.goal[:, 1])
        ahead = scan[:, np.abs(angles) < 0.5].min(axis=1)
        left = scan[:, (angles > 0.3) & (angles < 1.5)].mean(axis=1)
        right = scan[:, (angles < -0.3) & (angles > -1.5)].mean(axis=1)
        blocked = (observations.floor % 2 == 0) & (ahead < 4 * radius)
        turn = np.where(blocked, np.where(left > right, max_turn, -max_turn), 2.5 * bearing)
        speed = np.where(blocked, 0.2 * max_speed, max_speed)
        actions = np.column_stack([speed, turn])
        for floor, action in zip(observations.floor.tolist(), actions.tolist()):
            self.commands.setdefault(floor, []).append((action[0], action[1]))
        if observations.step < self.keep:
            for floor, ranges in zip(observations.floor.tolist(), scan):
                self.scans.setdefault(floor, []).append(ranges.copy())
        return actions


def drive_recording(
    floors: Population, scans: int = 0, indices: np.ndarray | None = None
) -> tuple[Episodes, RecordingPolicy]:
    """MazeGen's drive of the floors ``indices`` (default every valid one) with
    :class:`RecordingPolicy` (keeping the lidar scans of the first ``scans`` steps), and the policy
    with the commands it gave."""
    policy = RecordingPolicy(scans)
    robot = robot_for(floors.arena)
    episodes = drive(floors, robot=robot, controller=policy, indices=indices, record=True)
    return episodes, policy


@dataclass(frozen=True)
class Replay:
    """IR-SIM's run of a command sequence.

    Attributes:
        outcome: ``arrived`` or ``collision`` at the step IR-SIM says so, else ``running``.
        poses: ``float64[k + 1, 3]`` the robot's poses from the start, in the world's metres.
        scans: ``float64[k + 1, beams]`` IR-SIM's lidar ranges at each of those poses.
    """

    outcome: str
    poses: np.ndarray
    scans: np.ndarray


def make(world: Path):
    import irsim

    return irsim.make(str(world), headless=True, log_level="ERROR")


def replay(world: Path, commands: np.ndarray, start: np.ndarray | None = None) -> Replay:
    """Step IR-SIM's world with ``commands`` (``(v, w)`` rows in its units), stopping at its first
    collision or arrival, from the world's start or ``start`` (``x, y, theta`` in its units). A
    start that already touches an obstacle is a collision at step 0."""
    env = make(world)
    robot = env.robot
    if start is not None:
        robot.set_state(np.asarray(start, np.float64).reshape(3, 1), init=True)
        env.build_tree()
    poses = [robot.state[:3, 0].copy()]
    scans = [_ranges(robot)]
    if any(robot.check_collision(obstacle) for obstacle in env.obstacle_list):
        return Replay("collision", np.array(poses), np.array(scans))
    for v, w in np.asarray(commands, np.float64).reshape(-1, 2):
        env.step([float(v), float(w)])
        poses.append(robot.state[:3, 0].copy())
        scans.append(_ranges(robot))
        if robot.collision or robot.arrive:
            return Replay("collision" if robot.collision else "arrived", np.array(poses), np.array(scans))
    return Replay("running", np.array(poses), np.array(scans))


def _ranges(robot) -> np.ndarray:
    """The robot's lidar ranges (none when it has no lidar)."""
    return robot.sensors[0].range_data.copy() if robot.sensors else np.zeros(0)


def disc_sides() -> int:
    """Sides of the polygon IR-SIM draws a disc robot as (shapely's ``buffer`` default)."""
    import shapely

    return len(shapely.Point(0, 0).buffer(1.0).exterior.coords) - 1


def inscribed(radius: float) -> float:
    """The inner radius of IR-SIM's polygonal disc of ``radius``."""
    return radius * math.cos(math.pi / disc_sides())
