"""Element types, random populations and their shapely outlines, shared by the geometry tests."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon

from mazegen.dsl.shapes import bar_parts, polygon_parts, rect_parts, regular_polygon_parts, triangle_parts
from mazegen.runtime.geometry._elements import ElementTable, world_parts
from mazegen.spec import ElementType

TYPES = (
    ElementType("box", "rect", rect_parts(), (20, 120), (20, 120)),
    ElementType("tri", "triangle", triangle_parts(), (20, 120)),
    ElementType("hex", "polygon", regular_polygon_parts(6), (20, 120)),
    ElementType(
        "arrow",
        "polygon",
        polygon_parts([(0, 1), (3, 1), (3, 2), (5, 0), (3, -2), (3, -1), (0, -1)]),
        (20, 120),
    ),
    ElementType("ell", "bars", bar_parts([((0, 0), (0, 2)), ((0, 0), (1, 0))], 6.0), (20, 120)),
    ElementType(
        "e",
        "bars",
        bar_parts([((0, 0), (0, 4)), ((0, 0), (3, 0)), ((0, 2), (2, 2)), ((0, 4), (3, 4))], 4.0),
        (20, 120),
    ),
)
SQUARE = (ElementType("square", "square", rect_parts(), (20, 20)),)
TABLE = ElementTable.from_types(TYPES)


def random_population(
    rng: np.random.Generator, n: int, k: int, width: float, height: float, margin: float = 0.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random individuals; rects get two sizes, other types one. Padding is -1 / NaN."""
    n_elements = rng.integers(0, k + 1, n).astype(np.int32)
    used = np.arange(k) < n_elements[:, None]
    ids = np.where(used, rng.integers(0, len(TYPES), (n, k)), -1).astype(np.int32)
    params = np.empty((n, k, 5))
    params[..., 0] = rng.uniform(-margin, width + margin, (n, k))
    params[..., 1] = rng.uniform(-margin, height + margin, (n, k))
    params[..., 2] = rng.uniform(20, 120, (n, k))
    params[..., 3] = np.where(ids == 0, rng.uniform(20, 120, (n, k)), params[..., 2])
    params[..., 4] = rng.uniform(-2 * np.pi, 2 * np.pi, (n, k))
    params[~used] = np.nan  # the kernels must never read padding
    return ids, n_elements, params


def element_geometry(table: ElementTable, element_id: int, row: np.ndarray):
    return shapely.union_all([Polygon(v) for v in world_parts(table, element_id, row)])


def shapely_geometries(table, ids, n_elements, params) -> list[list]:
    return [
        [element_geometry(table, ids[i, k], params[i, k]) for k in range(n_elements[i])]
        for i in range(len(ids))
    ]


def squares(*centres: tuple[float, float], size: float = 20.0):
    k = len(centres)
    params = np.array([[[x, y, size, size, 0.0] for x, y in centres]])
    return np.zeros((1, k), np.int32), np.array([k], np.int32), params
