"""base_local_planner's trajectories on a costmap: rolling a velocity sample out, checking each pose's
footprint, and scoring it (TrajectoryPlanner::generateTrajectory), for :mod:`._movebase`.

A rollout of ``(vs, ws)`` checks ``max(vs · horizon / granularity, |ws| / angular_granularity)``
poses (rounded, at least 1), ``horizon / n`` apart in time: the robot's own pose first, then each by
forward Euler after the velocity has moved toward the sample by at most the robot's accelerations.
A pose is invalid when it leaves the costmap or its padded rectangular footprint's outline (Bresenham
lines between its corners' cells) crosses an obstacle cell (:data:`OFF`), or when its cell is not
reached by the goal distance (:data:`CUT`: within the inscribed radius of an obstacle, or cut off;
base_local_planner exempts the cells under the robot's footprint from its path distance's obstacles,
not from its goal distance's, so a robot whose own cell is that near an obstacle stands). A valid
rollout costs ``(path_weight · plan distance + goal_weight · goal distance) · resolution +
obstacle_weight · occupancy``, distances in cells at its last pose, the occupancy the costliest cell
under any pose's outline or centre. ``meter_scoring`` multiplies the two distance weights by the
resolution, not the obstacle weight: navigation 1.16 (ROS Melodic, on which BARN's timing runs ran)
dropped the obstacle weight's scaling from TrajectoryPlanner's reconfigure, which sets the weights
the planner scores with (ros-planning/navigation 65d59a47). So ``obstacle_weight`` is a length: the
goal distance one unit of cost weighs as.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.simulation._controllers import ACCEL, TURN_ACCEL
from mazegen.runtime.simulation._costmap import INSCRIBED, cell_cost

# The parameters a rollout reads, in the order of movebase's row in mazegen/controllers.py.
HORIZON, GRANULARITY, ANGULAR_GRANULARITY = 2, 3, 4
PATH_WEIGHT, GOAL_WEIGHT, OBSTACLE_WEIGHT = 8, 9, 10
LENGTH, WIDTH, PADDING, INFLATION, DECAY, RESOLUTION = range(16, 22)
GOAL_DISTANCE, COST = 1, 2
"""The goal distance's and the costmap's layers of ``nav`` (navfn's potential is layer 0)."""
OFF, CUT, OVER = -1.0, -2.0, -3.0
"""A rollout's verdicts other than a cost: a pose off the map or its footprint on an obstacle, a pose
cut off from the goal, and a cost over the budget."""
_EDGE = 1e-6
"""A rollout's end this close (in cells) to a cell's side may fall in either cell."""
OUTLINES = 1024
"""Outlines :func:`pose_cost` remembers (a power of two): a robot's rollouts from one step to the next
trace many of the same."""


@njit(cache=True, inline="always")
def frame_of(params, grid):  # pragma: no cover - compiled
    """``(x0, y0, cell, inscribed, inflation, decay, half length, half width)``."""
    half_length = 0.5 * params[LENGTH] + params[PADDING]
    half_width = 0.5 * params[WIDTH] + params[PADDING]
    inscribed = half_width
    return (
        grid[0],
        grid[1],
        grid[2],
        inscribed,
        params[INFLATION],
        params[DECAY],
        half_length,
        half_width,
    )


@njit(cache=True, inline="always")
def cell_of(frame, clear, x, y):  # pragma: no cover - compiled
    """The costmap cell ``(row, col)`` of ``(x, y)``; ``(-1, -1)`` off the map."""
    u = (x - frame[0]) / frame[2]
    t = (y - frame[1]) / frame[2]
    if u < 0.0 or t < 0.0:
        return -1, -1
    c, r = int(u), int(t)
    if r >= clear.shape[0] or c >= clear.shape[1]:
        return -1, -1
    return r, c


@leaf_kernel
def plan_distance(plan, n_plan, row, col):  # pragma: no cover - compiled
    """Manhattan distance in cells from ``(row, col)`` to the nearest of the plan's kept cells."""
    best = 1 << 62
    for k in range(n_plan):
        best = min(best, abs(plan[k, 0] - row) + abs(plan[k, 1] - col))
    return float(best)


@njit(cache=True, inline="always")
def _ramp(target, now, accel, dt):  # pragma: no cover - compiled
    """base_local_planner's computeNewVelocity: ``now`` moved toward ``target`` by at most ``accel · dt``."""
    return min(target, now + accel * dt) if target >= now else max(target, now - accel * dt)


@njit(cache=True, inline="always")
def _steps(params, vs, ws):  # pragma: no cover - compiled
    """Poses a rollout of ``(vs, ws)`` checks, and the time between them."""
    horizon = params[HORIZON]
    n = int(max(abs(vs) * horizon / params[GRANULARITY], abs(ws) / params[ANGULAR_GRANULARITY]) + 0.5)
    n = max(n, 1)
    return n, horizon / n


@wrapped_leaf_kernel
def bound(params, limits, frame, nav, clear, pose, vs, ws, here):  # pragma: no cover - compiled
    """``(lower bound, row, col)``: a lower bound of the cost of the rollout of ``(vs, ws)`` but for its
    plan distance (``inf`` when it cannot be valid), and the cell of its end (row -1 when rounding
    may put it in the next cell). From its end alone, found by the ramp's poses and then the
    constant-velocity rest in closed form (its goal distance and :func:`least_occupancy`), and the
    occupancy ``here`` of the robot's own pose, its first. Add :func:`plan_term` of the cell for a
    bound of the whole cost."""
    n, dt = _steps(params, vs, ws)
    x, y, theta, v, w = pose[0], pose[1], pose[2], pose[3], pose[4]
    k = 0
    while k < n - 1 and (v != vs or w != ws):
        v = _ramp(vs, v, limits[ACCEL], dt)
        w = _ramp(ws, w, limits[TURN_ACCEL], dt)
        x += v * math.cos(theta) * dt
        y += v * math.sin(theta) * dt
        theta += w * dt
        k += 1
    rest = n - 1 - k  # steps at (vs, ws): x moves by vs·dt·Σ cos(theta + i·a), i < rest
    a = ws * dt
    if rest > 0:
        scale = math.sin(0.5 * rest * a) / math.sin(0.5 * a) if abs(a) > 1e-12 else float(rest)
        middle = theta + 0.5 * (rest - 1) * a
        x += vs * dt * scale * math.cos(middle)
        y += vs * dt * scale * math.sin(middle)
    weight = params[OBSTACLE_WEIGHT]
    u = (x - frame[0]) / frame[2]
    t = (y - frame[1]) / frame[2]
    if min(abs(u - round(u)), abs(t - round(t))) < _EDGE:  # the stepped end may be in the next cell
        return weight * here, -1, -1
    r, c = math.floor(t), math.floor(u)
    if r < 0 or c < 0 or r >= nav.shape[1] or c >= nav.shape[2] or nav[GOAL_DISTANCE, r, c] == math.inf:
        return math.inf, -1, -1
    occupancy = max(here, least_occupancy(frame, clear[r, c]))
    return params[GOAL_WEIGHT] * nav[GOAL_DISTANCE, r, c] * params[RESOLUTION] + weight * occupancy, r, c


@njit(cache=True, inline="always")
def plan_term(params, plan, n_plan, r, c):  # pragma: no cover - compiled
    """The plan distance's part of the cost of a rollout ending in cell ``(r, c)`` (0 for row -1)."""
    return 0.0 if r < 0 else params[PATH_WEIGHT] * plan_distance(plan, n_plan, r, c) * params[RESOLUTION]


@njit(cache=True)
def trajectory(params, limits, pose, vs, ws):  # pragma: no cover - compiled
    """The poses a rollout of ``(vs, ws)`` from ``pose`` checks: ``(float64[n, 4]`` of x, y, cos and sin
    of the heading, the last heading)``."""
    n, dt = _steps(params, vs, ws)
    poses = np.empty((n, 4))
    x, y, v, w = pose[0], pose[1], pose[3], pose[4]
    theta = pose[2]
    cos_t, sin_t = math.cos(theta), math.sin(theta)
    turn_cos, turn_sin = math.cos(ws * dt), math.sin(ws * dt)  # one step's turn at the sample's rate
    for k in range(n):
        if k:
            v = _ramp(vs, v, limits[ACCEL], dt)
            x += v * cos_t * dt
            y += v * sin_t * dt
            if w != ws:  # ramping: the heading by its angle
                w = _ramp(ws, w, limits[TURN_ACCEL], dt)
                theta += w * dt
                cos_t, sin_t = math.cos(theta), math.sin(theta)
            else:  # at the sample's rate: turned by a rotation, no trigonometry a pose
                theta += w * dt
                cos_t, sin_t = cos_t * turn_cos - sin_t * turn_sin, sin_t * turn_cos + cos_t * turn_sin
        poses[k, 0], poses[k, 1], poses[k, 2], poses[k, 3] = x, y, cos_t, sin_t
    return poses, theta


@wrapped_leaf_kernel
def score(
    params, frame, nav, clear, plan, n_plan, poses, here, limit, outlines
):  # pragma: no cover - compiled
    """The cost of the rollout through ``poses`` (:func:`trajectory`'s) when it is valid and costs less
    than ``limit`` (``nextafter(best, inf)`` lets a cost tie the best), else :data:`OFF`, :data:`CUT` or
    :data:`OVER`.

    ``here`` is the occupancy of the robot's own pose, the first of every rollout, when it has been
    checked: a first pass then reads each pose's cell alone (reached? what occupancy must its outline
    have, :func:`least_occupancy`?) and stops a rollout that cannot be valid or within budget, before
    the outlines are traced; the verdict is the same. With ``here`` negative the poses are checked
    once, in time order, and an invalid rollout's verdict is its first invalid pose's.
    """
    n = poses.shape[0]
    weight = params[OBSTACLE_WEIGHT]
    distances = 0.0
    r, c = cell_of(frame, clear, poses[n - 1, 0], poses[n - 1, 1])
    if r >= 0 and nav[GOAL_DISTANCE, r, c] < math.inf:
        distances = params[PATH_WEIGHT] * plan_distance(plan, n_plan, r, c)
        distances = (distances + params[GOAL_WEIGHT] * nav[GOAL_DISTANCE, r, c]) * params[RESOLUTION]
    occupancy = max(here, 0.0)
    if here >= 0.0:
        if r < 0 or nav[GOAL_DISTANCE, r, c] == math.inf:
            return CUT if r >= 0 else OFF
        for k in range(1, n):
            r, c = cell_of(frame, clear, poses[k, 0], poses[k, 1])
            if r < 0:
                return OFF
            if nav[GOAL_DISTANCE, r, c] == math.inf:
                return CUT
            occupancy = max(occupancy, least_occupancy(frame, clear[r, c]))
        if distances + weight * occupancy >= limit:
            return OVER
    for j in range(1 if here >= 0.0 else 0, n + len(PROBES) if here >= 0.0 else n):
        k = j if here < 0.0 else _probe_then_all(j, n)
        cost = pose_cost(frame, clear, nav, poses[k, 0], poses[k, 1], poses[k, 2], poses[k, 3], outlines)
        if cost < 0.0:
            return cost
        occupancy = max(occupancy, cost)
        if distances + weight * occupancy >= limit:
            return OVER
    return distances + weight * occupancy


PROBES = (1.0, 0.5, 0.25, 0.75, 0.125, 0.375, 0.625, 0.875)
"""Where along a rollout within budget after its first pass the first poses traced lie (the last, then
halfway between those traced): a rollout over budget meets its costliest poses early. Then every pose
in time order, where consecutive outlines often lie on the same cells."""


@njit(cache=True, inline="always")
def _probe_then_all(j, n):  # pragma: no cover - compiled
    """The ``j``-th pose to trace (``j`` from 1): the :data:`PROBES`, then ``1 .. n - 1``."""
    if j <= len(PROBES):
        return max(1, int(PROBES[j - 1] * (n - 1) + 0.5))
    return j - len(PROBES)


@njit(cache=True, inline="always")
def least_occupancy(frame, d):  # pragma: no cover - compiled
    """What a pose whose cell is ``d`` from the nearest obstacle cell must cost at least: its centre's
    cost, and its outline's, which passes within the inscribed radius ``b`` of that obstacle cell, or
    within ``d - b`` of it when it lies outside the footprint, give or take a cell's half-diagonal for
    each of two cells."""
    inscribed, inflation, decay, half_cell = frame[3], frame[4], frame[5], 0.5 * math.sqrt(2.0) * frame[2]
    outline = max(d + half_cell - frame[7], frame[7]) + half_cell
    return max(cell_cost(d, inscribed, inflation, decay), cell_cost(outline, inscribed, inflation, decay))


@wrapped_leaf_kernel
def pose_cost(frame, clear, nav, x, y, cos_t, sin_t, outlines):  # pragma: no cover - compiled
    """The occupancy of the pose: the costliest cell of its footprint's outline and its centre; or
    :data:`OFF` (off the map, or the outline on an obstacle cell) or :data:`CUT` (its cell cut off).
    ``outlines`` (:data:`OUTLINES` rows, zeroed for a new floor) remembers outlines traced before by
    their corner cells: an outline between the same four cells costs the same."""
    r, c = cell_of(frame, clear, x, y)
    if r < 0:
        return OFF
    worst = float(nav[COST, r, c])
    half_length, half_width = frame[6], frame[7]
    # Nearer than this to an obstacle cell, an outline cell may cost something.
    if clear[r, c] <= math.hypot(half_length, half_width) + frame[4] + math.sqrt(2.0) * frame[2]:
        # Corners in footprint order (rear right, rear left, front left, front right), as cell numbers.
        k0 = corner_number(frame, clear, x, y, cos_t, sin_t, -half_length, -half_width)
        k1 = corner_number(frame, clear, x, y, cos_t, sin_t, -half_length, half_width)
        k2 = corner_number(frame, clear, x, y, cos_t, sin_t, half_length, half_width)
        k3 = corner_number(frame, clear, x, y, cos_t, sin_t, half_length, -half_width)
        if k0 < 0 or k1 < 0 or k2 < 0 or k3 < 0:
            return OFF
        mixed = ((k0 * 1000003 + k1) * 1000003 + k2) * 1000003 + k3
        row = (mixed ^ (mixed >> 29)) & (outlines.shape[0] - 1)
        if not (  # (the first corner stored plus one: a zeroed row is empty)
            outlines[row, 0] == k0 + 1
            and outlines[row, 1] == k1
            and outlines[row, 2] == k2
            and outlines[row, 3] == k3
        ):
            cost = _outline_cost(nav[COST], clear.shape[1], k0, k1, k2, k3)
            outlines[row, 0], outlines[row, 1], outlines[row, 2], outlines[row, 3] = k0 + 1, k1, k2, k3
            outlines[row, 4] = cost
        if outlines[row, 4] < 0.0:
            return OFF
        worst = max(worst, outlines[row, 4])
    if nav[GOAL_DISTANCE, r, c] == math.inf:
        return CUT
    return worst


@njit(cache=True, inline="always")
def _outline_cost(cost, cols, k0, k1, k2, k3):  # pragma: no cover - compiled
    """The costliest cell of the outline through the cells numbered ``k0 .. k3`` (``row · cols + col``);
    :data:`OFF` on an obstacle cell."""
    worst = 0.0
    for a, b in ((k0, k1), (k1, k2), (k2, k3), (k3, k0)):
        line = line_cost(cost, a // cols, a % cols, b // cols, b % cols)
        if line < 0.0:
            return OFF
        worst = max(worst, line)
    return worst


@njit(cache=True, inline="always")
def corner_number(frame, clear, x, y, cos_t, sin_t, fx, fy):  # pragma: no cover - compiled
    """The cell number (``row · cols + col``) of the footprint point ``(fx, fy)`` (robot frame) of the
    pose; -1 off the map."""
    r, c = cell_of(frame, clear, x + fx * cos_t - fy * sin_t, y + fx * sin_t + fy * cos_t)
    return r * clear.shape[1] + c if r >= 0 else -1


@leaf_kernel
def line_cost(cost, r0, c0, r1, c1):  # pragma: no cover - compiled
    """The costliest cell of the Bresenham line from ``(r0, c0)`` to ``(r1, c1)``; -1 on an obstacle cell."""
    dc, dr = abs(c1 - c0), abs(r1 - r0)
    sc = 1 if c1 >= c0 else -1
    sr = 1 if r1 >= r0 else -1
    along_columns = dc >= dr
    den = dc if along_columns else dr
    add = dr if along_columns else dc
    num = den // 2
    c, r = c0, r0
    worst = 0.0
    for _ in range(den + 1):
        here = cost[r, c]
        if here > INSCRIBED:
            return -1.0
        worst = max(worst, here)
        num += add
        if num >= den:
            num -= den
            if along_columns:
                r += sr
            else:
                c += sc
        if along_columns:
            c += sc
        else:
            r += sr
    return worst
