"""Exact collision and clearance of a disc robot against a floor's convex parts and walls.

A step moves the robot's centre along a straight segment ``p0 → p1`` (forward Euler), so the
disc sweeps a capsule. The robot collides when the capsule touches a part or a wall: some point
of the segment lies at distance ``≤ radius`` from it (touching, distance equal to the radius,
counts as a collision). :func:`sweep` returns the first such point's fraction ``t`` of the
segment, found in closed form: the segment enters the radius-``r`` neighbourhood of a convex part
where it enters the capsule of one of the part's edges (a disc at each vertex and a slab along
each edge), or at ``t = 0`` when it starts inside the part. A thin wall cannot be stepped
through: the whole segment is tested, not its ends. Bounding boxes cull parts first; no grid
takes part in the verdict.

All functions are compiled (numba) and allocate nothing; they read a floor's parts as
``first, vertices, count, box, size`` (:class:`mazegen.runtime.simulation._world.World`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel

NO_HIT = np.inf
"""What :func:`sweep` returns when the segment touches nothing."""


@njit(cache=True, inline="always")
def slab(q0, qd, lo, hi, enter, leave):  # pragma: no cover - compiled
    """Narrow ``[enter, leave]`` to the ``t`` where ``lo ≤ q0 + t·qd ≤ hi``."""
    if qd == 0.0:
        if q0 < lo or q0 > hi:
            return 1.0, 0.0  # empty
        return enter, leave
    a = (lo - q0) / qd
    b = (hi - q0) / qd
    if a > b:
        a, b = b, a
    return max(enter, a), min(leave, b)


@njit(cache=True, inline="always")
def disc_entry(px, py, dx, dy, cx, cy, r):  # pragma: no cover - compiled
    """First ``t`` in ``[0, 1]`` where ``p + t·d`` is within ``r`` of ``c``, else ``NO_HIT``."""
    fx = px - cx
    fy = py - cy
    c = fx * fx + fy * fy - r * r
    if c <= 0.0:
        return 0.0
    a = dx * dx + dy * dy
    b = fx * dx + fy * dy
    if a == 0.0 or b >= 0.0:  # not moving, or moving away
        return NO_HIT
    disc = b * b - a * c
    if disc < 0.0:
        return NO_HIT
    t = (-b - math.sqrt(disc)) / a
    return t if t <= 1.0 else NO_HIT


@njit(cache=True, inline="always")
def _edge_slab_entry(px, py, dx, dy, ax, ay, bx, by, r):  # pragma: no cover - compiled
    """First ``t`` in ``[0, 1]`` where ``p + t·d`` is within ``r`` of segment ``ab`` through its side
    (the slab over the edge; the discs at its ends are tested separately), else ``NO_HIT``."""
    ex = bx - ax
    ey = by - ay
    length = math.sqrt(ex * ex + ey * ey)
    if length == 0.0:
        return NO_HIT
    ux = ex / length
    uy = ey / length
    fx = px - ax
    fy = py - ay
    enter, leave = slab(ux * fx + uy * fy, ux * dx + uy * dy, 0.0, length, 0.0, 1.0)
    enter, leave = slab(ux * fy - uy * fx, ux * dy - uy * dx, -r, r, enter, leave)
    return enter if enter <= leave else NO_HIT


@njit(cache=True, inline="always")
def _edge(vertices, n, k, px, py):  # pragma: no cover - compiled
    """Edge ``k`` of a counter-clockwise part, ``(ax, ay, bx, by)``, and whether ``p`` is on its
    inner side (or on it): ``p`` is inside the part when it is for every edge."""
    ax, ay = vertices[k, 0], vertices[k, 1]
    j = k + 1 if k + 1 < n else 0
    bx, by = vertices[j, 0], vertices[j, 1]
    return ax, ay, bx, by, (bx - ax) * (py - ay) - (by - ay) * (px - ax) >= 0.0


@leaf_kernel
def part_entry(px, py, dx, dy, vertices, n, r):  # pragma: no cover - compiled
    """First ``t`` in ``[0, 1]`` where ``p + t·d`` is within ``r`` of the convex part (``n``
    counter-clockwise ``vertices``), else ``NO_HIT``."""
    best = NO_HIT
    inside = True
    for k in range(n):
        ax, ay, bx, by, left = _edge(vertices, n, k, px, py)
        inside = inside and left
        best = min(best, disc_entry(px, py, dx, dy, ax, ay, r))
        best = min(best, _edge_slab_entry(px, py, dx, dy, ax, ay, bx, by, r))
    return 0.0 if inside else best


@njit(cache=True, inline="always")
def wall_entry(q, qd, r, far):  # pragma: no cover - compiled
    """First ``t`` in ``[0, 1]`` where ``q + t·qd`` is within ``r`` of 0 or of ``far``."""
    if q <= r or q >= far - r:
        return 0.0
    if qd < 0.0:
        t = (r - q) / qd
    elif qd > 0.0:
        t = (far - r - q) / qd
    else:
        return NO_HIT
    return t if t <= 1.0 else NO_HIT


@njit(cache=True, inline="always")
def segment_distance2(px, py, ax, ay, bx, by):  # pragma: no cover - compiled
    """Squared distance from ``p`` to segment ``ab``."""
    ex = bx - ax
    ey = by - ay
    fx = px - ax
    fy = py - ay
    den = ex * ex + ey * ey
    s = 0.0 if den == 0.0 else min(max((fx * ex + fy * ey) / den, 0.0), 1.0)
    gx = fx - s * ex
    gy = fy - s * ey
    return gx * gx + gy * gy


@leaf_kernel
def part_distance(px, py, vertices, n):  # pragma: no cover - compiled
    """Distance from point ``p`` to the convex part (0 inside)."""
    best = np.inf
    inside = True
    for k in range(n):
        ax, ay, bx, by, left = _edge(vertices, n, k, px, py)
        inside = inside and left
        best = min(best, segment_distance2(px, py, ax, ay, bx, by))
    return 0.0 if inside else math.sqrt(best)


@wrapped_leaf_kernel
def distance(px, py, floor, world, cutoff):  # pragma: no cover - compiled
    """Distance from point ``p`` to the nearest part or wall of driven floor ``floor``, or
    ``cutoff`` when that is nearer (parts beyond it are culled by their boxes)."""
    first, vertices, count, box, size = world
    best = min(px, size[floor, 0] - px, py, size[floor, 1] - py, cutoff)
    for q in range(first[floor], first[floor + 1]):
        gx = max(box[q, 0] - px, 0.0, px - box[q, 2])
        gy = max(box[q, 1] - py, 0.0, py - box[q, 3])
        if gx * gx + gy * gy < best * best:  # the box is nearer than the best so far
            best = min(best, part_distance(px, py, vertices[q], count[q]))
    return best


@wrapped_leaf_kernel
def sweep(x0, y0, x1, y1, r, floor, world):  # pragma: no cover - compiled
    """First fraction ``t`` of the segment ``(x0, y0) → (x1, y1)`` at which a disc of radius ``r``
    centred on it touches a part or wall of driven floor ``floor``; ``NO_HIT`` if it never does."""
    first, vertices, count, box, size = world
    dx = x1 - x0
    dy = y1 - y0
    best = min(wall_entry(x0, dx, r, size[floor, 0]), wall_entry(y0, dy, r, size[floor, 1]))
    # The capsule's box: a part whose box misses it cannot be touched.
    xmin = min(x0, x1) - r
    xmax = max(x0, x1) + r
    ymin = min(y0, y1) - r
    ymax = max(y0, y1) + r
    for q in range(first[floor], first[floor + 1]):
        if box[q, 0] > xmax or box[q, 2] < xmin or box[q, 1] > ymax or box[q, 3] < ymin:
            continue
        best = min(best, part_entry(x0, y0, dx, dy, vertices[q], count[q], r))
        if best == 0.0:
            break
    return best
