"""Drive a controller over floors of a population: one robot per floor, one :class:`Episodes`.

:func:`drive` gathers what the kernels read (the floors' parts, MazeGen's paths and optimal
times, the robot's limits, the controller's parameters), puts every robot at its start, runs the
episodes (the compiled loop for a bundled controller, a step kernel between calls of a user's
policy otherwise) and returns the outcomes. Floors MazeGen finds no path on are not driven.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from mazegen.errors import MazeError
from mazegen.runtime.engine.population import Population
from mazegen.runtime.simulation._choice import FIELDS, Choice, choose, lidar_reach
from mazegen.runtime.simulation._episodes import COLLISION, NO_PATH, Episodes
from mazegen.runtime.simulation._fields import floor_fields
from mazegen.runtime.simulation._lidar import beam_angles
from mazegen.runtime.simulation._loop import begin_all, controller_slots, run_all
from mazegen.runtime.simulation._paths import FloorPaths, floor_paths
from mazegen.runtime.simulation._policy import run_policy
from mazegen.runtime.simulation._step import CLEARANCE, CX, CY, DISTANCE, Setup, new_state
from mazegen.runtime.simulation._world import World, world_of
from mazegen.runtime.threads import in_blocks
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
    state, outcome, steps, progress, stuck = new_state(m)
    outcome[np.isnan(optimal)] = NO_PATH
    limits = np.array(
        [
            robot.max_speed,
            robot.min_speed,
            robot.max_turn,
            robot.accel,
            robot.turn_accel,
            robot.step,
            arena.robot_radius,
            robot.goal_tolerance,
        ],
        np.float64,
    )
    goal = np.array(arena.goal, np.float64)
    angles = beam_angles(robot.beams, robot.fov) if choice.lidar else np.zeros(0)
    stuck_steps = max(1, math.ceil(robot.stuck / robot.step - 1e-9))
    run = Setup(
        limits,
        goal,
        world,
        paths,
        angles,
        lidar_reach(choice, robot),
        max_steps.astype(np.int32),
        stuck_steps,
    )
    trajectory = np.full((m if record else 0, int(max_steps.max(initial=0)) + 1, 3), np.nan)
    if m:
        begin_all(poses, limits, goal, world.arrays, state, outcome)
        arrays = (state, outcome, steps, progress, stuck, trajectory)
        if choice.policy is None and choice.name in FIELDS:
            _run_with_fields(population, robot, rows, choice, run, *arrays)
        elif choice.policy is None:
            _run_bundled(choice, run, _NO_FIELDS, *arrays)
        else:
            run_policy(choice.name, choice.policy, run, rows, *arrays)
    driven = outcome != NO_PATH
    return Episodes(
        controller=choice.name,
        outcome=outcome,
        time=steps * robot.step,
        distance=np.where(driven, state[:, DISTANCE], 0.0),
        clearance=np.where(driven, state[:, CLEARANCE], np.nan),
        optimal_time=optimal,
        steps=steps,
        collision=np.where((outcome == COLLISION)[:, None], state[:, [CX, CY]], np.nan),
        stuck=stuck,
        trajectory=trajectory if record else None,
    )


_NO_FIELDS = (np.full((1, 1, 1), np.inf, np.float32), np.zeros((1, 1, 1), np.float32), np.zeros(5))
"""The fields of controllers that read none: one 1×1 dummy shared by every floor."""


FIELD_CHUNK = 1024
"""Floors whose fields are built and driven at a time: the fields of a 128 × 128 grid take 128 kB
a floor, so a drive over many floors holds a chunk's, not all of them."""


def _run_with_fields(
    population: Population, robot: Robot, rows: np.ndarray, choice: Choice, run: Setup, *arrays: np.ndarray
) -> None:
    """Drive chunk after chunk of floors, each with the fields of its floors."""
    world = run.world
    for a in range(0, len(rows), FIELD_CHUNK):
        b = min(a + FIELD_CHUNK, len(rows))
        part = Setup(
            run.limits,
            run.goal,
            World(world.first[a : b + 1], world.vertices, world.count, world.box, world.size),
            FloorPaths(run.paths.length[a:b], run.paths.corners[a:b], run.paths.count[a:b]),
            run.angles,
            run.reach,
            run.max_steps[a:b],
            run.stuck_steps,
        )
        fields = floor_fields(population, robot, rows[a:b])
        _run_bundled(choice, part, fields, *(array[a:b] if len(array) else array for array in arrays))


def _run_bundled(choice: Choice, run: Setup, fields: tuple, *arrays: np.ndarray) -> None:
    paths, fov = (run.paths.corners, run.paths.count), (run.angles, run.reach)
    in_blocks(
        run_all,
        len(arrays[0]),
        *controller_slots(choice.code, choice.params),
        run.world.arrays,
        run.episode,
        *paths,
        fields,
        *fov,
        arrays[:5],
        arrays[5],
        per_thread=32,  # episodes differ in length: many small blocks even them out
    )


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
