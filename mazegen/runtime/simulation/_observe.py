"""What a robot sees at a step: the lidar, the goal in its own frame and its velocity, gathered for
every robot still driving at once (:class:`Observations`), as a user's policy is shown it."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from mazegen.runtime.simulation._lidar import scan
from mazegen.runtime.simulation._state import THETA, DriveState, V, W, X, Y
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
        limits: ``float64[8]`` the robot's max_speed, min_speed, max_turn, accel, turn_accel, step,
            radius and goal_tolerance (arena units, seconds, radians;
            :data:`mazegen.controllers.LIMITS`).
    """

    scan: np.ndarray
    angles: np.ndarray
    goal: np.ndarray
    velocity: np.ndarray
    step: int
    floor: np.ndarray
    limits: np.ndarray


def observe(drive: DriveState, active: np.ndarray, step: int) -> Observations:
    """What robots ``active`` of ``drive`` see after ``step`` steps."""
    setup, state = drive.setup, drive.robots.state
    most = int(np.diff(setup.world.first).max(initial=0))  # the scan's scratch: the most parts a floor has
    n = active.size
    ranges = np.empty((n, setup.angles.size))
    goal = np.empty((n, 3))
    lidar = (setup.angles, setup.reach, setup.world.arrays, most)
    in_blocks(_observe_kernel, n, active, state, setup.goal, *lidar, ranges, goal)
    velocity = state[active][:, [V, W]]
    return Observations(
        ranges, _read_only(setup.angles), goal, velocity, step, drive.rows[active], _read_only(setup.limits)
    )


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
        m = active[j]
        x, y, theta = state[m, X], state[m, Y], state[m, THETA]
        if angles.shape[0]:
            scan(x, y, theta, angles, reach, m, world, near, ranges[j])
        dx, dy = goal[0] - x, goal[1] - y
        bearing = math.atan2(dy, dx) - theta
        to_goal[j, 0] = math.hypot(dx, dy)
        to_goal[j, 1] = math.cos(bearing)
        to_goal[j, 2] = math.sin(bearing)
