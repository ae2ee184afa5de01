"""Which floors are the same test: the homotopy classes of a floor's start-to-goal paths.

Two paths from start to goal are in one homotopy class when one can be deformed into the other
without crossing an obstacle: they pass every obstacle on the same side. A class is named by its
**signature**, the side (``L``eft or ``R``ight of the path) of each obstacle group that some class
passes on the other side, the groups in a canonical order (along the start-goal line, then from
left to right). A floor's **canonical class** is the set of its classes' signatures: two floors
with equal ones offer a robot the same choices of route, however different their coordinates.

The classes are found on the configuration space, for the robot's disc (docs/classes.md), by
:mod:`._homotopy`: an A* search over the junctions of the free rectangles and each path's H-signature
(its crossings of a ray from every obstacle group), each class's corridor pulled taut into its shortest
path. Classes
whose shortest path is longer than ``detour`` times the floor's shortest are left out (a robot would
not take them), and at most ``max_classes`` are kept, shortest first.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mazegen.runtime.navigation._homotopy import (
    GOAL_STATES_PER_CLASS,
    LENGTH_TOLERANCE,
    class_scratch,
    floor_classes,
)
from mazegen.runtime.navigation._paths import free_cells
from mazegen.runtime.navigation._sides import narrowest_width, sides
from mazegen.spec import DETOUR, MAX_CLASSES

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population
    from mazegen.runtime.geometry import Grid


@dataclass(frozen=True)
class PathClass:
    """One homotopy class of a floor's start-to-goal paths.

    Attributes:
        signature: The side of each distinguishing obstacle group (``L``, ``R``), in the canonical
            order; empty when the floor has one class.
        length: Its shortest path's length, arena units (8-neighbour grid steps).
        narrowest: The narrowest gap that path passes through, arena units: the least width of free
            floor across it (to a cell, between the obstacles, not the robot's disc).
        path: ``float64[n, 2]``: that path's points, start to goal.
    """

    signature: str
    length: float
    narrowest: float
    path: np.ndarray


@dataclass(frozen=True)
class Topology:
    """The homotopy classes of one floor and task, shortest first (none when no path exists).

    Attributes:
        classes: The classes kept (see :data:`MAX_CLASSES`, :data:`DETOUR`).
        groups: Obstacle groups that tell them apart.
        start: The start, arena units.
        goal: The goal, arena units.
        marks: ``float64[H, 2]``: a point of each obstacle group apart from the arena's edge.
        keys: Each class's side of every one of them (+1 left, -1 right).
        telling: The groups that tell the classes apart (indices into ``marks``), in canonical order.
    """

    classes: tuple[PathClass, ...]
    start: tuple[float, float]
    goal: tuple[float, float]
    marks: np.ndarray
    keys: tuple[tuple[int, ...], ...]
    telling: tuple[int, ...]

    @property
    def groups(self) -> int:
        return len(self.telling)

    @property
    def signature(self) -> str:
        """The canonical class: the number of classes and their sorted signatures, ``"3:LL,LR,RR"``
        (``"1:"`` for one, ``"0:"`` for none). The sides are a path's own: a floor's mirror image
        has every class's letters swapped."""
        return f"{len(self.classes)}:" + ",".join(sorted(c.signature for c in self.classes))

    def class_of(self, points: np.ndarray) -> str | None:
        """The signature of the class of a path from start to goal through ``points`` (``[n, 2]``, arena
        units; start and goal added), or None when it is none of :attr:`classes` (one too long or
        looping)."""
        path = np.concatenate([[self.start], np.asarray(points, np.float64)[:, :2], [self.goal]])
        key = tuple(sides(path, self.marks, np.array(self.start), np.array(self.goal)).tolist())
        return next((c.signature for c, k in zip(self.classes, self.keys) if k == key), None)


def floor_topology(
    pop: Population,
    grid: Grid,
    index: int,
    *,
    free: np.ndarray | None = None,
    max_classes: int = MAX_CLASSES,
    detour: float = DETOUR,
) -> Topology:
    """The homotopy classes of individual ``index`` of ``pop`` from ``grid``'s start to its goal;
    ``free``: its free cells on ``grid``, when already found (one floor's tasks share them)."""
    return topology(
        free_cells(pop, grid, index) if free is None else free,
        cells=(grid.start_cell, grid.goal_cell),
        ends=(grid.start, grid.goal),
        cell=grid.cell,
        radius=pop.arena.robot_radius,
        max_classes=max_classes,
        detour=detour,
    )


def topology(
    free: np.ndarray,
    *,
    cells: tuple[tuple[int, int], tuple[int, int]],
    ends: tuple[tuple[float, float], tuple[float, float]],
    cell: float,
    radius: float,
    max_classes: int = MAX_CLASSES,
    detour: float = DETOUR,
) -> Topology:
    """The homotopy classes of the paths from start to goal on one floor.

    Args:
        free: ``bool[rows, cols]``: configuration-space free cells (row 0 at y = 0).
        cells: The start's and goal's cells, ``(row, col)``.
        ends: The start and goal, arena units.
        cell: The cell size, arena units.
        radius: The robot's radius (gap widths are between the obstacles, not their discs).
        max_classes: Classes kept, at most.
        detour: Longest class kept, as a multiple of the shortest.
    """
    free = np.ascontiguousarray(free, np.bool_)
    rows, cols = free.shape
    scratch = class_scratch(rows, cols, max_classes)
    walks = GOAL_STATES_PER_CLASS * max_classes
    lengths, keys = np.empty(walks), np.empty(walks, np.uint64)  # written for the classes found
    paths, turns = np.empty((walks, len(scratch[12]), 2)), np.empty(walks, np.int64)
    found, holes = floor_classes(
        _bit_rows(free), cols, np.array([*cells[0], *cells[1]], np.int64),
        np.array([*ends[0], *ends[1]], np.float64) / cell, max_classes, float(detour), scratch, lengths,
        keys, paths, turns,
    )  # fmt: skip
    found_holes = scratch[2][3][:holes]
    marks, centres = found_holes[:, :2] * cell, found_holes[:, 3:5] / found_holes[:, 5:] * cell
    if not found:
        return Topology((), ends[0], ends[1], marks, (), ())
    shortest = float(lengths[:found].min()) * cell
    within: dict[tuple[int, ...], tuple[float, np.ndarray]] = {}
    for k in range(found):
        length = float(lengths[k]) * cell
        if not length <= detour * shortest * (1.0 + LENGTH_TOLERANCE):  # (inf: a corridor not pulled)
            continue
        points = paths[k, : turns[k]] * cell
        points[0], points[-1] = ends
        within[tuple(1 if int(keys[k]) >> h & 1 else -1 for h in range(holes))] = (length, points)
    kept = sorted(within.items(), key=lambda kc: (kc[1][0], kc[0]))[:max_classes]
    order = _canonical_order(centres, ends, radius)
    telling = [k for k in order if len({key[k] for key, _ in kept}) > 1]
    classes = tuple(
        PathClass(
            "".join("L" if key[k] > 0 else "R" for k in telling),
            length,
            float(narrowest_width(points / cell, free)) * cell + 2 * radius,
            points,
        )
        for key, (length, points) in kept
    )
    return Topology(classes, ends[0], ends[1], marks, tuple(key for key, _ in kept), tuple(telling))


def _bit_rows(free: np.ndarray) -> np.ndarray:
    """``uint64[rows, words]``: the bit rows of a ``bool[rows, cols]`` grid, column ``c`` bit ``c % 64`` of
    word ``c // 64`` (as :mod:`mazegen.runtime.geometry._cspace` writes them)."""
    rows, cols = free.shape
    words = (cols + 63) // 64
    padded = np.zeros((rows, 64 * words), np.bool_)
    padded[:, :cols] = free
    return np.packbits(padded, axis=1, bitorder="little").view("<u8").astype(np.uint64)


def _runs(items: list[int], value: Callable[[int], float], tolerance: float) -> list[list[int]]:
    """``items`` (sorted by ``value``) in runs whose neighbours' values are within ``tolerance``."""
    runs: list[list[int]] = []
    for item in items:
        if runs and value(item) - value(runs[-1][-1]) <= tolerance:
            runs[-1].append(item)
        else:
            runs.append([item])
    return runs


Ends = tuple[tuple[float, float], tuple[float, float]]


def _canonical_order(centres: np.ndarray, ends: Ends, tolerance: float) -> list[int]:
    """The holes' indices in canonical order: by their centres' distance along the start-goal line,
    those within ``tolerance`` of each other from left to right."""
    (sx, sy), (gx, gy) = ends
    norm = math.hypot(gx - sx, gy - sy) or 1.0
    ux, uy = (gx - sx) / norm, (gy - sy) / norm
    x, y = centres[:, 0] - sx, centres[:, 1] - sy
    along, left = (x * ux + y * uy).tolist(), (ux * y - uy * x).tolist()
    order = sorted(range(len(centres)), key=lambda k: along[k])
    return [
        k for run in _runs(order, lambda k: along[k], tolerance) for k in sorted(run, key=lambda k: -left[k])
    ]
