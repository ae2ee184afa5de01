"""Exact collision and clearance of a box robot against a floor's convex parts and walls.

A box robot (a robot block's ``footprint``) is a ``length`` x ``width`` rectangle centred on the
robot's centre, its length along the heading. A step (forward Euler, :mod:`._step`) first moves the
box along the heading it starts with, ``p0 → p1``, then turns it on the spot at ``p1`` by ``w · dt``:

- **The move.** Two convex polygons touch exactly when their projections overlap on every axis
  normal to an edge of either (the separating axis theorem). Moving the box by ``t · d`` slides its
  projections by ``t`` times the axis's share of ``d``, so the box first touches a part at the
  latest of the times the projections begin to overlap, if that comes before the earliest of the
  times they part again. Touching, distance 0, counts.
- **The turn.** A box turning from clear to touching first touches where a corner of the box meets
  an edge of the part, or a vertex of the part meets an edge of the box. So it touches exactly when
  a corner's arc about the centre crosses an edge of the part, or the arc of one of the part's
  vertices, seen from the box as it turns, crosses an edge of the box.

The arena's walls are four more edges, and its corners four more vertices. Bounding boxes cull the
parts first, and no grid takes part. The parts are read as :mod:`._collide` reads them.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mazegen.runtime.compiling import leaf_kernel, wrapped_leaf_kernel
from mazegen.runtime.simulation._collide import NO_HIT, segment_distance2, slab, wall_entry


@njit(cache=True, inline="always")
def _corner(hl, hw, k):  # pragma: no cover - compiled
    """Corner ``k`` of the box in its own frame, counter-clockwise from the rear right."""
    return (hl if k == 1 or k == 2 else -hl), (hw if k >= 2 else -hw)


@njit(cache=True, inline="always")
def _placed(x, y, c, s, fx, fy):  # pragma: no cover - compiled
    """The point ``(fx, fy)`` of the box's frame placed at ``(x, y)`` heading ``(c, s)``."""
    return x + fx * c - fy * s, y + fx * s + fy * c


@njit(cache=True, inline="always")
def _part_span(vertices, n, ax, ay):  # pragma: no cover - compiled
    """The part's projection on the axis ``(ax, ay)``."""
    lo, hi = np.inf, -np.inf
    for j in range(n):
        p = vertices[j, 0] * ax + vertices[j, 1] * ay
        lo, hi = min(lo, p), max(hi, p)
    return lo, hi


@leaf_kernel
def _part_entry(x, y, c, s, hl, hw, dx, dy, vertices, n, enter, leave):  # pragma: no cover - compiled
    """First ``t`` in ``[enter, leave]`` at which the box moved by ``t · (dx, dy)`` touches the convex
    part, else ``NO_HIT``."""
    for k in range(2 + n):
        if k < 2:  # the box's own axes, along and across the heading
            ax, ay = (c, s) if k == 0 else (-s, c)
            centre, half = x * ax + y * ay, hl if k == 0 else hw
            lo, hi = centre - half, centre + half
        else:  # the normal of one of the part's edges
            j = k - 2
            q = j + 1 if j + 1 < n else 0
            ax, ay = vertices[q, 1] - vertices[j, 1], vertices[j, 0] - vertices[q, 0]
            centre = x * ax + y * ay
            half = hl * abs(c * ax + s * ay) + hw * abs(c * ay - s * ax)
            lo, hi = centre - half, centre + half
        part_lo, part_hi = _part_span(vertices, n, ax, ay)
        # [lo, hi] slid by t · (d · axis) overlaps the part's projection (touching included) where
        # t · (d · axis) lies within [part_lo - hi, part_hi - lo].
        enter, leave = slab(0.0, dx * ax + dy * ay, part_lo - hi, part_hi - lo, enter, leave)
        if enter > leave:
            return NO_HIT
    return enter


@njit(cache=True, inline="always")
def _extent(c, s, hl, hw):  # pragma: no cover - compiled
    """The box's half extents along x and y."""
    return hl * abs(c) + hw * abs(s), hl * abs(s) + hw * abs(c)


@njit(cache=True, inline="always")
def _arc_crosses(cx, cy, radius, start, turn, ax, ay, bx, by):  # pragma: no cover - compiled
    """Whether the arc of ``radius`` about ``(cx, cy)``, from angle ``start`` turning by ``turn``,
    meets the segment ``ab``."""
    ex, ey = bx - ax, by - ay
    fx, fy = ax - cx, ay - cy
    a = ex * ex + ey * ey
    if a == 0.0:
        return False
    b = fx * ex + fy * ey
    disc = b * b - a * (fx * fx + fy * fy - radius * radius)
    if disc < 0.0:
        return False
    root = math.sqrt(disc)
    for t in ((-b - root) / a, (-b + root) / a):
        if 0.0 <= t <= 1.0:
            angle = math.atan2(fy + t * ey, fx + t * ex)
            if turn >= 0.0:
                if (angle - start) % (2.0 * math.pi) <= turn:
                    return True
            elif (start - angle) % (2.0 * math.pi) <= -turn:
                return True
    return False


@leaf_kernel
def _corners_cross(x, y, theta, turn, hl, hw, ax, ay, bx, by):  # pragma: no cover - compiled
    """Whether a corner of the box turning on the spot crosses the segment ``ab``."""
    radius = math.hypot(hl, hw)
    for k in range(4):
        fx, fy = _corner(hl, hw, k)
        if _arc_crosses(x, y, radius, theta + math.atan2(fy, fx), turn, ax, ay, bx, by):
            return True
    return False


@leaf_kernel
def _vertex_crosses(x, y, theta, turn, hl, hw, vx, vy):  # pragma: no cover - compiled
    """Whether the point ``(vx, vy)`` crosses an edge of the box turning on the spot: seen from the
    box, the point turns by ``-turn`` about its centre."""
    radius = math.hypot(vx - x, vy - y)
    if radius > math.hypot(hl, hw):
        return False
    start = math.atan2(vy - y, vx - x) - theta
    for k in range(4):
        ax, ay = _corner(hl, hw, k)
        bx, by = _corner(hl, hw, (k + 1) % 4)
        if _arc_crosses(0.0, 0.0, radius, start, -turn, ax, ay, bx, by):
            return True
    return False


@wrapped_leaf_kernel
def turn_touches(x, y, theta, turn, hl, hw, floor, world):  # pragma: no cover - compiled
    """Whether the box at ``(x, y)`` heading ``theta`` touches a part or wall of driven floor
    ``floor`` while it turns on the spot by ``turn`` (clear where it starts)."""
    if turn == 0.0:
        return False
    first, vertices, count, box, size = world
    width, height = size[floor, 0], size[floor, 1]
    for k in range(4):  # the walls, and the arena's corners
        ax, ay = (width if k == 1 or k == 2 else 0.0), (height if k >= 2 else 0.0)
        bx, by = (width if k == 0 or k == 1 else 0.0), (height if k == 1 or k == 2 else 0.0)
        if _corners_cross(x, y, theta, turn, hl, hw, ax, ay, bx, by):
            return True
        if _vertex_crosses(x, y, theta, turn, hl, hw, ax, ay):
            return True
    reach = math.hypot(hl, hw)
    for q in range(first[floor], first[floor + 1]):
        if box[q, 0] > x + reach or box[q, 2] < x - reach or box[q, 1] > y + reach or box[q, 3] < y - reach:
            continue
        n = count[q]
        for j in range(n):
            i = j + 1 if j + 1 < n else 0
            ax, ay, bx, by = vertices[q, j, 0], vertices[q, j, 1], vertices[q, i, 0], vertices[q, i, 1]
            if _corners_cross(x, y, theta, turn, hl, hw, ax, ay, bx, by):
                return True
            if _vertex_crosses(x, y, theta, turn, hl, hw, ax, ay):
                return True
    return False


@wrapped_leaf_kernel
def box_sweep(x, y, theta, dx, dy, turn, hl, hw, floor, world):  # pragma: no cover - compiled
    """First fraction ``t`` of the move ``(dx, dy)`` from ``(x, y)`` at which the box heading
    ``theta`` touches a part or wall of driven floor ``floor``; 1 when it touches only as it then
    turns by ``turn`` at the move's end; ``NO_HIT`` if it never does."""
    first, vertices, count, box, size = world
    c, s = math.cos(theta), math.sin(theta)
    ex, ey = _extent(c, s, hl, hw)
    best = min(wall_entry(x, dx, ex, size[floor, 0]), wall_entry(y, dy, ey, size[floor, 1]))
    xmin, xmax = min(x, x + dx) - ex, max(x, x + dx) + ex
    ymin, ymax = min(y, y + dy) - ey, max(y, y + dy) + ey
    for q in range(first[floor], first[floor + 1]):
        if box[q, 0] > xmax or box[q, 2] < xmin or box[q, 1] > ymax or box[q, 3] < ymin:
            continue
        best = min(best, _part_entry(x, y, c, s, hl, hw, dx, dy, vertices[q], count[q], 0.0, 1.0))
        if best == 0.0:
            return best
    if best <= 1.0:
        return best
    return 1.0 if turn_touches(x + dx, y + dy, theta, turn, hl, hw, floor, world) else NO_HIT


@leaf_kernel
def _part_distance(x, y, c, s, hl, hw, vertices, n):  # pragma: no cover - compiled
    """Distance from the box to the convex part (0 where they overlap or touch)."""
    if _part_entry(x, y, c, s, hl, hw, 0.0, 0.0, vertices, n, 0.0, 0.0) == 0.0:
        return 0.0
    best = np.inf
    for k in range(4):  # the box's corners to the part's edges, the part's vertices to the box's edges
        fx, fy = _corner(hl, hw, k)
        gx, gy = _corner(hl, hw, (k + 1) % 4)
        px, py = _placed(x, y, c, s, fx, fy)
        qx, qy = _placed(x, y, c, s, gx, gy)
        for j in range(n):
            i = j + 1 if j + 1 < n else 0
            ax, ay, bx, by = vertices[j, 0], vertices[j, 1], vertices[i, 0], vertices[i, 1]
            best = min(best, segment_distance2(px, py, ax, ay, bx, by))
            best = min(best, segment_distance2(ax, ay, px, py, qx, qy))
    return math.sqrt(best)


@wrapped_leaf_kernel
def box_distance(x, y, theta, hl, hw, floor, world, cutoff):  # pragma: no cover - compiled
    """Distance from the box at ``(x, y)`` heading ``theta`` to the nearest part or wall of driven
    floor ``floor`` (0 touching or overlapping), or ``cutoff`` when that is nearer."""
    first, vertices, count, box, size = world
    c, s = math.cos(theta), math.sin(theta)
    ex, ey = _extent(c, s, hl, hw)
    walls = min(x - ex, size[floor, 0] - x - ex, y - ey, size[floor, 1] - y - ey)
    best = min(max(walls, 0.0), cutoff)
    for q in range(first[floor], first[floor + 1]):
        gx = max(box[q, 0] - x - ex, 0.0, x - ex - box[q, 2])
        gy = max(box[q, 1] - y - ey, 0.0, y - ey - box[q, 3])
        if gx * gx + gy * gy < best * best:  # the bounding boxes are nearer than the best so far
            best = min(best, _part_distance(x, y, c, s, hl, hw, vertices[q], count[q]))
    return best
