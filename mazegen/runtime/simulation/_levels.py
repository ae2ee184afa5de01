"""Levels as fixed-shape arrays: everything an episode on a floor reads, one row per level.

A level is a floor, a task (start pose and goal) and a robot. :class:`LevelRows` holds ``n`` of
them padded to common shapes (the most parts, vertices and path corners of any), so that levels of
different specs, arenas and robots sit in one set of arrays: a vector environment copies a row into
the slot of the robot that plays it (:mod:`mazegen.runtime.simulation._slots`), a curriculum keeps
them, and JAX users load a batch from one ``.npz`` and ``vmap`` over it. A padding part has no
vertices and an empty box (``+inf`` low corner, ``-inf`` high corner), which every collision, distance
and lidar kernel culls before any exact test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mazegen.controllers import BUNDLED
from mazegen.runtime.engine import Population
from mazegen.runtime.simulation._drive import start_poses, step_limits
from mazegen.runtime.simulation._paths import floor_paths
from mazegen.runtime.simulation._state import robot_limits
from mazegen.runtime.simulation._world import stacked, world_of
from mazegen.spec import Robot, metres_per_unit

INERT_BOX = (math.inf, math.inf, -math.inf, -math.inf)
"""The box of a padding part: no point lies in it, so every kernel culls it."""

_PUREPURSUIT = BUNDLED["purepursuit"]
PLAN_MARGIN: float = _PUREPURSUIT.parameters[_PUREPURSUIT.index("path_margin")].default
"""Metres a level's path keeps clear of the obstacles beyond the robot's radius where it can (half that
where it cannot, else none): BARN's inflation radius, as ``purepursuit``'s path keeps, and as
move_base's global plan on its inflated costmap does. MazeGen's own path touches the configuration
space's edge: a robot following it closely grazes every corner (a pure pursuit of a point 0.5 m
ahead on it arrives on 73 of 96 held-out training-spec floors, on this path on all 96)."""


@dataclass(frozen=True)
class LevelRows:
    """``n`` levels, one row each (arena units, seconds, radians).

    Attributes:
        parts: ``float64[n, P, V, 2]`` each floor's convex parts (its elements' and its base map's
            walls), vertices counter-clockwise, padded.
        count: ``int64[n, P]`` vertices of each part; 0 marks a padding part.
        box: ``float64[n, P, 4]`` each part's ``(xmin, ymin, xmax, ymax)``; :data:`INERT_BOX` for padding.
        size: ``float64[n, 2]`` the arena's width and height (its walls).
        start: ``float64[n, 3]`` the start pose ``(x, y, theta)``.
        goal: ``float64[n, 2]``.
        limits: ``float64[n, 10]`` the robot's limits (:data:`mazegen.controllers.LIMITS`).
        path: ``float64[n, C, 2]`` the corners of the level's path, start to goal, padded: MazeGen's
            path kept :data:`PLAN_MARGIN` clear where it can.
        path_count: ``int64[n]`` corners of each path.
        optimal_time: ``float64[n]`` the path's length over the top speed (BARN's OT).
        max_steps: ``int32[n]`` steps before the episode times out.
        stuck_steps: ``int64[n]`` steps without progress before it times out, stuck.
        carry_on: ``bool[n]`` whether the robot's contacts continue.
        reach: ``float64[n]`` the lidar's range.
        scale: ``float64[n]`` metres in one arena unit.
    """

    parts: np.ndarray
    count: np.ndarray
    box: np.ndarray
    size: np.ndarray
    start: np.ndarray
    goal: np.ndarray
    limits: np.ndarray
    path: np.ndarray
    path_count: np.ndarray
    optimal_time: np.ndarray
    max_steps: np.ndarray
    stuck_steps: np.ndarray
    carry_on: np.ndarray
    reach: np.ndarray
    scale: np.ndarray

    def __len__(self) -> int:
        return len(self.start)

    @property
    def arrays(self) -> dict[str, np.ndarray]:
        """Every array by its field's name."""
        return dict(vars(self))  # the fields, in their order (a dataclass without slots)

    def take(self, rows: np.ndarray) -> LevelRows:
        """Levels ``rows``, in that order."""
        index = np.asarray(rows, np.int64)
        return LevelRows(**{name: array[index] for name, array in self.arrays.items()})

    @classmethod
    def joined(cls, levels: list[LevelRows]) -> LevelRows:
        """The levels of ``levels`` one after another, padded to the largest shapes."""
        if len(levels) == 1:
            return levels[0]
        arrays = {name: stacked([level.arrays[name] for level in levels], 0) for name in levels[0].arrays}
        arrays["box"][arrays["count"] == 0] = INERT_BOX
        return cls(**arrays)


def level_rows(
    population: Population, robot: Robot, indices: np.ndarray, starts: np.ndarray | None = None
) -> LevelRows:
    """The levels of floors ``indices`` of ``population`` (its arena's task) driven by ``robot`` from
    ``starts`` (default the arena's start, heading toward the goal); MazeGen's path is searched on
    each, kept :data:`PLAN_MARGIN` clear where it can (its length, and the optimal time, MazeGen's; a
    floor without one has ``optimal_time`` NaN and no corners)."""
    arena = population.arena
    rows = np.ascontiguousarray(indices, np.int64).reshape(-1)
    n = len(rows)
    world = world_of(population, rows)
    per_floor = np.diff(world.first)
    most = int(per_floor.max(initial=0))
    at = world.first[:-1, None] + np.arange(max(most, 1))
    real = np.arange(max(most, 1)) < per_floor[:, None]
    at = np.where(real, at, 0)
    has_parts = len(world.count) > 0
    parts = np.where(real[..., None, None], world.vertices[at], 0.0) if has_parts else np.zeros((n, 1, 3, 2))
    count = np.where(real, world.count[at], 0) if has_parts else np.zeros((n, 1), np.int64)
    box = (
        np.where(real[..., None], world.box[at], np.array(INERT_BOX))
        if has_parts
        else np.tile(INERT_BOX, (n, 1, 1))
    )
    paths = floor_paths(population, rows, margin=PLAN_MARGIN / metres_per_unit(arena))
    optimal = paths.length / robot.max_speed
    max_steps, stuck_steps = step_limits(robot, optimal)
    return LevelRows(
        parts=np.ascontiguousarray(parts, np.float64),
        count=np.ascontiguousarray(count, np.int64),
        box=np.ascontiguousarray(box, np.float64),
        size=world.size,
        start=start_poses(population, n, starts),
        goal=np.tile(np.array(arena.goal, np.float64), (n, 1)),
        limits=np.tile(robot_limits(robot, arena), (n, 1)),
        path=paths.corners,
        path_count=paths.count,
        optimal_time=optimal,
        max_steps=max_steps,
        stuck_steps=stuck_steps,
        carry_on=np.full(n, robot.contact == "continue"),
        reach=np.full(n, robot.lidar_range),
        scale=np.full(n, metres_per_unit(arena)),
    )
