"""Drive a controller over floors of a population: one robot per floor, one :class:`Episodes`.

A drive is a set-up and steps. :func:`set_up` turns the floors, robot, controller and starts into a
:class:`~mazegen.runtime.simulation._state.DriveState` whose robots stand at their starts: what
the kernels read (the floors' parts, MazeGen's paths and optimal times, the robot's limits, the
controller's parameters and lidar), floors MazeGen finds no path on marked ``NO_PATH`` and never
driven. :func:`drive` then runs every episode to its end (the compiled loop of a bundled
controller, a step between calls of a user's policy otherwise; the fields of a map-reading
controller built a chunk of floors at a time) and returns what came of them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from mazegen.controllers import FIELDS
from mazegen.errors import MazeError
from mazegen.runtime.engine import Population
from mazegen.runtime.simulation._choice import choose
from mazegen.runtime.simulation._episodes import NO_PATH, Episodes
from mazegen.runtime.simulation._fields import floor_fields
from mazegen.runtime.simulation._lidar import beam_angles
from mazegen.runtime.simulation._loop import run_bundled
from mazegen.runtime.simulation._paths import floor_paths
from mazegen.runtime.simulation._policy import run_policy
from mazegen.runtime.simulation._state import DriveState, Robots, Setup, robot_limits
from mazegen.runtime.simulation._step import begin_all
from mazegen.runtime.simulation._world import world_of
from mazegen.spec import ControllerSpec, Robot


def drive(
    population: Population,
    *,
    robot: Robot,
    controller: str | ControllerSpec | Callable[[Any], Any],
    indices: np.ndarray | None = None,
    starts: np.ndarray | None = None,
    record: bool = False,
) -> Episodes:
    """Drive ``controller`` over the floors ``indices`` of ``population`` (default: every valid one).

    Args:
        population: The floors.
        robot: The robot's limits, lidar and timeouts (:func:`mazegen.spec.robot_for`).
        controller: A bundled controller's name, a spec's :class:`ControllerSpec`, a dotted path
            ``package.module:name`` or entry point name of a user's policy, or the policy itself.
        indices: Which individuals to drive, in this order.
        starts: ``float64[M, 3]`` start pose ``(x, y, theta)`` per driven floor; default the arena's
            start, heading toward the goal.
        record: Keep every pose (:attr:`Episodes.trajectory`).

    Nothing is drawn at random: the same floors, robot, controller and starts give the same
    episodes (perturbed starts are the caller's, drawn from its own seeded generator).

    Raises:
        MazeError: an unknown controller or parameter, or a user's policy that fails.
    """
    state = set_up(population, robot, controller, indices, starts, record)
    if len(state.rows):  # (no floors: nothing to compile)
        _run_to_the_end(state)
    return state.episodes()


def _run_to_the_end(state: DriveState) -> None:
    """Run every episode of ``state`` to its end, with the loop its controller needs."""
    choice = state.choice
    if choice.policy is not None:
        run_policy(state, choice.policy)
    elif FIELDS in choice.reads:
        _run_with_fields(state)
    else:
        run_bundled(state, _NO_FIELDS)


_NO_FIELDS = (np.full((1, 1, 1), np.inf, np.float32), np.zeros((1, 1, 1), np.float32), np.zeros(5))
"""The fields of controllers that read none: one 1×1 dummy shared by every floor."""


FIELD_CHUNK = 1024
"""Floors whose fields are built and driven at a time: the fields of a 128 × 128 grid take 128 kB
a floor, so a drive over many floors holds a chunk's, not all of them."""


def _run_with_fields(state: DriveState) -> None:
    """Drive chunk after chunk of floors, each with the fields of its floors."""
    for a in range(0, len(state.rows), FIELD_CHUNK):
        part = state.part(a, min(a + FIELD_CHUNK, len(state.rows)))
        run_bundled(part, floor_fields(state.population, state.robot, part.rows))


def set_up(
    population: Population,
    robot: Robot,
    controller: str | ControllerSpec | Callable[[Any], Any],
    indices: np.ndarray | None,
    starts: np.ndarray | None,
    record: bool,
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
