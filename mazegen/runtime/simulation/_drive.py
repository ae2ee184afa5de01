"""Drive a controller over floors of a population: one robot per floor, one :class:`Episodes`.

A drive is a set-up and steps. :func:`set_up` turns the floors, robot, controller and starts into a
:class:`~mazegen.runtime.simulation._state.DriveState` whose robots stand at their starts: what
the kernels read (the floors' parts, MazeGen's paths and optimal times, the robot's limits, the
controller's parameters and lidar), floors MazeGen finds no path on marked ``NO_PATH`` and never
driven. :func:`drive` then runs every episode to its end (the compiled loop of a bundled
controller, a step between calls of a user's policy otherwise; the fields of a map-reading
controller built a chunk of floors at a time) and returns what came of them. :func:`drive_many`
drives many requests (floors of different arenas, tasks, robots and controller parameters) in one
batch, each episode exactly as its request alone gives it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mazegen.controllers import COSTMAP, FIELDS
from mazegen.errors import MazeError
from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import grid_of
from mazegen.runtime.simulation._choice import Choice, choose
from mazegen.runtime.simulation._costmap import costmap_fields, costmap_grid
from mazegen.runtime.simulation._episodes import NO_PATH, Episodes
from mazegen.runtime.simulation._fields import floor_fields, joined_fields
from mazegen.runtime.simulation._lidar import beam_angles
from mazegen.runtime.simulation._loop import run_bundled
from mazegen.runtime.simulation._paths import floor_paths
from mazegen.runtime.simulation._policy import run_policy
from mazegen.runtime.simulation._state import DriveState, FloorGroup, Robots, Setup, robot_limits
from mazegen.runtime.simulation._step import begin_all
from mazegen.runtime.simulation._world import world_of
from mazegen.runtime.threads import map_in_threads
from mazegen.spec import ControllerSpec, Robot


@dataclass(frozen=True)
class DriveRequest:
    """Floors to drive and what drives them: one part of a batch of :func:`drive_many`.

    Attributes:
        population: The floors (one arena, task and element library).
        robot: The robot's limits, lidar and timeouts (:func:`mazegen.spec.robot_for`).
        controller: A bundled controller's name, a spec's :class:`ControllerSpec`, a dotted path
            ``package.module:name`` or entry point name of a user's policy, or the policy itself.
        indices: Which individuals to drive, in this order (default: every valid one).
        starts: ``float64[M, 3]`` start pose ``(x, y, theta)`` per driven floor; default the arena's
            start, heading toward the goal.
    """

    population: Population
    robot: Robot
    controller: str | ControllerSpec | Callable[[Any], Any]
    indices: np.ndarray | None = None
    starts: np.ndarray | None = None


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

    The arguments are :class:`DriveRequest`'s; ``record`` keeps every pose (:attr:`Episodes.trajectory`).
    Nothing is drawn at random: the same floors, robot, controller and starts give the same
    episodes (perturbed starts are the caller's, drawn from its own seeded generator).

    Raises:
        MazeError: an unknown controller or parameter, or a user's policy that fails.
    """
    return drive_many([DriveRequest(population, robot, controller, indices, starts)], record=record)[0]


def drive_many(requests: Sequence[DriveRequest], *, record: bool = False) -> list[Episodes]:
    """Drive every request's floors, each with its own arena, task, robot and controller parameters,
    in as few batches as the controllers allow; one :class:`Episodes` per request, in order.

    Requests of one bundled controller whose robots carry the same lidar beams drive in one batch
    (its episodes spread over every thread); a user's policy drives each request on its own, so that
    it sees one robot's limits at a time. Each episode is exactly what driving its request alone
    gives: no episode reads another's floor, robot or parameters.
    """
    planned = [_plan(request) for request in requests]
    found: list[Episodes | None] = [None] * len(planned)
    for batch in _batches(planned):
        state = _joined([planned[k] for k in batch], record)
        if len(state.rows):  # (no floors: nothing to compile)
            _run_to_the_end(state)
        episodes, at = state.episodes(), 0
        for k in batch:
            m = len(planned[k].group.rows)
            found[k] = _own(episodes, at, at + m, planned[k], record)
            at += m
    return [episodes for episodes in found if episodes is not None]


@dataclass(frozen=True)
class _Plan:
    """One request made ready: its floors, resolved controller, set-up and start poses."""

    group: FloorGroup
    choice: Choice
    setup: Setup
    optimal: np.ndarray
    poses: np.ndarray


def _batches(planned: list[_Plan]) -> list[list[int]]:
    """The requests that drive together: one bundled controller and one set of lidar beams."""
    batches: dict[Any, list[int]] = {}
    for k, plan in enumerate(planned):
        choice = plan.choice
        key = k if choice.policy is not None else (choice.code, plan.setup.angles.tobytes())
        batches.setdefault(key, []).append(k)
    return list(batches.values())


def _own(episodes: Episodes, a: int, b: int, plan: _Plan, record: bool) -> Episodes:
    """Episodes ``a`` to ``b - 1`` of a batch: one request's, as driving it alone gives them."""
    trajectory = None
    if record and episodes.trajectory is not None:
        trajectory = episodes.trajectory[a:b, : int(plan.setup.max_steps.max(initial=0)) + 1]
    return Episodes(
        controller=plan.choice.name,
        outcome=episodes.outcome[a:b],
        time=episodes.time[a:b],
        distance=episodes.distance[a:b],
        clearance=episodes.clearance[a:b],
        optimal_time=episodes.optimal_time[a:b],
        steps=episodes.steps[a:b],
        collision=episodes.collision[a:b],
        stuck=episodes.stuck[a:b],
        trajectory=trajectory,
        contacts=None if episodes.contacts is None else episodes.contacts[a:b],
    )


def _run_to_the_end(state: DriveState, loop: Callable[[DriveState, tuple], None] | None = None) -> None:
    """Run every episode of ``state`` to its end, with the loop its controller needs (a bundled
    controller's is ``loop``, given the state and its fields; default :func:`run_bundled`)."""
    loop = run_bundled if loop is None else loop
    choice = state.choice
    if choice.policy is not None:
        run_policy(state, choice.policy)
    elif FIELDS in choice.reads or COSTMAP in choice.reads:
        _run_with_fields(state, loop)
    else:
        loop(state, _NO_FIELDS)


def compile_set_up(population: Population, robot: Robot, controller: str) -> None:
    """Compile what a drive of bundled ``controller`` over ``population``'s floors calls before its
    episode loop (the paths, the parts, the starts, the fields or costmaps), by setting up those floors
    and building their fields, without driving them: half of a first drive's compiling, which
    :func:`compile_loop` leaves to another process."""
    _run_to_the_end(set_up(population, robot, controller, None, None, False), lambda state, fields: None)


def compile_loop(population: Population, robot: Robot, controller: str) -> None:
    """Compile the episode loop a drive of bundled ``controller`` over ``population``'s floors runs,
    with the very types a drive gives it (those of a drive of no floor), and nothing else: no floor is
    set up, so none of :func:`compile_set_up`'s kernels is called."""
    state = set_up(population, robot, controller, np.zeros(0, np.int64), None, False)
    reads = state.choice.reads
    if COSTMAP in reads:
        run_bundled(state, joined_fields([costmap_fields(population, state.choice.params, state.rows)]))
    elif FIELDS in reads:
        run_bundled(state, joined_fields([floor_fields(population, robot, state.rows)]))
    else:
        run_bundled(state, _NO_FIELDS)


_NO_FIELDS = (np.full((1, 1, 1), np.inf, np.float32), np.zeros((1, 1, 1), np.float32), np.zeros((1, 5)))
"""The fields of controllers that read none: one 1×1 dummy shared by every floor."""


FIELD_CELLS = 1 << 24
"""Field cells built and driven at a time (a chunk of floors, at least one): 16 M cells of the two or
three float32 layers a floor's fields hold take 130 to 200 MB, so a drive over many floors holds a
chunk's, not all of them."""


def _run_with_fields(state: DriveState, loop: Callable[[DriveState, tuple], None]) -> None:
    """Drive chunk after chunk of floors with ``loop``, each with the fields of its floors."""
    costmap = COSTMAP in state.choice.reads
    cells = np.concatenate(
        [np.full(len(g.rows), _cells(g, params, costmap)) for g, params in _group_params(state)]
    )
    a = 0
    while a < len(cells):
        b = a + max(1, int(np.searchsorted(np.cumsum(cells[a:]), FIELD_CELLS, side="right")))
        part = state.part(a, b)
        if costmap:
            fields = map_in_threads(_group_costmap, _group_params(part))
        else:
            fields = map_in_threads(_group_fields, part.groups)
        loop(part, joined_fields(fields))
        a = b


def _group_costmap(group_params: tuple[FloorGroup, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    group, params = group_params
    return costmap_fields(group.population, params, group.rows)


def _group_fields(group: FloorGroup) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return floor_fields(group.population, group.robot, group.rows)


def _group_params(state: DriveState) -> list[tuple[FloorGroup, np.ndarray]]:
    """Each group of ``state`` with its controller parameters (one row for all its floors)."""
    found, at = [], 0
    for group in state.groups:
        found.append((group, state.setup.params[at]))
        at += len(group.rows)
    return found


def _cells(group: FloorGroup, params: np.ndarray, costmap: bool) -> int:
    """Cells of each of ``group``'s floors' fields."""
    grid = costmap_grid(group.population.arena, params) if costmap else grid_of(group.population.arena)
    return grid.rows * grid.cols


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
    return _joined([_plan(DriveRequest(population, robot, controller, indices, starts))], record)


def _plan(request: DriveRequest) -> _Plan:
    population, robot = request.population, request.robot
    arena = population.arena
    choice = choose(request.controller, robot, arena)
    indices = request.indices
    rows = np.flatnonzero(population.valid) if indices is None else np.asarray(indices, np.int64).reshape(-1)
    m = len(rows)
    if m and (rows.min() < 0 or rows.max() >= population.size):
        raise MazeError(f"indices must lie in [0, {population.size}), got {rows.min()}..{rows.max()}")
    poses = start_poses(population, m, request.starts)
    paths = floor_paths(population, rows, margin=choice.margin)
    optimal = paths.length / robot.max_speed
    max_steps, stuck_steps = step_limits(robot, optimal)
    setup = Setup(
        np.tile(robot_limits(robot, arena), (m, 1)),
        np.tile(np.array(arena.goal, np.float64), (m, 1)),
        world_of(population, rows),
        paths,
        np.tile(choice.params, (m, 1)),
        beam_angles(robot.beams, robot.fov) if choice.lidar else np.zeros(0),
        np.full(m, choice.reach),
        max_steps,
        stuck_steps,
        np.full(m, robot.contact == "continue"),
    )
    return _Plan(FloorGroup(population, rows, robot), choice, setup, optimal, poses)


def step_limits(robot: Robot, optimal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``int32`` steps before each episode times out (``robot.timeout`` times its optimal time, 0
    without a path) and ``int64`` steps without progress before it times out, stuck."""
    driven = np.ceil(robot.timeout * np.nan_to_num(optimal) / robot.step - 1e-9)
    max_steps = np.where(np.isnan(optimal), 0, driven).astype(np.int32)
    return max_steps, np.full(len(optimal), max(1, math.ceil(robot.stuck / robot.step - 1e-9)), np.int64)


def _joined(planned: list[_Plan], record: bool) -> DriveState:
    """One drive of the planned requests' floors, one after another, its robots at their starts."""
    setup = planned[0].setup if len(planned) == 1 else Setup.joined([plan.setup for plan in planned])
    optimal = np.concatenate([plan.optimal for plan in planned])
    m = len(optimal)
    robots = Robots.new(m, int(setup.max_steps.max(initial=0)) if record else None)
    robots.outcome[np.isnan(optimal)] = NO_PATH
    if m:
        poses = np.concatenate([plan.poses for plan in planned])
        arrays = (setup.world.arrays, robots.state, robots.outcome, setup.boxes)
        begin_all(poses, setup.limits, setup.goal, *arrays)
    groups = tuple(plan.group for plan in planned)
    return DriveState(groups, planned[0].choice, optimal, setup, robots, record)


def start_poses(population: Population, m: int, starts: np.ndarray | None) -> np.ndarray:
    """``float64[m, 3]``: ``starts`` checked, or the arena's start heading toward the goal ``m`` times."""
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
