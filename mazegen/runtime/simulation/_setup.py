"""A drive's set-up: the floors, robot, controller and starts become a :class:`DriveState` whose
robots stand at their starts, ready for the step kernels.

It gathers what the kernels read (the floors' parts, MazeGen's paths and optimal times, the
robot's limits, the controller's parameters and lidar) and puts every robot at its start. Floors
MazeGen finds no path on are marked ``NO_PATH`` and never driven. The fields of a map-reading
controller are not part of it: a drive builds them a chunk of floors at a time
(:mod:`mazegen.runtime.simulation._drive`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.engine.population import Population
from mazegen.runtime.simulation._choice import choose
from mazegen.runtime.simulation._episodes import NO_PATH
from mazegen.runtime.simulation._lidar import beam_angles
from mazegen.runtime.simulation._paths import floor_paths
from mazegen.runtime.simulation._state import DriveState, Robots, Setup, robot_limits
from mazegen.runtime.simulation._step import begin_all
from mazegen.runtime.simulation._world import world_of
from mazegen.spec import ControllerSpec, Robot


def set_up(
    population: Population,
    *,
    robot: Robot,
    controller: str | ControllerSpec | Callable[[Any], Any],
    indices: np.ndarray | None = None,
    starts: np.ndarray | None = None,
    record: bool = False,
) -> DriveState:
    """The drive of ``controller`` over floors ``indices`` of ``population``, its robots at their
    starts; the arguments are :func:`mazegen.runtime.simulation.drive`'s."""
    arena = population.arena
    choice = choose(controller, robot, arena)
    rows = np.flatnonzero(population.valid) if indices is None else np.asarray(indices, np.int64).reshape(-1)
    m = len(rows)
    if m and (rows.min() < 0 or rows.max() >= population.size):
        raise MazeError(f"indices must lie in [0, {population.size}), got {rows.min()}..{rows.max()}")
    poses = _starts(population, m, starts)
    world = world_of(population, rows)
    paths = floor_paths(population, rows, margin=choice.margin)
    optimal = paths.length / robot.max_speed
    max_steps = np.where(
        np.isnan(optimal), 0, np.ceil(robot.timeout * np.nan_to_num(optimal) / robot.step - 1e-9)
    )
    robots = Robots.new(m, int(max_steps.max(initial=0)) if record else None)
    robots.outcome[np.isnan(optimal)] = NO_PATH
    setup = Setup(
        robot_limits(robot, arena),
        np.array(arena.goal, np.float64),
        world,
        paths,
        beam_angles(robot.beams, robot.fov) if choice.lidar else np.zeros(0),
        choice.reach,
        max_steps.astype(np.int32),
        max(1, math.ceil(robot.stuck / robot.step - 1e-9)),
    )
    if m:
        begin_all(poses, setup.limits, setup.goal, world.arrays, robots.state, robots.outcome)
    return DriveState(population, rows, robot, choice, optimal, setup, robots, record)


def _starts(population: Population, m: int, starts: np.ndarray | None) -> np.ndarray:
    arena = population.arena
    if starts is None:
        (sx, sy), (gx, gy) = arena.start, arena.goal
        return np.tile(np.array([sx, sy, math.atan2(gy - sy, gx - sx)]), (m, 1))
    poses = np.ascontiguousarray(starts, np.float64)
    if poses.shape != (m, 3) or not np.isfinite(poses).all():
        raise MazeError(
            f"starts must be {m} finite (x, y, theta) rows, one per driven floor, got shape {poses.shape}"
        )
    return poses
