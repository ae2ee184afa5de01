"""The bundled controllers simcore owns: ``straight`` and ``purepursuit``, one robot per call.

Every per-robot controller kernel has the one signature the episode loop dispatches on
(:mod:`mazegen.runtime.simulation._loop`)::

    NAME_command(params, limits, pose, goal, nav, clear, grid, path, scan, angles, out)

``params`` are the controller's parameters in :mod:`mazegen.controllers` order (lengths in arena
units), ``limits`` the robot's (see :data:`LIMITS`), ``pose`` ``(x, y, theta, v, w)``, ``goal``
``(gx, gy)``; ``nav``, ``clear`` and ``grid`` are the navigation and clearance fields, ``path``
MazeGen's path corners, ``scan`` and ``angles`` the lidar; the command ``(v, w)`` goes to ``out``.
The loop clamps it to the robot's limits and acceleration window afterwards.
"""

from __future__ import annotations

import math

from numba import njit

LIMITS = ("max_speed", "min_speed", "max_turn", "accel", "turn_accel", "step", "radius", "goal_tolerance")
"""The order of the ``limits`` array every controller kernel reads."""
MAX_SPEED, MIN_SPEED, MAX_TURN, ACCEL, TURN_ACCEL, STEP, RADIUS, GOAL_TOLERANCE = range(8)


@njit(cache=True, inline="always")
def wrap(angle):  # pragma: no cover - compiled
    """``angle`` in ``[-pi, pi)``."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@njit(cache=True)
def straight_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, out
):  # pragma: no cover
    """Turn toward the goal (proportional gain ``params[0]``) and drive at top speed; turn on the
    spot while the heading error exceeds ``params[1]``."""
    error = wrap(math.atan2(goal[1] - pose[1], goal[0] - pose[0]) - pose[2])
    out[0] = 0.0 if abs(error) > params[1] else limits[MAX_SPEED]
    out[1] = params[0] * error


@njit(cache=True, inline="always")
def _closest(path, x, y):  # pragma: no cover - compiled
    """Segment index and fraction of the point of polyline ``path`` nearest ``(x, y)``."""
    best = math.inf
    segment = 0
    fraction = 0.0
    for s in range(path.shape[0] - 1):
        ax, ay = path[s, 0], path[s, 1]
        ex, ey = path[s + 1, 0] - ax, path[s + 1, 1] - ay
        den = ex * ex + ey * ey
        u = 0.0 if den == 0.0 else min(max(((x - ax) * ex + (y - ay) * ey) / den, 0.0), 1.0)
        gx, gy = ax + u * ex - x, ay + u * ey - y
        d = gx * gx + gy * gy
        if d < best:
            best, segment, fraction = d, s, u
    return segment, fraction


@njit(cache=True, inline="always")
def carrot(path, x, y, reach):  # pragma: no cover - compiled
    """The lookahead point: walking ``path`` on from its point nearest ``(x, y)``, the first point
    ``reach`` away from ``(x, y)``; the path's end when all of it is nearer."""
    n = path.shape[0]
    if n == 0:
        return x, y
    segment, fraction = _closest(path, x, y)
    for s in range(segment, n - 1):
        u0 = fraction if s == segment else 0.0
        ax, ay = path[s, 0], path[s, 1]
        ex, ey = path[s + 1, 0] - ax, path[s + 1, 1] - ay
        bx, by = path[s + 1, 0] - x, path[s + 1, 1] - y
        if bx * bx + by * by < reach * reach:
            continue
        # The far root u of |a + u·e - p| = reach on [u0, 1]: the segment leaves the circle there.
        fx, fy = ax - x, ay - y
        a = ex * ex + ey * ey
        b = fx * ex + fy * ey
        c = fx * fx + fy * fy - reach * reach
        root = math.sqrt(max(b * b - a * c, 0.0))
        u = max(u0, (-b + root) / a) if a > 0.0 else 1.0
        return ax + u * ex, ay + u * ey
    return path[n - 1, 0], path[n - 1, 1]


@njit(cache=True)
def purepursuit_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, out
):  # pragma: no cover
    """nav2's regulated pure pursuit along MazeGen's path.

    ``params``: lookahead, min_lookahead, max_lookahead, lookahead_time, min_radius,
    rotate_to_heading, regulated_min_speed (see :mod:`mazegen.controllers`).
    """
    x, y, theta = pose[0], pose[1], pose[2]
    # nav2's velocity-scaled lookahead, or its fixed lookahead_dist when lookahead_time is 0
    reach = min(max(abs(pose[3]) * params[3], params[1]), params[2]) if params[3] > 0.0 else params[0]
    cx, cy = carrot(path, x, y, reach) if path.shape[0] else (goal[0], goal[1])
    c, s = math.cos(theta), math.sin(theta)
    lx = c * (cx - x) + s * (cy - y)
    ly = c * (cy - y) - s * (cx - x)
    d2 = lx * lx + ly * ly
    if lx < math.cos(params[5]) * math.sqrt(d2):  # the carrot's bearing exceeds it: rotate to heading
        out[0] = 0.0
        out[1] = math.copysign(limits[MAX_TURN], ly)
        return
    curvature = 2.0 * ly / d2 if d2 > 0.0 else 0.0
    speed = limits[MAX_SPEED]
    if curvature != 0.0 and 1.0 / abs(curvature) < params[4]:  # regulate: slow down in tight turns
        speed = max(speed * (1.0 / abs(curvature)) / params[4], min(params[6], speed))
    out[0] = speed
    out[1] = speed * curvature
