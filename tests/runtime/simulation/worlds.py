"""Hand-made and random worlds of convex parts for the collision and lidar tests, with their shapely
outlines as the plain reference."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon, box

from mazegen.runtime.simulation._world import World

SIZE = (400.0, 300.0)


def world(parts: list[np.ndarray], size: tuple[float, float] = SIZE) -> World:
    """One floor holding ``parts`` (counter-clockwise vertex arrays)."""
    most = max((len(p) for p in parts), default=3)
    vertices = np.zeros((len(parts), most, 2))
    for q, part in enumerate(parts):
        vertices[q, : len(part)] = part
    count = np.array([len(p) for p in parts], np.int64)
    boxes = np.array([[*p.min(axis=0), *p.max(axis=0)] for p in parts]).reshape(-1, 4)
    return World(np.array([0, len(parts)], np.int64), vertices, count, boxes, np.array([size], np.float64))


def random_parts(rng: np.random.Generator, count: int, size: tuple[float, float] = SIZE) -> list[np.ndarray]:
    """Convex hulls of a few random points each, some of them thin slivers."""
    parts = []
    for _ in range(count):
        centre = rng.uniform((0, 0), size)
        spread = rng.uniform(2, 60, 2) * (rng.uniform(0.02, 0.2) if rng.random() < 0.2 else 1.0)
        points = centre + rng.uniform(-1, 1, (rng.integers(3, 9), 2)) * spread
        hull = shapely.convex_hull(shapely.MultiPoint(points))
        if hull.geom_type != "Polygon":
            continue
        ring = np.array(hull.exterior.coords)[:-1]
        if shapely.LinearRing(ring).is_ccw is False:
            ring = ring[::-1]
        parts.append(ring)
    return parts


def outline(parts: list[np.ndarray]):
    """The union of the parts, as shapely."""
    return shapely.union_all([Polygon(p) for p in parts]) if parts else Polygon()


def walls(size: tuple[float, float] = SIZE):
    """The arena's boundary as a shapely line: its walls."""
    return box(0, 0, *size).exterior


def reference_range(obstacles, x: float, y: float, angle: float, reach: float, size=SIZE) -> float:
    """Distance along the ray to the first part or wall it meets, at most ``reach``."""
    ray = LineString([(x, y), (x + reach * math.cos(angle), y + reach * math.sin(angle))])
    edges = walls(size) if obstacles.is_empty else shapely.union(obstacles.boundary, walls(size))
    met = ray.intersection(edges)
    pieces = [piece for piece in getattr(met, "geoms", [met]) if not piece.is_empty]
    return min((Point(x, y).distance(piece) for piece in pieces), default=reach)
