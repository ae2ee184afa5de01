"""One robot's episode, step by step: the kinematics, the collision verdict and how episodes end.

A robot's state is a row of ``state`` (columns :data:`X` … :data:`CY`) plus its outcome, step
count, the step of its last progress toward the goal and whether it ended stuck. Each step:

1. The command ``(v, w)`` is clamped to the acceleration window around the current velocity
   (``accel · step``, ``turn_accel · step``), then to ``[min_speed, max_speed]`` and
   ``[-max_turn, max_turn]``.
2. Forward Euler, as IR-SIM: ``x += v cos(theta) dt; y += v sin(theta) dt; theta += w dt``.
3. The swept disc is checked exactly (:func:`mazegen.runtime.simulation._collide.sweep`), or for
   a robot with a ``footprint`` the box moved along its heading and then turned
   (:func:`mazegen.runtime.simulation._box.box_sweep`). A lower bound of the centre's distance to
   every obstacle (``SAFE``: the last distance computed, less the length driven since) skips the
   check when no point of the robot can touch (the disc's radius, the box's half diagonal); the
   verdict is exact either way.
4. The episode ends: **arrived** when the segment comes within ``goal_tolerance`` of the goal
   (before any contact); **collision** at the first contact, the robot left at the start of the
   step's segment and the contact centre kept, unless the robot's contacts continue (Gazebo's
   physics, where a touch ends nothing): then the robot stays at the start of the segment, its
   speed 0, its turn made (a box's only if it turns there clear), the touch counted and the first
   contact's centre kept, and drives on;
   **timeout** after ``max_steps`` steps or, stuck, after ``stuck_steps`` steps without a new best
   distance to the goal (better by at least :data:`PROGRESS` of a step at top speed).

The clearance (closest approach of the robot's edge) is taken at every pose, computed exactly
whenever the lower bound cannot rule out a new minimum.

:func:`advance` is the one step every way of driving shares: the compiled episode loop of a
bundled controller (:mod:`mazegen.runtime.simulation._loop`) calls it after each command, and
:func:`step` calls it for every robot at once with the commands a caller decided between steps (a
user's policy, :mod:`mazegen.runtime.simulation._policy`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import wrapped_leaf_kernel
from mazegen.runtime.simulation._box import box_distance, box_sweep, turn_touches
from mazegen.runtime.simulation._collide import NO_HIT, disc_entry, distance, sweep
from mazegen.runtime.simulation._controllers import (
    ACCEL,
    GOAL_TOLERANCE,
    LENGTH,
    MAX_SPEED,
    MAX_TURN,
    MIN_SPEED,
    RADIUS,
    STEP,
    TURN_ACCEL,
    WIDTH,
)
from mazegen.runtime.simulation._episodes import ARRIVED, COLLISION, TIMEOUT
from mazegen.runtime.simulation._state import (
    ACTIVE,
    BEST,
    CLEARANCE,
    CX,
    CY,
    DISTANCE,
    SAFE,
    THETA,
    DriveState,
    V,
    W,
    X,
    Y,
)
from mazegen.runtime.threads import in_blocks

LOOKOUT = 8
"""Steps at top speed beyond the closest approach so far that distances are searched to."""
PROGRESS = 0.01
"""Progress is a new best distance to the goal by at least this fraction of a step at top speed:
creeping ever closer by less does not hold off the stuck timeout."""


def step(drive: DriveState, active: np.ndarray, actions: np.ndarray) -> None:
    """Step robots ``active`` (still driving) of ``drive`` once, each by its row of ``actions``
    (``float64[len(active), 2]``, ``(v, w)``), and record their poses when poses are kept: the step
    of a caller that decides every robot's command between steps (a user's policy)."""
    setup = drive.setup
    arrays = (setup.world.arrays, setup.episode, drive.robots.arrays, setup.boxes)
    in_blocks(_apply, active.size, active, actions, *arrays)
    record(drive, active)


def record(drive: DriveState, active: np.ndarray) -> None:
    """Keep the poses of robots ``active`` at the steps they have driven, when poses are kept."""
    robots = drive.robots
    if robots.trajectory.shape[0] and active.size:
        robots.trajectory[active, robots.steps[active]] = robots.state[active][:, [X, Y, THETA]]


@njit(cache=True, nogil=True)
def _apply(first, last, active, actions, world, episode, robots, boxes):  # pragma: no cover - compiled
    for j in range(first, last):
        advance(active[j], actions[j, 0], actions[j, 1], world, episode, robots, boxes)


@njit(cache=True)
def begin_all(starts, limits, goal, world, state, outcome, boxes):  # pragma: no cover - compiled
    """Put every robot still to drive (outcome ``ACTIVE``) at its start; ``limits`` and ``goal``
    are each robot's rows."""
    for m in range(starts.shape[0]):
        if outcome[m] == ACTIVE:
            x, y, theta = starts[m, 0], starts[m, 1], starts[m, 2]
            begin(m, x, y, theta, limits[m], goal[m], world, state, outcome, boxes)


@njit(cache=True)
def begin(m, x, y, theta, limits, goal, world, state, outcome, boxes):  # pragma: no cover - compiled
    """Put robot ``m`` at its start, at rest; a start touching an obstacle is a collision and a
    start within the goal tolerance an arrival, both after 0 steps. ``boxes`` as :func:`advance`
    takes it."""
    state[m, X], state[m, Y], state[m, THETA] = x, y, theta
    state[m, V] = state[m, W] = state[m, DISTANCE] = 0.0
    d = distance(x, y, m, world, np.inf)
    state[m, SAFE] = d
    edge = d - limits[RADIUS]
    if boxes is not None:  # noqa: SIM102 - a test of the argument alone, which numba prunes
        if limits[LENGTH] > 0.0:
            edge = box_distance(x, y, theta, 0.5 * limits[LENGTH], 0.5 * limits[WIDTH], m, world, np.inf)
    state[m, CLEARANCE] = max(edge, 0.0)
    state[m, BEST] = math.hypot(goal[0] - x, goal[1] - y)
    if edge <= 0.0:
        outcome[m] = COLLISION
        state[m, CX], state[m, CY] = x, y
    elif state[m, BEST] <= limits[GOAL_TOLERANCE]:
        outcome[m] = ARRIVED


@njit(cache=True, inline="always")
def _window(command, current, change, low, high):  # pragma: no cover - compiled
    return min(max(min(max(command, current - change), current + change), low), high)


@wrapped_leaf_kernel
def advance(m, command_v, command_w, world, episode, robots, boxes):  # pragma: no cover - compiled
    """Step robot ``m`` by the command ``(command_v, command_w)``; see the module's docstring.

    ``world`` is the floors' parts (:class:`mazegen.runtime.simulation._world.World`'s arrays);
    ``episode`` is ``(limits, goal, max_steps, stuck_steps, carry_on)``, one row or value per robot:
    what the robots of a drive read (floors of different arenas and robots drive in one batch;
    ``carry_on`` whether its contacts continue);
    ``robots`` is ``(state, outcome, steps, progress, stuck, contacts)``: what they write. (The parts are not
    in ``episode``: numba's parallel loops take no tuple nested in a tuple.)
    ``boxes`` is None when no robot of the drive is a box (:attr:`._state.Setup.boxes`): numba then
    leaves the box's branches out, and a drive of discs compiles none of :mod:`._box`.
    """
    limits, goal = episode[0], episode[1]  # a row each per robot, indexed, not sliced: no view a step
    max_steps, stuck_steps, carry_on = episode[2], episode[3], episode[4]
    state, outcome, steps, progress, stuck, contacts = robots
    dt = limits[m, STEP]
    r = limits[m, RADIUS]
    hl, hw = 0.5 * limits[m, LENGTH], 0.5 * limits[m, WIDTH]
    outer = math.hypot(hl, hw) if hl > 0.0 else r  # no point of the robot is farther from its centre
    v = _window(command_v, state[m, V], limits[m, ACCEL] * dt, limits[m, MIN_SPEED], limits[m, MAX_SPEED])
    w = _window(command_w, state[m, W], limits[m, TURN_ACCEL] * dt, -limits[m, MAX_TURN], limits[m, MAX_TURN])
    x0, y0, theta = state[m, X], state[m, Y], state[m, THETA]
    dx = v * math.cos(theta) * dt
    dy = v * math.sin(theta) * dt
    x1, y1 = x0 + dx, y0 + dy
    length = abs(v) * dt
    safe = state[m, SAFE] - length  # no point of the segment is nearer an obstacle than this
    hit = NO_HIT
    if safe <= outer:  # (else no point of the robot can touch)
        if hl == 0.0:
            hit = sweep(x0, y0, x1, y1, r, m, world)
        elif boxes is not None:
            hit = box_sweep(x0, y0, theta, dx, dy, w * dt, hl, hw, m, world)
    reach = disc_entry(x0, y0, dx, dy, goal[m, 0], goal[m, 1], limits[m, GOAL_TOLERANCE])
    steps[m] += 1
    state[m, V], state[m, W] = v, w
    if hit <= 1.0 and hit < reach:
        if contacts[m] == 0:
            state[m, CX], state[m, CY] = x0 + hit * dx, y0 + hit * dy
        contacts[m] += 1
        state[m, CLEARANCE] = 0.0
        if not carry_on[m]:
            outcome[m] = COLLISION
            state[m, DISTANCE] += hit * length
            return
        state[m, V] = 0.0  # stopped short of the obstacle, as a body pressed against it is
        state[m, THETA] = theta + w * dt
        if boxes is not None:  # noqa: SIM102 - a test of the argument alone, which numba prunes
            if hl > 0.0 and turn_touches(x0, y0, theta, w * dt, hl, hw, m, world):
                state[m, THETA] = theta
        _timeouts(m, steps, progress, stuck, outcome, max_steps, stuck_steps)
        return
    state[m, X], state[m, Y], state[m, THETA] = x1, y1, theta + w * dt
    state[m, DISTANCE] += length
    if safe - outer >= state[m, CLEARANCE] and safe > outer:
        state[m, SAFE] = safe  # this pose can set no new closest approach
    else:
        # Beyond CLEARANCE + outer the distance cannot set a new closest approach: a cutoff a few
        # steps' drive past it keeps the bound useful and the search short.
        d = distance(x1, y1, m, world, state[m, CLEARANCE] + outer + LOOKOUT * limits[m, MAX_SPEED] * dt)
        state[m, SAFE] = d
        if hl == 0.0:
            state[m, CLEARANCE] = min(state[m, CLEARANCE], max(d - r, 0.0))
        elif boxes is not None:  # noqa: SIM102 - a test of the argument alone, which numba prunes
            if d - outer < state[m, CLEARANCE]:  # (else the box is no nearer than the closest so far)
                heading = theta + w * dt
                state[m, CLEARANCE] = box_distance(x1, y1, heading, hl, hw, m, world, state[m, CLEARANCE])
    if reach <= 1.0:
        outcome[m] = ARRIVED
        return
    to_goal = math.sqrt((goal[m, 0] - x1) ** 2 + (goal[m, 1] - y1) ** 2)
    if to_goal < state[m, BEST] - PROGRESS * limits[m, MAX_SPEED] * dt:
        state[m, BEST] = to_goal
        progress[m] = steps[m]
    _timeouts(m, steps, progress, stuck, outcome, max_steps, stuck_steps)


@njit(cache=True, inline="always")
def _timeouts(m, steps, progress, stuck, outcome, max_steps, stuck_steps):  # pragma: no cover - compiled
    """End robot ``m``'s episode, timed out, after its last step or too long without progress."""
    if steps[m] >= max_steps[m]:
        outcome[m] = TIMEOUT
    elif steps[m] - progress[m] >= stuck_steps[m]:
        outcome[m] = TIMEOUT
        stuck[m] = True
