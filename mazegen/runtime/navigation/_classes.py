"""Which floors are the same test: the homotopy classes of a floor's start-to-goal paths.

Two paths from start to goal are in one homotopy class when one can be deformed into the other
without crossing an obstacle: they pass every obstacle on the same side. A class is named by its
**signature**, the side (``L``eft or ``R``ight of the path) of each obstacle group that some class
passes on the other side, the groups in a canonical order (along the start-goal line, then from
left to right). A floor's **canonical class** is the set of its classes' signatures: two floors
with equal ones offer a robot the same choices of route, however different their coordinates.

The classes are found on the configuration space, for the robot's disc (docs/classes.md):

1. the free space is cut into rooms (:mod:`._rooms`);
2. walks through the rooms, from the start's to the goal's, are taken in order of their length
   through the cuts' narrowest points, best first, no cut crossed twice;
3. each walk's corridor is searched for its shortest path (:mod:`._corridors`), whose sides of
   every obstacle group make its class; a class keeps its shortest path;
4. classes whose shortest path is longer than ``detour`` times the floor's shortest path are
   left out (a robot would not take them), and at most ``max_classes`` are kept, shortest first.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mazegen.runtime.navigation._corridors import (
    corridor_path,
    goal_distances,
    narrowest_width,
    sides,
    simple,
)
from mazegen.runtime.navigation._paths import free_cells
from mazegen.runtime.navigation._rooms import BOUNDARY, CUT_COL, CUT_ROW, cut_rooms
from mazegen.spec import DETOUR, MAX_CLASSES

if TYPE_CHECKING:
    from mazegen.runtime.engine import Population
    from mazegen.runtime.geometry import Grid

WALKS_PER_CLASS = 4
"""Walks searched per class kept, at most: several walks through the rooms may be one class."""


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
    start, goal = (np.array(c, dtype=np.int64) for c in cells)
    free = np.ascontiguousarray(free, np.bool_)
    group, component, _, _, cut_of, room, cuts, joins = cut_rooms(free, start, goal)
    if not component[goal[0], goal[1]]:
        return Topology((), ends[0], ends[1], np.empty((0, 2)), (), ())
    walks = _walks(cuts, joins, room[start[0], start[1]], room[goal[0], goal[1]], ends, cell)
    holes = sorted({int(g) for g in cuts[:, 1:3].ravel().astype(np.int64)} - {BOUNDARY})
    marks = _marks(group, holes, ends, cell)
    start_point, goal_point = np.array(ends[0]), np.array(ends[1])
    to_goal = goal_distances(free, goal)
    found: dict[tuple[int, ...], PathClass] = {}
    shortest = math.inf
    for tried, (estimate, walk_rooms, walk_cuts) in enumerate(walks):
        if tried >= WALKS_PER_CLASS * max_classes or estimate > detour * shortest:
            break
        if len(found) >= max_classes and estimate > sorted(c.length for c in found.values())[max_classes - 1]:
            break  # the walks left are estimated longer than every class kept
        path_cells, steps = corridor_path(room, cut_of, walk_rooms, walk_cuts, start, goal, to_goal)
        if not path_cells.shape[0] or not simple(
            path_cells, *free.shape
        ):  # a class no path takes without looping
            continue
        points = (path_cells[:, ::-1] + 0.5) * cell
        points[0], points[-1] = ends
        key = tuple(sides(points, marks, start_point, goal_point).tolist())
        length = steps * cell
        shortest = min(shortest, length)
        if key not in found or length < found[key].length:
            narrowest = narrowest_width(path_cells, free) * cell + 2 * radius
            found[key] = PathClass("", length, float(narrowest), points)
    kept = sorted(((key, c) for key, c in found.items() if c.length <= detour * shortest + 1e-9),
                  key=lambda kc: (kc[1].length, kc[0]))[:max_classes]  # fmt: skip
    order = _canonical_order(group, holes, ends, cell, radius)
    telling = [k for k in order if len({key[k] for key, _ in kept}) > 1]
    classes = tuple(
        PathClass("".join("L" if key[k] > 0 else "R" for k in telling), c.length, c.narrowest, c.path)
        for key, c in kept
    )
    return Topology(classes, ends[0], ends[1], marks, tuple(key for key, _ in kept), tuple(telling))


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


def _walks(
    cuts: np.ndarray, joins: np.ndarray, first: int, last: int, ends: Ends, cell: float
) -> Iterator[tuple[float, np.ndarray, np.ndarray]]:
    """Walks from room ``first`` to room ``last`` as ``(estimate, rooms, cuts)``, shortest estimate
    first: the length through each crossed cut's narrowest point; no cut crossed twice."""
    crossing = (cuts[:, [CUT_COL, CUT_ROW]] + 0.5) * cell
    goal = np.asarray(ends[1])
    beside: dict[int, list[tuple[int, int]]] = {}
    for k, (a, b) in enumerate(joins.tolist()):
        if a != b and a >= 0:
            beside.setdefault(a, []).append((k, b))
            beside.setdefault(b, []).append((k, a))
    start = np.asarray(ends[0])
    Walk = tuple[float, float, int, tuple[int, ...], tuple[int, ...], tuple[float, ...]]
    queue: list[Walk] = [(float(np.linalg.norm(goal - start)), 0.0, 0, (first,), (), tuple(start))]
    pushed = 0
    while queue:
        estimate, travelled, _, rooms, crossed, point = heapq.heappop(queue)
        here = rooms[-1]
        if here == last:
            yield estimate, np.array(rooms, np.int64), np.array(crossed, np.int64)
        for k, there in beside.get(here, ()):
            if k in crossed:
                continue
            step = travelled + math.dist(point, crossing[k])
            pushed += 1
            ahead = step + math.dist(crossing[k], goal)
            heapq.heappush(queue, (ahead, step, pushed, (*rooms, there), (*crossed, k), tuple(crossing[k])))


def _marks(group: np.ndarray, holes: list[int], ends: Ends, cell: float) -> np.ndarray:
    """A point of each hole: its cell farthest from the start-goal line, so never on it."""
    (sx, sy), (gx, gy) = ends
    norm = math.hypot(gx - sx, gy - sy) or 1.0
    out = np.empty((len(holes), 2))
    for k, hole in enumerate(holes):
        rows, cols = np.nonzero(group == hole)
        x, y = (cols + 0.5) * cell, (rows + 0.5) * cell
        away = np.abs((gx - sx) * (y - sy) - (gy - sy) * (x - sx)) / norm
        j = int(np.argmax(away))
        out[k] = x[j], y[j]
    return out


def _canonical_order(
    group: np.ndarray, holes: list[int], ends: Ends, cell: float, tolerance: float
) -> list[int]:
    """The holes' indices in canonical order: by their centres' distance along the start-goal line,
    those within ``tolerance`` of each other from left to right."""
    (sx, sy), (gx, gy) = ends
    norm = math.hypot(gx - sx, gy - sy) or 1.0
    ux, uy = (gx - sx) / norm, (gy - sy) / norm
    along, left = [], []
    for hole in holes:
        rows, cols = np.nonzero(group == hole)
        x, y = float(np.mean((cols + 0.5) * cell)) - sx, float(np.mean((rows + 0.5) * cell)) - sy
        along.append(x * ux + y * uy)
        left.append(ux * y - uy * x)
    order = sorted(range(len(holes)), key=lambda k: along[k])
    return [
        k for run in _runs(order, lambda k: along[k], tolerance) for k in sorted(run, key=lambda k: -left[k])
    ]
