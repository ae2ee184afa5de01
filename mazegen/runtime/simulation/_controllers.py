"""The bundled controllers simcore owns: ``straight`` and ``purepursuit``, one robot per call.

Every per-robot controller kernel has the one signature the episode loop dispatches on
(:mod:`mazegen.runtime.simulation._loop`)::

    NAME_command(params, limits, pose, goal, nav, clear, grid, path, scan, angles, memory, out)

``params`` are the controller's parameters in the order of its row of :mod:`mazegen.controllers`
(lengths in arena units), ``limits`` the robot's (in :data:`mazegen.controllers.LIMITS` order),
``pose`` ``(x, y, theta, v, w)``, ``goal`` ``(gx, gy)``; ``nav``, ``clear`` and ``grid`` are the
navigation and clearance fields, ``path`` MazeGen's path corners, ``scan`` and ``angles`` the
lidar, ``memory`` the controller's own state carried from step to step (a row per robot, zeroed
when its episode begins; only ``movebase`` keeps any); the command ``(v, w)`` goes to ``out``.
The loop clamps it to the robot's limits and acceleration window afterwards.
"""

from __future__ import annotations

import math

from numba import njit

from mazegen.runtime.compiling import wrapped_leaf_kernel

# Positions in the limits array and in each controller's parameters: literals, which numba compiles
# in as constants (a kernel's cache is keyed on the runtime's sources alone), in the order of
# mazegen/controllers.py's LIMITS and rows; tests/runtime/simulation/test_registry.py checks them.
MAX_SPEED, MIN_SPEED, MAX_TURN, ACCEL, TURN_ACCEL, STEP, RADIUS, GOAL_TOLERANCE, LENGTH, WIDTH = range(10)
HEADING_GAIN, TURN_IN_PLACE = range(2)
"""straight's parameters."""
LOOKAHEAD, MIN_LOOKAHEAD, MAX_LOOKAHEAD, LOOKAHEAD_TIME = range(4)
MIN_RADIUS, ROTATE_TO_HEADING, REGULATED_MIN_SPEED = range(4, 7)
"""purepursuit's parameters (its path_margin is read by the drive, not the kernel)."""


@njit(cache=True, inline="always")
def wrap(angle):  # pragma: no cover - compiled
    """``angle`` in ``[-pi, pi)``."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


@wrapped_leaf_kernel
def straight_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, memory, out
):  # pragma: no cover
    """Turn toward the goal (proportional gain ``heading_gain``) and drive at top speed; turn on the
    spot while the heading error exceeds ``turn_in_place``."""
    error = wrap(math.atan2(goal[1] - pose[1], goal[0] - pose[0]) - pose[2])
    out[0] = 0.0 if abs(error) > params[TURN_IN_PLACE] else limits[MAX_SPEED]
    out[1] = params[HEADING_GAIN] * error


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


@wrapped_leaf_kernel
def purepursuit_command(
    params, limits, pose, goal, nav, clear, grid, path, scan, angles, memory, out
):  # pragma: no cover
    """nav2's regulated pure pursuit along MazeGen's path."""
    x, y, theta = pose[0], pose[1], pose[2]
    # nav2's velocity-scaled lookahead, or its fixed lookahead_dist when lookahead_time is 0
    reach = params[LOOKAHEAD]
    if params[LOOKAHEAD_TIME] > 0.0:
        reach = min(max(abs(pose[3]) * params[LOOKAHEAD_TIME], params[MIN_LOOKAHEAD]), params[MAX_LOOKAHEAD])
    cx, cy = carrot(path, x, y, reach) if path.shape[0] else (goal[0], goal[1])
    c, s = math.cos(theta), math.sin(theta)
    lx = c * (cx - x) + s * (cy - y)
    ly = c * (cy - y) - s * (cx - x)
    d2 = lx * lx + ly * ly
    if lx < math.cos(params[ROTATE_TO_HEADING]) * math.sqrt(d2):  # the carrot's bearing exceeds it
        out[0] = 0.0
        out[1] = math.copysign(limits[MAX_TURN], ly)
        return
    curvature = 2.0 * ly / d2 if d2 > 0.0 else 0.0
    speed = limits[MAX_SPEED]
    if curvature != 0.0 and 1.0 / abs(curvature) < params[MIN_RADIUS]:  # regulate: slow down in tight turns
        slowest = min(params[REGULATED_MIN_SPEED], speed)
        speed = max(speed * (1.0 / abs(curvature)) / params[MIN_RADIUS], slowest)
    out[0] = speed
    out[1] = speed * curvature
