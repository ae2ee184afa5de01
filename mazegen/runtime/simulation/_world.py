"""The world the robots drive in: every convex part of the driven floors, in world coordinates.

The parts of all driven floors are flattened into one array, floor after floor, so a robot's
kernel reads ``parts first[m] .. first[m + 1]`` of its floor ``m`` and nothing else. Vertices come
from :func:`mazegen.runtime.geometry.elements.world_vertices`, the transform every other kernel
uses, so the simulator collides with exactly the shapes the metrics and drawings see. Each part
carries its bounding box: the collision, distance and lidar kernels cull on it before any exact
test. The arena's four walls are the lines ``x = 0``, ``x = width``, ``y = 0``, ``y = height``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mazegen.runtime.engine.population import Population
from mazegen.runtime.geometry.elements import world_vertices


@dataclass(frozen=True)
class World:
    """The convex parts of M driven floors, flattened.

    Attributes:
        first: ``int64[M + 1]``: floor ``m``'s parts are ``first[m]`` to ``first[m + 1]`` (exclusive).
        vertices: ``float64[P, V, 2]``: each part's vertices, counter-clockwise, padded past ``count``.
        count: ``int64[P]``: vertices of each part.
        box: ``float64[P, 4]``: each part's ``(xmin, ymin, xmax, ymax)``.
        size: ``float64[2]``: the arena's width and height (its walls).
    """

    first: np.ndarray
    vertices: np.ndarray
    count: np.ndarray
    box: np.ndarray
    size: np.ndarray

    @property
    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(first, vertices, count, box, size)``: what the compiled kernels read."""
        return self.first, self.vertices, self.count, self.box, self.size

    def parts(self, floor: int) -> list[np.ndarray]:
        """The parts of driven floor ``floor``, one ``float64[n, 2]`` array each (to test or draw)."""
        return [self.vertices[p, : self.count[p]] for p in range(self.first[floor], self.first[floor + 1])]


def world_of(population: Population, indices: np.ndarray) -> World:
    """The parts of individuals ``indices`` of ``population``, in that order."""
    table = population.table
    rows = np.asarray(indices, np.int64)
    n_el = np.asarray(population.n_elements, np.int64)[rows]
    used = np.arange(population.element_ids.shape[1]) < n_el[:, None]
    ids = np.asarray(population.element_ids, np.int64)[rows][used]
    params = np.asarray(population.params, np.float64)[rows][used]
    placed = world_vertices(table, ids, params)  # [elements, P, V, 2]
    has_part = np.arange(table.n_parts.max(initial=1)) < table.n_parts[ids][:, None]
    vertices = np.ascontiguousarray(placed[has_part])
    count = table.n_vertices[ids][has_part].astype(np.int64)
    parts_per_floor = np.zeros(len(rows), np.int64)
    np.add.at(parts_per_floor, np.repeat(np.arange(len(rows)), n_el), table.n_parts[ids])
    first = np.concatenate(([0], np.cumsum(parts_per_floor))).astype(np.int64)
    real = (np.arange(vertices.shape[1]) < count[:, None])[..., None]
    low = np.where(real, vertices, np.inf).min(axis=1, initial=np.inf)
    high = np.where(real, vertices, -np.inf).max(axis=1, initial=-np.inf)
    box = np.ascontiguousarray(np.concatenate((low, high), axis=1).reshape(-1, 4))
    arena = population.arena
    return World(first, vertices, count, box, np.array([arena.width, arena.height], np.float64))
