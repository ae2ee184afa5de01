"""The dynamic window approach, as the BARN challenge's baseline runs it (move_base with
``base_local_planner``, ``dwa: true``), one robot per call.

Every control step (the simulation step) the planner samples velocities in the dynamic window
(what the acceleration limits reach within one step), rolls each out at constant velocity over
``horizon`` seconds, and drives the cheapest:

- speeds: ``v_samples`` evenly over the window, ends included; turn rates: 0 (when the window
  holds it, as base_local_planner always tries it first) and ``w_samples - 1`` evenly over the
  window, ends included;
- a rollout is the exact arc, checked at points at most a cell apart (base_local_planner's
  ``sim_granularity``; the clearance field changes by at most that much between them) against
  the clearance field: one that comes within the robot's radius of
  an obstacle (an inflated obstacle) or ends where the navigation function is ``inf`` is
  discarded. When the robot already stands that close (the raster is coarser than the exact
  geometry the simulator collides with), an arc is discarded only where it gets closer still;
- cost = ``path_weight`` × distance from the arc's end to MazeGen's path + ``goal_weight`` ×
  navigation function at the arc's end (both counted in costmap cells of ``resolution``, as
  base_local_planner scores without ``meter_scoring``) + ``obstacle_weight`` × the costmap's
  inflation cost of the closest approach along the arc: ``252 · exp(-gap / decay)`` for an edge
  gap below ``inflation``, else 0 (costmap_2d's inflation layer, ``cost_scaling_factor`` =
  1 / ``decay``);
- equal costs (turning on the spot: every turn rate ends where the robot stands) go to the arc
  whose final heading points down the navigation function, read ``forward`` ahead of its end
  (dwa_local_planner's ``forward_point_distance``: base_local_planner scores such turns by
  heading);
- no admissible sample: stop (base_local_planner backs up at ``escape_vel`` instead; this robot
  does not reverse), and the next step, or the stuck timeout, decides.
"""

from __future__ import annotations

import math

from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.simulation._controllers import (
    ACCEL,
    MAX_SPEED,
    MAX_TURN,
    MIN_SPEED,
    RADIUS,
    STEP,
    TURN_ACCEL,
)

# Parameters, in the order of dwa's row in mazegen/controllers.py (its path_margin is read by the
# drive, not the kernel); tests/runtime/simulation/test_registry.py checks them.
V_SAMPLES, W_SAMPLES, HORIZON, OBSTACLE_WEIGHT, PATH_WEIGHT, GOAL_WEIGHT = range(6)
INFLATION, DECAY, RESOLUTION, FORWARD = range(6, 10)
LETHAL = 252.0
"""costmap_2d's cost just outside the inscribed radius, where the inflation decay starts."""


@wrapped_leaf_kernel
def dwa_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, memory, out
):  # pragma: no cover
    """The cheapest admissible ``(v, w)`` of the dynamic window, written to ``out``.

    The result is the plain minimum over every sample of (cost, tie-break, speed index, turn
    index); the search only skips work that cannot change it: a sample whose end alone (path
    and goal terms, the obstacle term being ≥ 0) already costs more than the best so far is not
    rolled out, and a rollout stops once its obstacle term alone would exceed the best. The
    sample nearest the current velocity goes first, as it is usually good.
    """
    x, y, theta, v_now, w_now = pose[0], pose[1], pose[2], pose[3], pose[4]
    dt, radius = limits[STEP], limits[RADIUS]
    v_lo = max(limits[MIN_SPEED], v_now - limits[ACCEL] * dt)
    v_hi = min(limits[MAX_SPEED], v_now + limits[ACCEL] * dt)
    w_lo = max(-limits[MAX_TURN], w_now - limits[TURN_ACCEL] * dt)
    w_hi = min(limits[MAX_TURN], w_now + limits[TURN_ACCEL] * dt)
    v_lo, w_lo = min(v_lo, v_hi), min(w_lo, w_hi)
    nv, nw = max(int(params[V_SAMPLES]), 1), max(int(params[W_SAMPLES]), 1)
    horizon = params[HORIZON]
    frame = (grid[0], grid[1], 1.0 / grid[2], grid[2])  # x0, y0, cells per unit, cell
    here = _clear_at(clear, frame, x, y)
    # Hit: within the radius; from inside that (a coarse raster), only getting closer still.
    limit = radius if here > radius else here * (1.0 - 1e-9)
    first, last = _near_segments(path, x, y, v_hi * horizon)
    zero = w_lo <= 0.0 <= w_hi and nw > 1
    best = (math.inf, math.inf, nv, nw)
    cos_now, sin_now = math.cos(theta), math.sin(theta)
    still = math.nan  # the cost of standing still, once scored
    out[0], out[1] = 0.0, 0.0
    # The sample nearest the current velocity first, then all (it again, harmlessly).
    i0 = _nearest(v_now, v_lo, v_hi, nv, 0)
    j0 = _nearest(w_now, w_lo, w_hi, nw, 1 if zero else 0)
    for n in range(-1, nw):
        # Row n: every speed at turn rate n; row -1: the sample nearest the current velocity.
        j = j0 if n < 0 else n
        w = _sample(w_lo, w_hi, nw, j, zero)
        end = theta + w * horizon
        cos_end, sin_end = math.cos(end), math.sin(end)
        if abs(w) > 1e-9:  # the arc's end is (x, y) + v · (ax, ay)
            ax, ay = (sin_end - sin_now) / w, (cos_now - cos_end) / w
        else:
            ax, ay = horizon * cos_now, horizon * sin_now
        for i in range(nv) if n >= 0 else range(i0, i0 + 1):
            v = _sample(v_lo, v_hi, nv, i, False)
            ex, ey = x + v * ax, y + v * ay
            if v == 0.0 and not math.isnan(still):
                cost = still  # turning on the spot: every turn rate costs the same (its tie aside)
            else:
                cost = _score(
                    params,
                    x,
                    y,
                    theta,
                    ex,
                    ey,
                    v,
                    w,
                    horizon,
                    limit,
                    radius,
                    nav,
                    clear,
                    frame,
                    path,
                    first,
                    last,
                    best[0],
                )
                if v == 0.0:
                    still = cost  # (over budget stays over: the budget only falls)
            if cost == math.inf:
                continue
            tie = _nav_at(nav, frame, ex + params[FORWARD] * cos_end, ey + params[FORWARD] * sin_end)
            candidate = (cost, tie, i, j)
            if candidate < best:
                best = candidate
                out[0], out[1] = v, w


@njit(cache=True, inline="always")
def _sample(lo, hi, count, k, zero):  # pragma: no cover - compiled
    """Sample ``k`` of ``count`` over ``[lo, hi]``, ends included; with ``zero``, sample 0 is 0 and
    the other ``count - 1`` spread over the window."""
    if zero:
        if k == 0:
            return 0.0
        k -= 1
        count -= 1
    if count == 1:
        return hi if not zero else 0.5 * (lo + hi)
    return lo + (hi - lo) * k / (count - 1)


@njit(cache=True, inline="always")
def _nearest(value, lo, hi, count, offset):  # pragma: no cover - compiled
    """Index of the evenly spread sample nearest ``value`` (after ``offset`` leading samples)."""
    spread = count - offset
    if spread <= 1 or hi <= lo:
        return min(offset, count - 1)
    k = round((value - lo) / (hi - lo) * (spread - 1))
    return offset + min(max(k, 0), spread - 1)


@njit(cache=True, inline="always")
def _score(
    params, x, y, theta, ex, ey, v, w, horizon, limit, radius, nav, clear, frame, path, first, last, budget
):  # pragma: no cover - compiled
    """Cost of the arc ``(v, w)`` from ``(x, y, theta)`` to ``(ex, ey)``: ``inf`` when discarded or
    when it costs more than ``budget``."""
    to_goal = _nav_at(nav, frame, ex, ey)
    if to_goal == math.inf:
        return math.inf
    resolution = params[RESOLUTION]
    ends = params[GOAL_WEIGHT] * to_goal / resolution
    if ends > budget:  # the goal term alone is over budget: skip the path term too
        return math.inf
    ends += params[PATH_WEIGHT] * math.sqrt(_to_path(path, ex, ey, first, last)) / resolution
    if ends > budget:
        return math.inf
    # Clearance at which the obstacle term alone would spend the rest of the budget: stop there.
    weight, decay, inflation = params[OBSTACLE_WEIGHT], params[DECAY], params[INFLATION]
    stop = limit
    if weight > 0.0 and budget < math.inf:
        spare = (budget - ends) / (weight * LETHAL)
        if spare < 1.0:
            # (a hair closer, so that rounding never drops an exact tie)
            stop = max(stop, (radius + min(-decay * math.log(max(spare, 1e-300)), inflation)) * (1.0 - 1e-9))
    # The arc's points at most a cell apart (the clearance field changes by at most as much
    # between them), at times horizon·k/points: each chord turned by half the step's turn from
    # the heading before it.
    points = max(1, math.ceil(v * horizon * frame[2]))
    turn = w * horizon / points
    chord = v * horizon / points if turn == 0.0 else 2.0 * v / w * math.sin(0.5 * turn)
    ux, uy = math.cos(theta + 0.5 * turn), math.sin(theta + 0.5 * turn)
    rc, rs = math.cos(turn), math.sin(turn)
    px, py = x, y
    closest = math.inf
    for _ in range(points):
        px += chord * ux
        py += chord * uy
        ux, uy = ux * rc - uy * rs, ux * rs + uy * rc
        c = _clear_at(clear, frame, px, py)
        if c <= stop and (c <= limit or c < stop):  # a hit, or over budget
            return math.inf
        closest = min(closest, c)
    gap = closest - radius
    obstacle = LETHAL * math.exp(-max(gap, 0.0) / decay) if gap < inflation else 0.0
    return ends + weight * obstacle


@njit(cache=True, inline="always")
def _clear_at(clear, frame, x, y):  # pragma: no cover - compiled
    """The clearance field at ``(x, y)`` (its cell's value), 0 outside the grid; ``frame`` =
    ``(x0, y0, 1 / cell, cell)``."""
    u = (x - frame[0]) * frame[2]
    t = (y - frame[1]) * frame[2]
    if u < 0.0 or t < 0.0:
        return 0.0
    c, r = int(u), int(t)
    if r >= clear.shape[0] or c >= clear.shape[1]:
        return 0.0
    return clear[r, c]


@njit(cache=True, inline="always")
def _nav_at(nav, frame, x, y):  # pragma: no cover - compiled
    """The navigation function at ``(x, y)`` (its cell's value), ``inf`` outside the grid."""
    u = (x - frame[0]) * frame[2]
    t = (y - frame[1]) * frame[2]
    if u < 0.0 or t < 0.0:
        return math.inf
    c, r = int(u), int(t)
    if r >= nav.shape[0] or c >= nav.shape[1]:
        return math.inf
    return float(nav[r, c])


@leaf_kernel
def _near_segments(path, x, y, reach):  # pragma: no cover - compiled
    """``(first, last)``: the span of path segments that may hold the nearest path point of any
    point within ``reach`` of ``(x, y)`` (those within the nearest segment's distance + 2 reach)."""
    n = path.shape[0] - 1
    if n < 1:
        return 0, -1
    nearest = math.sqrt(_to_path(path, x, y, 0, n - 1))
    within = (nearest + 2.0 * reach) ** 2
    first, last = n, -1
    for s in range(n):
        if _to_path(path, x, y, s, s) <= within:
            first, last = min(first, s), max(last, s)
    return first, last


@njit(cache=True, inline="always")
def _to_path(path, x, y, first, last):  # pragma: no cover - compiled
    """Squared distance from ``(x, y)`` to path segments ``first..last`` (0 when there are none)."""
    if last < first:
        return 0.0
    best = math.inf
    for s in range(first, last + 1):
        ax, ay = path[s, 0], path[s, 1]
        ex, ey = path[s + 1, 0] - ax, path[s + 1, 1] - ay
        den = ex * ex + ey * ey
        u = 0.0 if den == 0.0 else min(max(((x - ax) * ex + (y - ay) * ey) / den, 0.0), 1.0)
        dx, dy = ax + u * ex - x, ay + u * ey - y
        best = min(best, dx * dx + dy * dy)
    return best
