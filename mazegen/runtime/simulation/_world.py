"""The world the robots drive in: every convex part of the driven floors, in world coordinates.

The parts of all driven floors are flattened into one array, floor after floor, so a robot's
kernel reads ``parts first[m] .. first[m + 1]`` of its floor ``m`` and nothing else. Vertices come
from :func:`mazegen.runtime.geometry._elements.world_element`, the transform every other kernel
(and :func:`~mazegen.runtime.geometry._elements.world_vertices`) uses, so the simulator collides
with exactly the shapes the metrics and drawings see. Each part
carries its bounding box: the collision, distance and lidar kernels cull on it before any exact
test. The arena's four walls are the lines ``x = 0``, ``x = width``, ``y = 0``, ``y = height`` of
each floor's own arena: floors of different arenas drive in one batch (:meth:`World.joined`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit

from mazegen.maps import base_cells, wall_rectangles
from mazegen.runtime.engine import Population
from mazegen.runtime.geometry import world_element
from mazegen.runtime.threads import in_blocks
from mazegen.spec import BaseMap


@dataclass(frozen=True)
class World:
    """The convex parts of M driven floors, flattened.

    Attributes:
        first: ``int64[M + 1]``: floor ``m``'s parts are ``first[m]`` to ``first[m + 1]`` (exclusive).
        vertices: ``float64[P, V, 2]``: each part's vertices, counter-clockwise, padded past ``count``.
        count: ``int64[P]``: vertices of each part.
        box: ``float64[P, 4]``: each part's ``(xmin, ymin, xmax, ymax)``.
        size: ``float64[M, 2]``: each floor's arena width and height (its walls).
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

    def part(self, a: int, b: int) -> World:
        """The world of driven floors ``a`` to ``b - 1``, sharing this one's parts."""
        return World(self.first[a : b + 1], self.vertices, self.count, self.box, self.size[a:b])

    @classmethod
    def joined(cls, worlds: list[World]) -> World:
        """The floors of ``worlds`` one after another, as one world (parts padded to the most vertices)."""
        spans = [slice(int(w.first[0]), int(w.first[-1])) for w in worlds]
        offsets = np.cumsum([0] + [span.stop - span.start for span in spans])
        first = [w.first[1:] - w.first[0] + at for w, at in zip(worlds, offsets)]
        return cls(
            np.concatenate([np.zeros(1, np.int64), *first]).astype(np.int64),
            stacked([w.vertices[span] for w, span in zip(worlds, spans)], 0.0),
            np.concatenate([w.count[span] for w, span in zip(worlds, spans)]),
            np.concatenate([w.box[span] for w, span in zip(worlds, spans)]),
            np.concatenate([w.size for w in worlds]),
        )

    def parts(self, floor: int) -> list[np.ndarray]:
        """The parts of driven floor ``floor``, one ``float64[n, 2]`` array each (to test or draw)."""
        return [self.vertices[p, : self.count[p]] for p in range(self.first[floor], self.first[floor + 1])]


def stacked(arrays: list[np.ndarray], fill: float) -> np.ndarray:
    """``arrays`` one after another along their first axis, each padded with ``fill`` to the largest
    of the others in every other axis (floors of different sizes in one batch)."""
    shape = tuple(max(a.shape[k] for a in arrays) for k in range(1, arrays[0].ndim))
    out = np.full((sum(len(a) for a in arrays), *shape), fill, arrays[0].dtype)
    at = 0
    for a in arrays:
        where = (slice(at, at + len(a)), *(slice(0, n) for n in a.shape[1:]))
        out[where] = a
        at += len(a)
    return out


def world_of(population: Population, indices: np.ndarray) -> World:
    """The parts of individuals ``indices`` of ``population``, in that order: each floor's elements,
    then the walls of its arena's base map (:func:`base_walls`)."""
    table = population.table
    arena = population.arena
    walls = base_walls(arena.base) if arena.base is not None else np.zeros((0, 4))
    rows = np.ascontiguousarray(indices, np.int64)
    n_el = np.asarray(population.n_elements, np.int64)[rows]
    ids = np.asarray(population.element_ids, np.int64)[rows]
    used = np.arange(ids.shape[1]) < n_el[:, None]
    parts_per_floor = np.where(used, table.n_parts[np.maximum(ids, 0)], 0).sum(axis=1) + len(walls)
    first = np.concatenate(([0], np.cumsum(parts_per_floor))).astype(np.int64)
    vertices = np.zeros((first[-1], max(table.unit.shape[2], 4 if len(walls) else 0), 2))
    count = np.zeros(first[-1], np.int64)
    box = np.zeros((first[-1], 4))
    if len(walls):  # the last parts of every floor, the same for all
        at = (first[1:, None] - len(walls) + np.arange(len(walls))).ravel()
        corners = walls[:, [0, 2, 2, 0, 1, 1, 3, 3]].reshape(-1, 2, 4).transpose(0, 2, 1)
        vertices[at, :4] = np.tile(corners, (len(rows), 1, 1))
        count[at] = 4
        box[at] = np.tile(walls, (len(rows), 1))
    if len(rows):
        params = np.ascontiguousarray(population.params, np.float64)
        element_ids = np.ascontiguousarray(population.element_ids, np.int32)
        n_elements = np.ascontiguousarray(population.n_elements, np.int32)
        in_blocks(
            _place,
            len(rows),
            table.shapes,
            element_ids,
            n_elements,
            params,
            rows,
            first,
            vertices,
            count,
            box,
        )
    size = np.tile(np.array([arena.width, arena.height], np.float64), (len(rows), 1))
    return World(first, vertices, count, box, size)


@lru_cache(maxsize=16)
def base_walls(base: BaseMap) -> np.ndarray:
    """``float64[W, 4]``: the base map's blocked cells merged into rectangles ``(xmin, ymin, xmax, ymax)``,
    arena units (:func:`mazegen.maps.wall_rectangles`)."""
    cells = np.array(wall_rectangles(base_cells(base)), dtype=np.float64).reshape(-1, 4)
    walls = np.stack([cells[:, 2], cells[:, 0], cells[:, 3] + 1, cells[:, 1] + 1], axis=1) * base.resolution
    walls.flags.writeable = False
    return walls


@njit(cache=True, nogil=True)
def _place(
    start, stop, shapes, ids, n_el, params, rows, first, vertices, count, box
):  # pragma: no cover - compiled
    """Write the parts of floors ``rows[start:stop]`` from ``first[m]`` on, as every kernel places them
    (:func:`mazegen.runtime.geometry._elements.world_element`)."""
    n_parts, n_vertices, unit = shapes[0], shapes[1], shapes[2]
    placed = np.empty((1, unit.shape[1], unit.shape[2], 2))
    part_box = np.empty((1, unit.shape[1], 4))
    element_box = np.empty((1, 4))
    for m in range(start, stop):
        i = rows[m]
        q = first[m]
        for k in range(n_el[i]):
            e = ids[i, k]
            world_element(shapes, e, params[i, k], placed, part_box, element_box, 0)
            for p in range(n_parts[e]):
                count[q] = n_vertices[e, p]
                for v in range(count[q]):
                    vertices[q, v, 0] = placed[0, p, v, 0]
                    vertices[q, v, 1] = placed[0, p, v, 1]
                for side in range(4):
                    box[q, side] = part_box[0, p, side]
                q += 1
