"""A fixed set of robots stepped together, each on a level that is swapped when its episode ends:
what a vector environment steps (:mod:`mazegen.gym`).

Slot ``i`` holds one robot and the level it plays (:class:`~mazegen.runtime.simulation._levels.LevelRows`'s
row copied in): its parts in a fixed span of the world's arrays (``capacity`` parts a slot, padding
parts culled by their boxes), its goal, limits, path and step limits. A slot's episode steps through
:func:`~mazegen.runtime.simulation._step.advance`, the step every way of driving shares, so a slot
driven by a bundled controller's commands drives exactly as :func:`drive` does. One compiled call
steps every slot still playing, scores the step and observes what each robot sees next.

The reward of a step (weights in :data:`REWARD_TERMS` order, ``float64[4]``):
``progress · (to_go before − to_go after) · metres per unit − time``, plus ``arrival`` on arriving,
minus ``collision`` on a step that touches an obstacle. ``to_go`` is the length of the shortest way
to the goal that goes straight to a point of the level's path and then follows it (:func:`path_to_go`):
the progress terms of an episode add up to its start's ``to_go`` less its end's, in metres.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.controllers import BUNDLED, LIDAR, LIMITS
from mazegen.errors import MazeError
from mazegen.runtime.compiling import leaf_kernel
from mazegen.runtime.simulation._episodes import ARRIVED, TIMEOUT
from mazegen.runtime.simulation._levels import INERT_BOX, LevelRows
from mazegen.runtime.simulation._loop import command, controller_slots
from mazegen.runtime.simulation._movebase import memory_for
from mazegen.runtime.simulation._policy import look
from mazegen.runtime.simulation._state import ACTIVE, THETA, Robots, V, W, X, Y, boxes_of
from mazegen.runtime.simulation._step import advance, begin
from mazegen.runtime.threads import in_blocks, thread_count, threads

REWARD_TERMS = ("progress", "arrival", "collision", "time")
"""The reward's weights, in the order the step kernel reads them."""
PROGRESS, ARRIVAL, COLLISION_COST, TIME_COST = range(4)

PARALLEL_WORK = 512
"""Robot steps (a lidar beam a quarter of one) a step of every slot must hold to be spread over threads:
waking a second thread costs more than it saves below (256 robots without a lidar: 540 k steps/s on
one thread, 424 k on two; 1,024: 0.89 M and 1.25 M)."""

_FIELDS = (np.full((1, 1), np.inf, np.float32), np.zeros((1, 1), np.float32), np.zeros(5))
"""The fields a controller reading none is handed: one 1×1 dummy."""


class Slots:
    """``n`` robots, each playing the level last loaded into its slot (none at first: every slot
    starts ended, a timeout of 0 steps).

    Attributes:
        angles: ``float64[beams]`` the lidar's beam angles relative to the heading (none: no lidar).
        robots: What the episodes write, a row per slot (:class:`~mazegen.runtime.simulation._state.Robots`).
        ranges: ``float64[n, beams]`` each robot's last scan.
        to_goal: ``float64[n, 3]`` the goal in each robot's frame: distance, cosine and sine of its bearing.
        reward: ``float64[n]`` each slot's reward at the last step (0 for a slot that did not step).
        waypoint: Metres ahead along the level's path of the waypoint observed (0: none observed).
        to_waypoint: ``float64[n, 3]`` (no rows without a waypoint) the waypoint in each robot's frame,
            as ``to_goal`` (:func:`path_waypoint`).
    """

    def __init__(self, n: int, angles: np.ndarray, *, waypoint: float = 0.0) -> None:
        self.n = n
        self.waypoint = float(waypoint)
        self.to_waypoint = np.zeros((n if waypoint else 0, 3))
        self.angles = np.ascontiguousarray(angles, np.float64)
        self.robots = Robots.new(n, None)
        self.robots.outcome[:] = TIMEOUT
        self.ranges = np.zeros((n, len(self.angles)))
        self.to_goal = np.zeros((n, 3))
        self.reward = np.zeros(n)
        self.to_go = np.zeros(n)
        self.levels = LevelRows(  # what each slot plays: nothing yet, one padding part each
            parts=np.zeros((n, 1, 3, 2)), count=np.zeros((n, 1), np.int64),
            box=np.tile(INERT_BOX, (n, 1, 1)), size=np.ones((n, 2)), start=np.zeros((n, 3)),
            goal=np.zeros((n, 2)), limits=np.ones((n, len(LIMITS))), path=np.zeros((n, 1, 2)),
            path_count=np.zeros(n, np.int64), optimal_time=np.full(n, np.nan),
            max_steps=np.zeros(n, np.int32), stuck_steps=np.ones(n, np.int64),
            carry_on=np.zeros(n, np.bool_), reach=np.zeros(n), scale=np.ones(n),
        )  # fmt: skip
        self._world: tuple = ()
        self._ours: tuple = ()
        self._given: tuple = (
            None,
            (),
        )  # the levels last loaded from, and their arrays as the kernel takes them
        self._rebuild_world()

    @property
    def capacity(self) -> int:
        """Parts a slot holds."""
        return self.levels.count.shape[1]

    @property
    def velocity(self) -> np.ndarray:
        """``float64[n, 2]`` each robot's speed and turn rate."""
        return self.robots.state[:, V : W + 1].copy()  # (adjacent columns: a slice, not a gather)

    @property
    def pose(self) -> np.ndarray:
        """``float64[n, 3]`` each robot's ``(x, y, theta)``."""
        return self.robots.state[:, [X, Y, THETA]]

    def load(self, slots: np.ndarray, levels: LevelRows, rows: np.ndarray | None = None) -> None:
        """Put level ``rows[k]`` of ``levels`` (default level ``k``) into slot ``slots[k]``, its robot at
        the level's start, and observe it (a start touching an obstacle ends the episode as a collision
        after 0 steps)."""
        slots = np.asarray(slots, np.int64)
        rows = np.arange(len(slots), dtype=np.int64) if rows is None else np.asarray(rows, np.int64)
        if any(a > b for a, b in zip(_shapes(levels), _shapes(self.levels))):  # room for its parts and path
            self.levels = LevelRows.joined([self.levels, levels.take(np.zeros(0, np.int64))])
            self._rebuild_world()
        if levels is not self._given[0]:  # a pool loads from one set of levels again and again
            ours = self.levels.arrays.values()
            given = (np.ascontiguousarray(a, b.dtype) for a, b in zip(levels.arrays.values(), ours))
            self._given = (levels, tuple(given))
        _load_slots(
            slots, rows, self._given[1], self._ours, self._world, self.robots.arrays, self.to_go, self.reward,
            self.angles, self.capacity, self.ranges, self.to_goal, self.waypoint, self.to_waypoint,
            boxes_of(levels.limits),
        )  # fmt: skip

    def step(self, actions: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """Step every slot still playing by its row of ``actions`` (``(v, w)``), score the step with
        ``weights`` (:data:`REWARD_TERMS`) and observe every slot; returns the rewards (a slot whose
        episode had ended gets 0 and does not move)."""
        work = self.n * (1 + len(self.angles) // 4)  # a beam costs about a quarter of a step
        with threads(thread_count() if work >= PARALLEL_WORK else 1):
            in_blocks(
                _step_slots, self.n, np.ascontiguousarray(actions, np.float64), self._world, self._episode,
                self.robots.arrays, self.levels.path, self.levels.path_count, self.levels.scale, self.to_go,
                np.ascontiguousarray(weights, np.float64), self.angles, self.levels.reach, self.capacity,
                self.reward, self.ranges, self.to_goal, self.waypoint, self.to_waypoint,
                boxes_of(self.levels.limits), per_thread=2,
            )  # fmt: skip
        return self.reward

    def commands(self, controller: str) -> np.ndarray:
        """``float64[n, 2]``: the command bundled ``controller`` (its default parameters, in each level's
        unit) gives each robot now, from its pose, goal and last scan. Only controllers that read
        neither MazeGen's path nor fields are offered (``straight``, and ``vfh`` with a lidar): nothing
        builds those per slot.

        Raises:
            MazeError: for another controller.
        """
        row = BUNDLED.get(controller)
        if row is None or not row.reads <= {LIDAR} or (LIDAR in row.reads and not len(self.angles)):
            offered = " or ".join(name for name, r in BUNDLED.items() if r.reads <= {LIDAR})
            raise MazeError(
                f"commands come from {offered} (one reading the lidar needs beams), not {controller!r}"
            )
        defaults = np.array([p.default for p in row.parameters])
        scaled = np.array([p.scaled for p in row.parameters])
        params = np.where(scaled, defaults / self.levels.scale[:, None], defaults)
        out = np.zeros((self.n, 2))
        in_blocks(
            _commands, self.n, *controller_slots(row.code, params), params, self.levels.limits,
            self.robots.state, self.levels.goal, self.levels.path, self.levels.path_count, _FIELDS,
            self.ranges, self.angles, out,
        )  # fmt: skip
        return out

    def playing(self) -> bool:
        """Whether any slot's episode still runs."""
        return bool((self.robots.outcome == ACTIVE).any())

    @property
    def _episode(self) -> tuple:
        levels = self.levels
        return levels.limits, levels.goal, levels.max_steps, levels.stuck_steps, levels.carry_on

    def _rebuild_world(self) -> None:
        """The world's flat arrays as views of the slots' padded parts."""
        levels = self.levels
        n, p = levels.count.shape
        first = np.arange(n + 1, dtype=np.int64) * p
        vertices = levels.parts.reshape(n * p, *levels.parts.shape[2:])
        self._world = (first, vertices, levels.count.reshape(-1), levels.box.reshape(n * p, 4), levels.size)
        self._ours = tuple(levels.arrays.values())


def _shapes(levels: LevelRows) -> tuple[int, int, int]:
    """Parts, vertices per part and path corners a row of ``levels`` holds."""
    return levels.parts.shape[1], levels.parts.shape[2], levels.path.shape[1]


@njit(cache=True)
def _load_slots(
    slots, rows, given, ours, world, robots, to_go, reward, angles, capacity, ranges, to_goal, waypoint,
    to_waypoint, boxes,
):  # fmt: skip  # pragma: no cover - compiled
    """Copy level ``rows[j]`` of ``given`` (:class:`LevelRows`' arrays in field order) into slot
    ``slots[j]`` of ``ours`` (padding what it leaves of the slot's parts, vertices and path), put the
    slot's robot at its start, measure its way to go and observe it."""
    parts, count, box, size, start, goal, limits, path, path_count = ours[:9]
    optimal_time, max_steps, stuck_steps, carry_on, reach, scale = ours[9:]
    state, outcome, steps, progress, stuck, contacts = robots
    near = np.empty(capacity, np.int64)
    for j in range(slots.shape[0]):
        m, k = slots[j], rows[j]
        for p in range(parts.shape[1]):
            real = p < given[0].shape[1]
            count[m, p] = given[1][k, p] if real else 0
            for c in range(4):
                box[m, p, c] = given[2][k, p, c] if real else INERT_BOX[c]
            for v in range(parts.shape[2]):
                inside = real and v < given[0].shape[2]
                parts[m, p, v, 0] = given[0][k, p, v, 0] if inside else 0.0
                parts[m, p, v, 1] = given[0][k, p, v, 1] if inside else 0.0
        for c in range(path.shape[1]):
            inside = c < given[7].shape[1]
            path[m, c, 0] = given[7][k, c, 0] if inside else 0.0
            path[m, c, 1] = given[7][k, c, 1] if inside else 0.0
        _copy_row(given[3], k, size, m)
        _copy_row(given[4], k, start, m)
        _copy_row(given[5], k, goal, m)
        _copy_row(given[6], k, limits, m)
        path_count[m], optimal_time[m], max_steps[m] = given[8][k], given[9][k], given[10][k]
        stuck_steps[m], carry_on[m], reach[m], scale[m] = (
            given[11][k],
            given[12][k],
            given[13][k],
            given[14][k],
        )
        steps[m] = progress[m] = contacts[m] = 0
        stuck[m] = False
        outcome[m] = ACTIVE
        reward[m] = 0.0
        begin(m, start[m, 0], start[m, 1], start[m, 2], limits[m], goal[m], world, state, outcome, boxes)
        to_go[m] = path_to_go(state[m, X], state[m, Y], path[m], path_count[m], goal[m])
        look(m, m, state, goal, angles, reach, world, near, ranges, to_goal)
        if to_waypoint.shape[0]:
            path_waypoint(state[m], path[m], path_count[m], goal[m], waypoint / scale[m], to_waypoint[m])


@leaf_kernel
def _copy_row(source, k, target, m):  # pragma: no cover - compiled
    for c in range(target.shape[1]):
        target[m, c] = source[k, c]


@njit(cache=True, nogil=True)
def _step_slots(
    first, last, actions, world, episode, robots, path, path_count, scale, to_go, weights, angles, reach,
    capacity, reward, ranges, to_goal, waypoint, to_waypoint, boxes,
):  # fmt: skip  # pragma: no cover - compiled
    state, outcome, contacts = robots[0], robots[1], robots[5]
    goal = episode[1]
    near = np.empty(capacity, np.int64)
    for m in range(first, last):
        r = 0.0
        if outcome[m] == ACTIVE:
            touched = contacts[m]
            advance(m, actions[m, 0], actions[m, 1], world, episode, robots, boxes)
            d = path_to_go(state[m, X], state[m, Y], path[m], path_count[m], goal[m])
            r = weights[PROGRESS] * (to_go[m] - d) * scale[m] - weights[TIME_COST]
            to_go[m] = d
            if outcome[m] == ARRIVED:
                r += weights[ARRIVAL]
            elif contacts[m] > touched:
                r -= weights[COLLISION_COST]
        reward[m] = r
        look(m, m, state, goal, angles, reach, world, near, ranges, to_goal)
        if to_waypoint.shape[0]:
            path_waypoint(state[m], path[m], path_count[m], goal[m], waypoint / scale[m], to_waypoint[m])


@njit(cache=True, nogil=True)
def _commands(
    first, last, straight, purepursuit, dwa, vfh, movebase, params, limits, state, goal, path, path_count,
    fields, ranges, angles, out,
):  # fmt: skip  # pragma: no cover - compiled
    nav, clear, grid = fields
    pose = np.zeros(5)
    memory = memory_for(movebase)
    command_out = np.zeros(2)
    for m in range(first, last):
        for k in range(5):
            pose[k] = state[m, X + k]
        command(
            straight, purepursuit, dwa, vfh, movebase, params[m], limits[m], pose, goal[m], nav, clear, grid,
            path[m, : path_count[m]], ranges[m], angles, memory, command_out,
        )  # fmt: skip
        out[m, 0], out[m, 1] = command_out[0], command_out[1]


@leaf_kernel
def path_waypoint(pose, path, count, goal, ahead, out):  # pragma: no cover - compiled
    """The point of the path (``count`` corners, start to goal) ``ahead`` beyond its point nearest the
    robot at ``pose`` (the goal where the path ends sooner, or without a path), written to ``out`` in
    the robot's frame: its distance, and the cosine and sine of its bearing."""
    x, y = pose[X], pose[Y]
    px, py = goal[0], goal[1]
    if count >= 2:
        nearest, k_near, t_near = math.inf, 0, 0.0
        for k in range(count - 1):
            ex, ey = path[k + 1, 0] - path[k, 0], path[k + 1, 1] - path[k, 1]
            length2 = ex * ex + ey * ey
            t = (
                0.0
                if length2 == 0.0
                else min(max(((x - path[k, 0]) * ex + (y - path[k, 1]) * ey) / length2, 0.0), 1.0)
            )
            d = math.hypot(path[k, 0] + t * ex - x, path[k, 1] + t * ey - y)
            if d < nearest:
                nearest, k_near, t_near = d, k, t
        ax = path[k_near, 0] + t_near * (path[k_near + 1, 0] - path[k_near, 0])
        ay = path[k_near, 1] + t_near * (path[k_near + 1, 1] - path[k_near, 1])
        left = ahead
        px, py = path[count - 1, 0], path[count - 1, 1]
        for k in range(k_near, count - 1):
            bx, by = path[k + 1, 0], path[k + 1, 1]
            length = math.hypot(bx - ax, by - ay)
            if length > 0.0 and length >= left:
                px, py = ax + (bx - ax) * left / length, ay + (by - ay) * left / length
                break
            left -= length
            ax, ay = bx, by
    bearing = math.atan2(py - y, px - x) - pose[THETA]
    out[0] = math.hypot(px - x, py - y)
    out[1] = math.cos(bearing)
    out[2] = math.sin(bearing)


@leaf_kernel
def path_to_go(x, y, path, count, goal):  # pragma: no cover - compiled
    """The length of the shortest way from ``(x, y)`` to the goal that goes straight to a point of the
    path (``count`` corners, start to goal) and follows it from there; straight to ``goal`` without
    a path."""
    if count < 2:
        return math.hypot(goal[0] - x, goal[1] - y)
    best = math.hypot(path[count - 1, 0] - x, path[count - 1, 1] - y)
    after = 0.0  # the path's length from corner k + 1 to its end
    for k in range(count - 2, -1, -1):
        ax, ay, bx, by = path[k, 0], path[k, 1], path[k + 1, 0], path[k + 1, 1]
        ex, ey = bx - ax, by - ay
        length = math.sqrt(ex * ex + ey * ey)  # sqrt, not hypot: no overflow to guard against here
        t = 0.0
        if length > 0.0:
            t = min(max(((x - ax) * ex + (y - ay) * ey) / (length * length), 0.0), 1.0)
        qx, qy = ax + t * ex, ay + t * ey
        best = min(best, math.sqrt((x - qx) * (x - qx) + (y - qy) * (y - qy)) + (1.0 - t) * length + after)
        after += length
    return best
