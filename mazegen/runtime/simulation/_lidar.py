"""The 2D lidar: beams cast exactly against a floor's part edges and the arena walls.

Beam ``k`` leaves the robot's centre at ``heading + angles[k]`` and reads the distance to the
first part edge or wall it meets, or ``lidar_range`` when it meets none within that range. The
parts whose boxes lie within range are gathered once per scan (into a scratch list); each is then
tested by the beams of its angular span only (a convex part seen from outside spans less than a
half turn), each beam culling it by its box before testing its edges. No raster is involved: the
ranges are exact up to floating point, and the same whatever order the parts are tested in.
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


ANGULAR_MARGIN = 1e-6
"""Radians a part's angular span is widened by before its beams are found: a beam farther outside
cannot meet it, whatever the rounding of the angles."""


@njit(cache=True)
def scan(x, y, theta, angles, reach, floor, world, near, out):  # pragma: no cover - compiled
    """Write the ranges of beams ``angles`` (relative to ``theta``, ascending) from ``(x, y)`` to ``out``.

    ``near`` is scratch of at least the floor's number of parts. Each beam first reads the walls; then
    each part within range is tested by the beams of its angular span only (its vertices' bearings, a
    span under a half turn from outside a convex part), each beam culled by the part's box before its
    edges are. The nearest crossing is kept, whatever order the parts come in.
    """
    first, vertices, count, box, size = world
    n_near = 0
    for q in range(first[floor], first[floor + 1]):
        gx = max(box[q, 0] - x, 0.0, x - box[q, 2])
        gy = max(box[q, 1] - y, 0.0, y - box[q, 3])
        if gx * gx + gy * gy <= reach * reach:
            near[n_near] = q
            n_near += 1
    beams = np.empty((angles.shape[0], 2))  # each beam's direction, found once
    for k in range(angles.shape[0]):
        dx = math.cos(theta + angles[k])
        dy = math.sin(theta + angles[k])
        beams[k, 0], beams[k, 1] = dx, dy
        best = min(_wall_range(x, dx, size[floor, 0], reach), _wall_range(y, dy, size[floor, 1], reach))
        out[k] = max(best, 0.0)
    for i in range(n_near):
        q = near[i]
        n = count[q]
        centre = math.atan2(vertices[q, 0, 1] - y, vertices[q, 0, 0] - x)
        low, high = 0.0, 0.0
        for v in range(1, n):
            bearing = math.atan2(vertices[q, v, 1] - y, vertices[q, v, 0] - x) - centre
            bearing = (bearing + math.pi) % (2.0 * math.pi) - math.pi
            low, high = min(low, bearing), max(high, bearing)
        if high - low >= math.pi - ANGULAR_MARGIN:  # not seen from outside: every beam may meet it
            _part_beams(x, y, beams, q, vertices, n, box, 0, angles.shape[0], out)
            continue
        relative = (centre - theta + math.pi) % (2.0 * math.pi) - math.pi  # the span's first bearing
        for turn in range(-1, 2):
            a = relative + low - ANGULAR_MARGIN + turn * 2.0 * math.pi
            b = relative + high + ANGULAR_MARGIN + turn * 2.0 * math.pi
            k0 = _first_not_below(angles, a)
            k1 = _first_above(angles, b)
            if k0 < k1:
                _part_beams(x, y, beams, q, vertices, n, box, k0, k1, out)


@njit(cache=True, inline="always")
def _first_not_below(ascending, value):  # pragma: no cover - compiled
    """``np.searchsorted(ascending, value, side="left")``, written out: numba's compiles for a second."""
    lo, hi = 0, ascending.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if ascending[mid] < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True, inline="always")
def _first_above(ascending, value):  # pragma: no cover - compiled
    """``np.searchsorted(ascending, value, side="right")``, likewise."""
    lo, hi = 0, ascending.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if ascending[mid] <= value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True, inline="always")
def _part_beams(x, y, beams, q, vertices, n, box, k0, k1, out):  # pragma: no cover - compiled
    """Shorten the ranges of beams ``k0`` to ``k1 - 1`` (directions ``beams``) where they cross part ``q``
    (``n`` vertices) nearer."""
    for k in range(k0, k1):
        dx, dy = beams[k, 0], beams[k, 1]
        best = out[k]
        if not _box_reach(x, y, dx, dy, box[q], best):
            continue
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
