"""A user's batch policy in the loop: one Python call per step for every robot still driving.

Between calls, compiled kernels run over the robots still driving: :func:`observe` gathers what
they see (:class:`Observations`: lidar, goal in the robot frame, velocity), and
:func:`mazegen.runtime.simulation._step.step` steps them by the returned actions through the same
step as the bundled controllers; a caller deciding the commands itself (a Gymnasium environment,
say) calls the two alike. A policy that raises (or exits), returns the wrong shape, numbers that
are not real, or a non-finite action ends the drive with one line naming the controller, the step
and the floor.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numba import njit

from mazegen.controllers import LIMITS
from mazegen.errors import MazeError
from mazegen.runtime.simulation._lidar import scan
from mazegen.runtime.simulation._state import ACTIVE, THETA, DriveState, Setup, V, W, X, Y
from mazegen.runtime.simulation._step import record, step
from mazegen.runtime.threads import in_blocks


@dataclass(frozen=True)
class Observations:
    """What a batch policy sees at one step, one row per robot still driving (``n`` of them).

    Attributes:
        scan: ``float64[n, beams]`` lidar ranges (arena units), each at most the lidar's range.
        angles: ``float64[beams]`` the beams' angles relative to the heading (radians).
        goal: ``float64[n, 3]`` the goal in the robot's frame: distance, and the cosine and sine of
            its bearing (0 straight ahead, positive to the left).
        velocity: ``float64[n, 2]`` the current speed and turn rate ``(v, w)``.
        step: Steps driven so far (0 at the first call); every robot shown has driven as many.
        floor: ``int64[n]`` the population indices of the floors the robots drive on.
        limits: ``float64[10]`` the robot's max_speed, min_speed, max_turn, accel, turn_accel, step,
            radius, goal_tolerance, and its box's length and width (0 for a disc) (arena units,
            seconds, radians; :data:`mazegen.controllers.LIMITS`).
    """

    scan: np.ndarray
    angles: np.ndarray
    goal: np.ndarray
    velocity: np.ndarray
    step: int
    floor: np.ndarray
    limits: np.ndarray


def run_policy(drive: DriveState, policy: Callable[[Observations], Any]) -> None:
    """Drive every robot of ``drive`` still driving to the end of its episode with ``policy``, its
    controller, one call per step."""
    name = drive.choice.name
    active = drive.active()
    record(drive, active)
    steps = 0
    while active.size:
        actions = _actions(name, policy, observe(drive, active, steps), steps)
        step(drive, active, actions)
        steps += 1
        active = active[drive.robots.outcome[active] == ACTIVE]


def _actions(
    name: str, policy: Callable[[Observations], Any], observations: Observations, driven: int
) -> np.ndarray:
    n = observations.floor.size
    where = f"controller {name} at step {driven}"
    try:
        returned = np.asarray(policy(observations))
    except (Exception, SystemExit) as error:  # the user's code: any failure is theirs, said in one line
        floors = observations.floor
        raise MazeError(
            f"{where} (floors {floors[0]}{'...' if n > 1 else ''}, {n} driving) raised "
            f"{type(error).__name__}: {error}"
        ) from error
    if returned.dtype.kind not in "biuf":  # complex, text, objects: no (v, w) without a guess
        raise MazeError(
            f"{where} on floor {observations.floor[0]}: returned actions of type {returned.dtype}, "
            "expected real numbers"
        )
    actions = returned.astype(np.float64)
    if actions.shape != (n, 2):
        raise MazeError(
            f"{where} on floor {observations.floor[0]}: returned actions of shape {actions.shape}, "
            f"expected ({n}, 2): one (v, w) per robot"
        )
    bad = np.flatnonzero(~np.isfinite(actions).all(axis=1))
    if bad.size:
        raise MazeError(
            f"{where} on floor {observations.floor[bad[0]]}: returned a non-finite action {actions[bad[0]]}"
        )
    return np.ascontiguousarray(actions)


def observe(drive: DriveState, active: np.ndarray, driven: int) -> Observations:
    """What robots ``active`` of ``drive`` see after ``driven`` steps."""
    setup, state = drive.setup, drive.robots.state
    most = int(np.diff(setup.world.first).max(initial=0))  # the scan's scratch: the most parts a floor has
    n = active.size
    ranges = np.empty((n, setup.angles.size))
    goal = np.empty((n, 3))
    lidar = (setup.angles, setup.reach, setup.world.arrays, most)
    in_blocks(_observe_kernel, n, active, state, setup.goal, *lidar, ranges, goal)
    velocity = state[active][:, [V, W]]
    return Observations(
        ranges, _read_only(setup.angles), goal, velocity, driven, drive.rows[active], _robot_limits(setup)
    )


def _robot_limits(setup: Setup) -> np.ndarray:
    """The limits of the robot a policy drives (a policy drives one request at a time, one robot)."""
    return _read_only(setup.limits[0] if len(setup.limits) else np.zeros(len(LIMITS)))


def _read_only(array: np.ndarray) -> np.ndarray:
    """A read-only copy of an array the simulator reads: a policy that writes into it is told so,
    and whatever it does to the copy never reaches the episodes."""
    copy = array.copy()
    copy.flags.writeable = False
    return copy


@njit(cache=True, nogil=True)
def _observe_kernel(
    first, last, active, state, goal, angles, reach, world, most, ranges, to_goal
):  # pragma: no cover - compiled
    near = np.empty(most, np.int64)
    for j in range(first, last):
        look(active[j], j, state, goal, angles, reach, world, near, ranges, to_goal)


@njit(cache=True)
def look(m, j, state, goal, angles, reach, world, near, ranges, to_goal):  # pragma: no cover - compiled
    """What robot ``m`` sees, written to row ``j`` of ``ranges`` (its lidar, when it has beams) and of
    ``to_goal`` (the goal's distance and the cosine and sine of its bearing); ``near`` is the scan's
    scratch."""
    x, y, theta = state[m, X], state[m, Y], state[m, THETA]
    if angles.shape[0]:
        scan(x, y, theta, angles, reach[m], m, world, near, ranges[j])
    dx, dy = goal[m, 0] - x, goal[m, 1] - y
    bearing = math.atan2(dy, dx) - theta
    to_goal[j, 0] = math.hypot(dx, dy)
    to_goal[j, 1] = math.cos(bearing)
    to_goal[j, 2] = math.sin(bearing)
