"""Convex parts of every shape kind, in the unit frame of :mod:`mazegen.spec`.

Every builder returns parts centred on the origin (bounding-box centre) whose
unit bounding box has longest side 1, so an element's size is its longest
extent. Vertices run counter-clockwise. Offsets are zero except for bars, whose
thickness is in arena units and does not scale with the size.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import combinations

from mazegen.spec import Part, Point

# Tolerance for orientation tests on normalised coordinates (extent 1).
_EPS = 1e-12

_UNIT_SQUARE: tuple[Point, ...] = ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))


def rect_parts() -> tuple[Part, ...]:
    """The unit square ``[-0.5, 0.5]²``; width and height scale x and y separately."""
    return (_part(_UNIT_SQUARE),)


def square_parts() -> tuple[Part, ...]:
    """The unit square ``[-0.5, 0.5]²`` (used with a uniform size)."""
    return (_part(_UNIT_SQUARE),)


def triangle_parts() -> tuple[Part, ...]:
    """An equilateral triangle pointing up, width 1, centred on its bounding box."""
    h = math.sqrt(3.0) / 2.0
    return (_part(((-0.5, -h / 2), (0.5, -h / 2), (0.0, h / 2))),)


def regular_polygon_parts(sides: int) -> tuple[Part, ...]:
    """A regular polygon with a horizontal bottom edge.

    Args:
        sides: Number of sides, at least 3.

    Raises:
        ValueError: If ``sides`` is below 3.
    """
    if sides < 3:
        raise ValueError(f"a regular polygon needs at least 3 sides, got {sides}")
    start = -math.pi / 2 - math.pi / sides
    ring = [
        (math.cos(start + 2 * math.pi * k / sides), math.sin(start + 2 * math.pi * k / sides))
        for k in range(sides)
    ]
    return (_part(_normalise(ring)),)


def polygon_parts(points: Sequence[Point]) -> tuple[Part, ...]:
    """An arbitrary simple polygon, split into convex parts when it is not convex.

    The points may be in any units and either orientation; a repeated closing
    point is ignored. A non-convex polygon is ear-clipped and the triangles are
    merged back into larger convex pieces where possible (Hertel–Mehlhorn).

    Args:
        points: The polygon's vertices in order.

    Raises:
        ValueError: For fewer than 3 distinct points, zero area or crossing edges.
    """
    ring: list[Point] = []
    for x, y in points:
        p = (float(x), float(y))
        if not ring or p != ring[-1]:
            ring.append(p)
    while len(ring) > 1 and ring[0] == ring[-1]:
        ring.pop()
    if len(set(ring)) < 3:
        raise ValueError("a polygon needs at least 3 distinct points")
    ring = _normalise(ring)
    far = max(ring, key=lambda p: (p[0] - ring[0][0]) ** 2 + (p[1] - ring[0][1]) ** 2)
    if all(abs(_cross(ring[0], far, p)) <= _EPS for p in ring):
        raise ValueError("polygon has zero area (all points on one line)")
    if _self_intersects(ring):
        raise ValueError("polygon edges cross or touch each other")
    if _signed_area(ring) < 0:
        ring.reverse()
    ring = [ring[i] for i in _drop_straight(ring, list(range(len(ring))))]
    if _is_convex(ring, list(range(len(ring)))):
        return (_part(ring),)
    pieces = _merge_convex(ring, _ear_clip(ring))
    return tuple(_part([ring[i] for i in piece]) for piece in pieces)


def bar_parts(segments: Sequence[tuple[Point, Point]], thickness: float) -> tuple[Part, ...]:
    """A figure drawn as thick line segments (angle, square, E or L shape…).

    All endpoints are normalised together (bounding box centred, longest side
    1). Each segment becomes a rectangle part: its corners are the unit endpoint
    plus the absolute offset ``±n·t/2 ± d·t/2`` (``n`` the unit normal, ``d`` the
    unit direction, ``t`` the thickness), so caps are square and the bars of a
    corner join. The offsets follow the unit direction, so bars must be used
    with uniform scaling (``sx == sy``).

    Args:
        segments: Segments as ``((x0, y0), (x1, y1))`` in any units.
        thickness: Bar thickness in arena units.

    Raises:
        ValueError: For no segments, a zero-length segment or a thickness <= 0.
    """
    if not thickness > 0:
        raise ValueError(f"bar thickness must be positive, got {thickness}")
    if not segments:
        raise ValueError("a bar figure needs at least one segment")
    ends = [(float(x), float(y)) for segment in segments for x, y in segment]
    if any(ends[i] == ends[i + 1] for i in range(0, len(ends), 2)):
        raise ValueError("a bar segment has zero length")
    unit = _normalise(ends)
    half = thickness / 2.0
    parts = []
    for (px, py), (qx, qy) in zip(unit[::2], unit[1::2], strict=True):
        length = math.hypot(qx - px, qy - py)
        dx, dy = (qx - px) / length * half, (qy - py) / length * half
        nx, ny = -dy, dx
        parts.append(
            Part(
                unit=((px, py), (qx, qy), (qx, qy), (px, py)),
                offset=((-nx - dx, -ny - dy), (-nx + dx, -ny + dy), (nx + dx, ny + dy), (nx - dx, ny - dy)),
            )
        )
    return tuple(parts)


def _part(ring: Sequence[Point]) -> Part:
    return Part(tuple((float(x), float(y)) for x, y in ring), ((0.0, 0.0),) * len(ring))


def _normalise(points: Sequence[Point]) -> list[Point]:
    """Centre the bounding box on the origin and scale its longest side to 1."""
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    span = max(max(xs) - min(xs), max(ys) - min(ys))
    cx, cy = (max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2
    return [((x - cx) / span, (y - cy) / span) for x, y in points]


def _cross(o: Point, a: Point, b: Point) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _signed_area(ring: Sequence[Point]) -> float:
    return 0.5 * sum(_cross((0.0, 0.0), ring[i - 1], ring[i]) for i in range(len(ring)))


def _on_segment(p: Point, q: Point, r: Point) -> bool:
    """True if ``r``, known to be collinear with ``pq``, lies within its bounding box."""
    return (
        min(p[0], q[0]) - _EPS <= r[0] <= max(p[0], q[0]) + _EPS
        and min(p[1], q[1]) - _EPS <= r[1] <= max(p[1], q[1]) + _EPS
    )


def _segments_meet(p: Point, q: Point, r: Point, s: Point) -> bool:
    d1, d2 = _cross(r, s, p), _cross(r, s, q)
    d3, d4 = _cross(p, q, r), _cross(p, q, s)
    if ((d1 > _EPS and d2 < -_EPS) or (d1 < -_EPS and d2 > _EPS)) and (
        (d3 > _EPS and d4 < -_EPS) or (d3 < -_EPS and d4 > _EPS)
    ):
        return True
    return (
        (abs(d1) <= _EPS and _on_segment(r, s, p))
        or (abs(d2) <= _EPS and _on_segment(r, s, q))
        or (abs(d3) <= _EPS and _on_segment(p, q, r))
        or (abs(d4) <= _EPS and _on_segment(p, q, s))
    )


def _self_intersects(ring: Sequence[Point]) -> bool:
    n = len(ring)
    for i in range(n):
        a, b, c = ring[i - 1], ring[i], ring[(i + 1) % n]
        # Adjacent edges only meet at their shared vertex unless the ring doubles back.
        back = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) < 0
        if abs(_cross(a, b, c)) <= _EPS and back:
            return True
    for i, j in combinations(range(n), 2):
        if (
            j - i > 1
            and not (i == 0 and j == n - 1)
            and _segments_meet(ring[i], ring[i + 1], ring[j], ring[(j + 1) % n])
        ):
            return True
    return False


def _drop_straight(ring: Sequence[Point], idx: list[int]) -> list[int]:
    """Remove vertices where the boundary goes straight on (they add no corner)."""
    changed = True
    while changed and len(idx) > 3:
        changed = False
        for k in range(len(idx)):
            if abs(_cross(ring[idx[k - 1]], ring[idx[k]], ring[idx[(k + 1) % len(idx)]])) <= _EPS:
                del idx[k]
                changed = True
                break
    return idx


def _is_convex(ring: Sequence[Point], idx: Sequence[int]) -> bool:
    n = len(idx)
    return all(_cross(ring[idx[k - 1]], ring[idx[k]], ring[idx[(k + 1) % n]]) > _EPS for k in range(n))


def _in_triangle(p: Point, a: Point, b: Point, c: Point) -> bool:
    """True if ``p`` is inside or on the counter-clockwise triangle ``abc``."""
    return _cross(a, b, p) >= -_EPS and _cross(b, c, p) >= -_EPS and _cross(c, a, p) >= -_EPS


def _ear_clip(ring: Sequence[Point]) -> list[list[int]]:
    """Triangulate a simple counter-clockwise ring; triangles are vertex indices."""
    idx = list(range(len(ring)))
    triangles = []
    while len(idx) > 3:
        m = len(idx)
        for k in range(m):
            a, b, c = idx[k - 1], idx[k], idx[(k + 1) % m]
            turn = _cross(ring[a], ring[b], ring[c])
            if abs(turn) <= _EPS:  # a straight vertex left by an earlier clip
                del idx[k]
                break
            if turn > 0 and not any(
                _in_triangle(ring[p], ring[a], ring[b], ring[c]) for p in idx if p not in (a, b, c)
            ):
                triangles.append([a, b, c])
                del idx[k]
                break
        else:
            raise ValueError("polygon could not be split into convex parts")
    if abs(_cross(*(ring[i] for i in idx))) > _EPS:
        triangles.append(idx)
    return triangles


def _merge_convex(ring: Sequence[Point], pieces: list[list[int]]) -> list[list[int]]:
    """Greedily join pieces that share an edge while the union stays convex."""
    merged = True
    while merged:
        merged = False
        for i, j in combinations(range(len(pieces)), 2):
            joined = _join(ring, pieces[i], pieces[j])
            if joined is not None:
                pieces[i] = joined
                del pieces[j]
                merged = True
                break
    return pieces


def _join(ring: Sequence[Point], p: list[int], q: list[int]) -> list[int] | None:
    q_edges = {(q[m], q[(m + 1) % len(q)]): m for m in range(len(q))}
    for k in range(len(p)):
        a, b = p[k], p[(k + 1) % len(p)]
        m = q_edges.get((b, a))
        if m is not None:
            # p walked from b round to a, then q's vertices strictly between a and b.
            q_from_a = q[m + 1 :] + q[: m + 1]
            joined = _drop_straight(ring, p[k + 1 :] + p[: k + 1] + q_from_a[1:-1])
            return joined if _is_convex(ring, joined) else None
    return None
