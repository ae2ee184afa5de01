"""A drive's state: what its episodes read (:class:`Setup`) and write (:class:`Robots`), one row
per driven floor, gathered in a :class:`DriveState`.

:func:`mazegen.runtime.simulation._drive.set_up` makes one; the step kernel
(:func:`mazegen.runtime.simulation._step.advance`) moves it on, a whole episode at a time in the
compiled loop of a bundled controller, or one step of every robot at a time between calls of a
user's policy; :meth:`DriveState.episodes` reads what came of it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mazegen.controllers import LIMITS
from mazegen.runtime.engine import Population
from mazegen.runtime.simulation._choice import Choice
from mazegen.runtime.simulation._episodes import COLLISION, NO_PATH, Episodes
from mazegen.runtime.simulation._paths import FloorPaths
from mazegen.runtime.simulation._world import World, stacked
from mazegen.spec import Arena, Robot

ACTIVE = -1
"""The outcome of an episode still running."""

X, Y, THETA, V, W, DISTANCE, CLEARANCE, SAFE, BEST, CX, CY = range(11)
"""Columns of a robot's state: pose, velocity, distance driven, closest approach so far, the lower
bound of the distance to obstacles, best distance to the goal so far, contact centre."""
COLUMNS = 11


def robot_limits(robot: Robot, arena: Arena) -> np.ndarray:
    """``float64[10]``: ``robot``'s limits in the order of :data:`mazegen.controllers.LIMITS`."""
    length, width = robot.footprint or (0.0, 0.0)
    values = {
        "max_speed": robot.max_speed,
        "min_speed": robot.min_speed,
        "max_turn": robot.max_turn,
        "accel": robot.accel,
        "turn_accel": robot.turn_accel,
        "step": robot.step,
        "radius": arena.robot_radius,
        "goal_tolerance": robot.goal_tolerance,
        "length": length,
        "width": width,
    }
    return np.array([values[name] for name in LIMITS], np.float64)


def boxes_of(limits: np.ndarray) -> np.ndarray | None:
    """``limits`` when any of their robots collides as a box (its ``footprint``), else None: what the
    step kernels take as ``boxes``, compiling the box's branches only for a drive that has one."""
    return limits if limits[:, LIMITS.index("length")].any() else None


@dataclass(frozen=True)
class Setup:
    """What the episodes of one drive read, a row or value per driven floor (floors of different
    arenas, tasks and robots drive in one batch): the robot's limits (:func:`robot_limits`), the goal,
    the floors' parts and paths, the controller's parameters, the lidar's beam angles (one set for
    the batch) and range, the step limits, whether its contacts continue."""

    limits: np.ndarray
    goal: np.ndarray
    world: World
    paths: FloorPaths
    params: np.ndarray
    angles: np.ndarray
    reach: np.ndarray
    max_steps: np.ndarray
    stuck_steps: np.ndarray
    carry_on: np.ndarray

    @property
    def boxes(self) -> np.ndarray | None:
        """:func:`boxes_of` the robots' limits."""
        return boxes_of(self.limits)

    @property
    def episode(self) -> tuple:
        """``(limits, goal, max_steps, stuck_steps, carry_on)``: what the step kernel reads besides the
        parts."""
        return self.limits, self.goal, self.max_steps, self.stuck_steps, self.carry_on

    def part(self, a: int, b: int) -> Setup:
        """What the episodes of driven floors ``a`` to ``b - 1`` read."""
        paths = self.paths
        return Setup(
            self.limits[a:b],
            self.goal[a:b],
            self.world.part(a, b),
            FloorPaths(paths.length[a:b], paths.corners[a:b], paths.count[a:b]),
            self.params[a:b],
            self.angles,
            self.reach[a:b],
            self.max_steps[a:b],
            self.stuck_steps[a:b],
            self.carry_on[a:b],
        )

    @classmethod
    def joined(cls, setups: list[Setup]) -> Setup:
        """The set-ups of ``setups``' floors one after another (paths padded to the most corners);
        they share one set of lidar beams."""
        corners = stacked([s.paths.corners for s in setups], 0.0)
        return cls(
            np.concatenate([s.limits for s in setups]),
            np.concatenate([s.goal for s in setups]),
            World.joined([s.world for s in setups]),
            FloorPaths(
                np.concatenate([s.paths.length for s in setups]),
                corners,
                np.concatenate([s.paths.count for s in setups]),
            ),
            np.concatenate([s.params for s in setups]),
            setups[0].angles,
            np.concatenate([s.reach for s in setups]),
            np.concatenate([s.max_steps for s in setups]),
            np.concatenate([s.stuck_steps for s in setups]),
            np.concatenate([s.carry_on for s in setups]),
        )


@dataclass(frozen=True)
class Robots:
    """What the episodes write, one row per driven floor: the state (columns :data:`X` … :data:`CY`),
    the outcome (:data:`ACTIVE` while driving), the steps driven, the step of the last progress
    toward the goal, whether the episode ended stuck, the steps that touched an obstacle, and the
    poses (no rows unless recorded)."""

    state: np.ndarray
    outcome: np.ndarray
    steps: np.ndarray
    progress: np.ndarray
    stuck: np.ndarray
    contacts: np.ndarray
    trajectory: np.ndarray

    @classmethod
    def new(cls, m: int, recorded_steps: int | None) -> Robots:
        """``m`` robots, none started; poses kept for up to ``recorded_steps`` steps (None: not kept)."""
        rows, columns = (0, 1) if recorded_steps is None else (m, recorded_steps + 1)
        return cls(
            np.full((m, COLUMNS), np.nan),
            np.full(m, ACTIVE, np.int8),
            np.zeros(m, np.int32),
            np.zeros(m, np.int32),
            np.zeros(m, np.bool_),
            np.zeros(m, np.int32),
            np.full((rows, columns, 3), np.nan),
        )

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(state, outcome, steps, progress, stuck, contacts)``: what the step kernel writes."""
        return self.state, self.outcome, self.steps, self.progress, self.stuck, self.contacts

    def part(self, a: int, b: int) -> Robots:
        """Views of robots ``a`` to ``b - 1``."""
        state, outcome, steps, progress, stuck, contacts = (array[a:b] for array in self.arrays)
        trajectory = self.trajectory[a:b] if len(self.trajectory) else self.trajectory
        return Robots(state, outcome, steps, progress, stuck, contacts, trajectory)


@dataclass(frozen=True)
class FloorGroup:
    """Floors ``rows`` of ``population``, driven by ``robot``: one part of a drive's batch."""

    population: Population
    rows: np.ndarray
    robot: Robot


@dataclass(frozen=True)
class DriveState:
    """One drive: its floors (``groups``, one after another; ``rows`` their population indices), its
    controller, what its episodes read and what they have written so far."""

    groups: tuple[FloorGroup, ...]
    choice: Choice
    optimal: np.ndarray
    setup: Setup
    robots: Robots
    record: bool

    @property
    def rows(self) -> np.ndarray:
        """``int64[M]``: each driven floor's index in its group's population."""
        if len(self.groups) == 1:
            return self.groups[0].rows
        return np.concatenate([group.rows for group in self.groups]) if self.groups else np.zeros(0, np.int64)

    def part(self, a: int, b: int) -> DriveState:
        """The drive of floors ``a`` to ``b - 1`` alone, sharing this one's arrays."""
        groups, at = [], 0
        for group in self.groups:
            low, high = max(a - at, 0), min(b - at, len(group.rows))
            if low < high:
                groups.append(FloorGroup(group.population, group.rows[low:high], group.robot))
            at += len(group.rows)
        return DriveState(
            tuple(groups),
            self.choice,
            self.optimal[a:b],
            self.setup.part(a, b),
            self.robots.part(a, b),
            self.record,
        )

    def active(self) -> np.ndarray:
        """The robots still driving."""
        return np.flatnonzero(self.robots.outcome == ACTIVE)

    def episodes(self) -> Episodes:
        """What came of the drive so far."""
        state, outcome = self.robots.state, self.robots.outcome
        driven = outcome != NO_PATH
        return Episodes(
            controller=self.choice.name,
            outcome=outcome,
            time=self.robots.steps * self.setup.limits[:, LIMITS.index("step")],
            distance=np.where(driven, state[:, DISTANCE], 0.0),
            clearance=np.where(driven, state[:, CLEARANCE], np.nan),
            optimal_time=self.optimal,
            steps=self.robots.steps,
            collision=np.where(
                ((outcome == COLLISION) | (self.robots.contacts > 0))[:, None], state[:, [CX, CY]], np.nan
            ),
            stuck=self.robots.stuck,
            contacts=self.robots.contacts,
            trajectory=self.robots.trajectory if self.record else None,
        )
