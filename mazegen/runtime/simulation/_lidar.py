"""The 2D lidar: beams cast exactly against a floor's part edges and the arena walls.

Beam ``k`` leaves the robot's centre at ``heading + angles[k]`` and reads the distance to the
first part edge or wall it meets, or ``lidar_range`` when it meets none within that range. The
parts whose boxes lie within range are gathered once per scan (into a scratch list), so each beam
tests only those: first their boxes, then their edges. No raster is involved: the ranges are
exact up to floating point.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


def beam_angles(beams: int, fov: float) -> np.ndarray:
    """``float64[beams]``: beam angles relative to the heading, spread evenly over ``fov`` centred
    on it (a full circle does not repeat its first beam)."""
    if beams <= 0:
        return np.zeros(0)
    if fov >= 2 * math.pi - 1e-12:
        return -math.pi + (2 * math.pi / beams) * np.arange(beams)
    if beams == 1:
        return np.zeros(1)
    return np.linspace(-fov / 2, fov / 2, beams)


@njit(cache=True, inline="always")
def _wall_range(p, d, far, reach):  # pragma: no cover - compiled
    """Distance along ``p + t·d`` to the wall at 0 or ``far``, or ``reach`` when beyond it."""
    if d > 0.0:
        return min(reach, (far - p) / d)
    if d < 0.0:
        return min(reach, -p / d)
    return reach


@njit(cache=True, inline="always")
def _box_reach(px, py, dx, dy, box, reach):  # pragma: no cover - compiled
    """Whether the beam ``p + t·d``, ``0 ≤ t ≤ reach``, meets the box (slab test)."""
    enter = 0.0
    leave = reach
    for axis in range(2):
        p = px if axis == 0 else py
        d = dx if axis == 0 else dy
        lo = box[axis]
        hi = box[axis + 2]
        if d == 0.0:
            if p < lo or p > hi:
                return False
        else:
            a = (lo - p) / d
            b = (hi - p) / d
            if a > b:
                a, b = b, a
            enter = max(enter, a)
            leave = min(leave, b)
    return enter <= leave


@njit(cache=True)
def scan(x, y, theta, angles, reach, floor, world, near, out):  # pragma: no cover - compiled
    """Write the ranges of beams ``angles`` (relative to ``theta``) from ``(x, y)`` to ``out``.

    ``near`` is scratch of at least the floor's number of parts.
    """
    first, vertices, count, box, size = world
    n_near = 0
    for q in range(first[floor], first[floor + 1]):
        gx = max(box[q, 0] - x, 0.0, x - box[q, 2])
        gy = max(box[q, 1] - y, 0.0, y - box[q, 3])
        if gx * gx + gy * gy <= reach * reach:
            near[n_near] = q
            n_near += 1
    for k in range(angles.shape[0]):
        dx = math.cos(theta + angles[k])
        dy = math.sin(theta + angles[k])
        best = min(_wall_range(x, dx, size[floor, 0], reach), _wall_range(y, dy, size[floor, 1], reach))
        best = max(best, 0.0)
        for i in range(n_near):
            q = near[i]
            if not _box_reach(x, y, dx, dy, box[q], best):
                continue
            n = count[q]
            for v in range(n):
                ax, ay = vertices[q, v, 0], vertices[q, v, 1]
                j = v + 1 if v + 1 < n else 0
                ex = vertices[q, j, 0] - ax
                ey = vertices[q, j, 1] - ay
                den = dx * ey - dy * ex
                if den == 0.0:
                    continue
                fx = ax - x
                fy = ay - y
                t = (fx * ey - fy * ex) / den
                s = (fx * dy - fy * dx) / den
                if 0.0 <= t < best and 0.0 <= s <= 1.0:
                    best = t
        out[k] = best
